#!/usr/bin/env bash
# Every format asked for is written for every object and every body with a surface: a cloth's
# frames in OBJ, PLY, VTU (triangles, with its ParaView series) and USD, a tessellated collider's
# too. Each .pvd entry names a file that exists (relative to OUT). VTU frames are binary and
# compressed. Where python3's vtk module is installed (Debian python3-vtk9), VTK's own reader
# opens every entry of three runs (the cloth's; a mirrored torus_puddle: tets with det F and
# inverted flags; poncho_dance where its dancer, Debian's assimp-testmodels, is installed) and
# finds the run's values: a surface's points, triangles and velocities as its OBJ frame and USD
# layer print them, a solid's boundary among its nodes, its inverted count and smallest det F as
# energies.csv has them. The garment's USD layer holds its OBJ frame's panels as GeomSubsets
# (read by USD itself where its pxr module is installed). The readers are in frame_formats.py.
#   frame_formats.sh INVFEM SCENE WORKDIR
set -euo pipefail
invfem="$1" scene="$2" work="$3"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
scenes="$here/../../apps/scenes"
rm -rf "$work" && mkdir -p "$work"
# run SCENE FORMATS OUT [ARGS...]
run() { "$invfem" run "$1" --quick --quiet --threads 2 --set frames=2 --format "$2" --out "$3" "${@:4}"; }
run "$scene" obj,ply,vtu,usd "$work/run"
# The torus starts mirrored (every tet inverted) and is partly back by frame 1.
run "$scenes/torus_puddle.json" obj,vtu,usd "$work/solid" --set solids.0.initial_shape.scramble=mirror
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i }
         NR == 3 { ok = $c["inverted"] > 0 && $c["inverted"] < $c["elements"] }
         END { exit !ok }' "$work/solid/energies.csv" ||
  { echo "FAIL: the mirrored torus has no mix of inverted and upright tets at frame 1"; exit 1; }
runs=("$work/run" "$work/solid")
dancer=$(grep -o '/usr/share/assimp/models/[^"]*' "$scenes/poncho_dance.json")
if [ -f "$dancer" ]; then
  run "$scenes/poncho_dance.json" obj,usd,vtu "$work/garment"
  runs+=("$work/garment")
else
  echo "skipped: the garment's run ($dancer, Debian's assimp-testmodels, is absent)"
fi
out="$work/run"
fail=0
for dir in "$out"/frames/*/; do
  name=$(basename "$dir")
  for ext in obj ply vtu; do
    for f in 0 1 2; do
      [ -f "$dir/000$f.$ext" ] || { echo "FAIL: $name has no frame $f in .$ext"; fail=1; }
    done
  done
  [ -f "$out/frames/$name.usda" ] || { echo "FAIL: $name has no USD layer"; fail=1; }
  [ -f "$out/$name.pvd" ] || { echo "FAIL: $name has no ParaView series"; fail=1; }
  for entry in $(grep -o 'file="[^"]*"' "$out/$name.pvd" | sed 's/file="//; s/"$//'); do
    [ -f "$out/$entry" ] || { echo "FAIL: $name.pvd names $entry, which does not exist"; fail=1; }
  done
done
# One stage for the shot: it references every layer, each of which exists.
[ -f "$out/shot.usda" ] || { echo "FAIL: no shot.usda"; fail=1; }
for ref in $(grep -o '@[^@]*@' "$out/shot.usda" | tr -d @); do
  [ -f "$out/$ref" ] || { echo "FAIL: shot.usda references $ref, which does not exist"; fail=1; }
done
[ "$(grep -c '@' "$out/shot.usda")" = "$(ls "$out"/frames/*.usda | wc -l)" ] || { echo "FAIL: shot.usda misses a layer"; fail=1; }
grep -q 'endTimeCode = 2' "$out/shot.usda" || { echo "FAIL: shot.usda does not end at frame 2"; fail=1; }
# Every USD layer carries per-vertex normals every frame, and velocities (the cloth's nodes', the
# bodies' own) from frame 0 on.
for layer in "$out"/frames/*.usda; do
  grep -q 'normal3f\[\] normals.timeSamples' "$layer" || { echo "FAIL: $layer has no normals"; fail=1; }
  grep -q 'vector3f\[\] velocities.timeSamples' "$layer" || { echo "FAIL: $layer has no velocities"; fail=1; }
done
# Binary VTU frames: appended raw, zlib-compressed arrays, nothing in ASCII.
for r in "${runs[@]}"; do
  for f in "$r"/frames/*/*.vtu; do
    xml=$(head -c 4096 "$f" | tr -d '\000')
    [[ $xml == *'<AppendedData encoding="raw">'* && $xml == *'compressor="vtkZLibDataCompressor"'* &&
       $xml != *'format="ascii"'* ]] ||
      { echo "FAIL: $f is not binary and compressed"; fail=1; }
  done
done
[ "$fail" = 0 ] || exit 1
if [ -d "$work/garment" ]; then
  python3 "$here/frame_formats.py" panels "$work/garment" poncho
fi
# Debian's python3-vtk9 is for the system's python3, which a user's PATH may shadow (pyenv).
py=""
for p in python3 /usr/bin/python3; do
  if command -v "$p" >/dev/null && "$p" -c "import vtk" 2>/dev/null; then py=$p; break; fi
done
if [ -n "$py" ]; then
  "$py" "$here/frame_formats.py" vtk "${runs[@]}"
else
  echo "skipped: VTK's reader (python3's vtk module, Debian python3-vtk9) is not installed"
fi
usd_py=""
for p in python3 /usr/bin/python3; do
  if command -v "$p" >/dev/null && "$p" -c "import pxr" 2>/dev/null; then usd_py=$p; break; fi
done
if [ -n "$usd_py" ] && [ -d "$work/garment" ]; then
  "$usd_py" "$here/frame_formats.py" pxr "$work/garment" poncho
else
  echo "skipped: USD's reader of the panels (python3's pxr module) is not installed"
fi
echo "every object and body is written in every format asked for"
