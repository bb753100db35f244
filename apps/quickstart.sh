#!/usr/bin/env bash
# One command from a fresh clone: install what is missing, build (Release), and run the default
# scene, the ITF04 Figure 5 Buddha with a cape (apps/scenes/buddha_cape.json) at a middle
# resolution (7.6K tets, a 2.3K-triangle cape, 60 frames: about 3-5 minutes on 2 cores), writing
# its frames and preview PNGs. It also builds the Python module invfem (build/apps/python), so that
# README.md's Python example runs next.
#   apps/quickstart.sh [OUT_DIR]          (default: out/buddha_cape)
#   apps/quickstart.sh --torus [OUT_DIR]  the ITF04 Figure 2 torus puddle instead (default: out/torus_puddle)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
scene=buddha_cape
if [[ "${1:-}" == "--torus" ]]; then
  scene=torus_puddle
  shift
fi
bash "$root/apps/deps.sh"
build="$root/build"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)" --target invfem invfem_python
out="${1:-$root/out/$scene}"
if [[ "$scene" == buddha_cape ]]; then
  # The middle resolution; the scene file itself holds the full one (about 300K tets, an
  # 84K-triangle cape), and its "quick" block the tests' one. A BCC mesh this coarse locks (it is
  # stiffer than its material), so it takes E = 2 MPa, as the quick one does, to bend and invert
  # under the ball as the full one does at 10 MPa (at 2 MPa a fine Buddha buckles under its own
  # weight: apps/scenes/README.md). The ball goes in deeper than the full scene's, to z = 0.03 m,
  # and stays to 0.36 s, as in the "quick" block: the full scene's ball, which bounces off at
  # z = 0.08 m, inverts only 2 tets of this coarse Buddha.
  "$build/apps/invfem" run "$root/apps/scenes/buddha_cape.json" --out "$out" --overwrite --render \
    --set solids.0.mesh_resolution=24 --set solids.0.material.young=2e6 \
    --set cloths.0.grid.nx=24 --set cloths.0.grid.ny=48 \
    --set 'colliders.1.motion.translate_keys=[[0.0,[0.02,0.52,0.9]],[0.3,[0.02,0.52,0.03]],[0.36,[0.02,0.52,0.03]],[1.2,[0.1,0.6,1.0]]]'
  echo "frames:   $out/frames/{buddha,cape,ball}/NNNN.obj"
else
  "$build/apps/invfem" run "$root/apps/scenes/torus_puddle.json" --out "$out" --overwrite --render
  echo "frames:   $out/frames/torus/NNNN.obj"
fi
echo "previews: $out/png/NNNN.png"
echo "energies: $out/energies.csv"
# The interpreter the module is built for (Debian's, with NumPy; the top CMakeLists.txt).
python=$(sed -n 's/^PYTHON_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")
echo "python:   PYTHONPATH=$build/apps/python ${python:-python3}   (then import invfem: README.md, \"Python\")"
