#!/usr/bin/env bash
# The README's Blender recipe as a user runs it: a garment's run written as OBJ frames and a PC2
# point cache, frame 0 imported into Blender with its UVs, the Mesh Cache modifier on the cache,
# and the evaluated mesh at a later frame equal to that frame's OBJ (blender_mesh_cache.py).
# Skipped where Blender (Debian's blender) is absent.
#   blender_mesh_cache.sh INVFEM SCENE WORKDIR
set -euo pipefail
invfem="$1" scene="$2" work="$3"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if ! command -v blender >/dev/null; then
  echo "skipped: Blender (Debian blender) is not installed"
  exit 0
fi
for model in $(grep -o '/usr/share/assimp/models/[^"]*' "$scene"); do
  [ -f "$model" ] || { echo "skipped: $model (Debian's assimp-testmodels) is absent"; exit 0; }
done
rm -rf "$work" && mkdir -p "$work"
"$invfem" run "$scene" --quick --quiet --threads 2 --set frames=6 --format obj,pc2 --out "$work/run"
for name in $(ls "$work/run/frames"); do
  [ -f "$work/run/$name.pc2" ] || continue
  blender -b --factory-startup --python "$here/blender_mesh_cache.py" -- "$work/run" "$name" 5 > "$work/$name.log" 2>&1 ||
    { echo "FAIL: $name"; grep -v '^$' "$work/$name.log" | tail -5; exit 1; }
  grep '^blender:' "$work/$name.log"
done
grep -q ' [1-9][0-9]* uv layers' "$work"/*.log || { echo "FAIL: no garment came in with its UVs"; exit 1; }
