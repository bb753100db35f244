#!/usr/bin/env bash
# Every format asked for is written for every object and every body with a surface: a cloth's
# frames in OBJ, PLY, VTU (triangles, with its ParaView series) and USD, a tessellated collider's
# too. Each .pvd entry names a file that exists (relative to OUT); where python3's vtk module is
# installed (Debian python3-vtk9), VTK's own reader opens every entry and finds the OBJ frame's
# vertex count, else that check is skipped with a message.
#   frame_formats.sh INVFEM SCENE WORKDIR
set -euo pipefail
invfem="$1" scene="$2" work="$3"
rm -rf "$work" && mkdir -p "$work"
"$invfem" run "$scene" --quick --quiet --threads 2 --set frames=2 --format obj,ply,vtu,usd --out "$work/run"
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
[ "$fail" = 0 ] || exit 1
# Debian's python3-vtk9 is for the system's python3, which a user's PATH may shadow (pyenv).
py=""
for p in python3 /usr/bin/python3; do
  if command -v "$p" >/dev/null && "$p" -c "import vtk" 2>/dev/null; then py=$p; break; fi
done
if [ -n "$py" ]; then
  "$py" - "$out" <<'PY'
import glob, os, re, sys, vtk
out = sys.argv[1]
for pvd in glob.glob(os.path.join(out, "*.pvd")):
    name = os.path.basename(pvd)[:-4]
    for k, entry in enumerate(re.findall(r'file="([^"]*)"', open(pvd).read())):
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(os.path.join(out, entry))
        r.Update()
        n = r.GetOutput().GetNumberOfPoints()
        obj = os.path.join(out, "frames", name, "%04d.obj" % k)
        want = sum(1 for l in open(obj) if l.startswith("v "))
        assert n > 0 and n == want, (entry, n, want)  # a surface: its VTU points are its OBJ vertices
    print("VTK read %s" % os.path.basename(pvd))
PY
else
  echo "skipped: VTK's reader (python3's vtk module, Debian python3-vtk9) is not installed"
fi
echo "every object and body is written in every format asked for"
