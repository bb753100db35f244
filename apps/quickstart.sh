#!/usr/bin/env bash
# One command from a fresh clone: install what is missing, build (Release), and run the default
# scene (the ITF04 Figure 2 torus puddle), writing its frames and preview PNGs.
#   apps/quickstart.sh [OUT_DIR]        (default: out/torus_puddle)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/apps/deps.sh"
build="$root/build"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)" --target invfem
out="${1:-$root/out/torus_puddle}"
"$build/apps/invfem" run "$root/apps/scenes/torus_puddle.json" --out "$out" --render
echo "frames:   $out/frames/torus/NNNN.obj"
echo "previews: $out/png/NNNN.png"
echo "energies: $out/energies.csv"
