#!/usr/bin/env bash
# The dress dance driven from Python (apps/python/examples/dress_on_numpy_body.py) over all its
# frames, then `invfem check` over every frame: no intersecting pair. Skips (77) without the data.
# usage: dress_on_numpy_body.sh PYTHON EXAMPLE INVFEM DATA
set -euo pipefail
python=$1 example=$2 invfem=$3 data=$4
if [ ! -e "$data/garment/rumba/shell120.obj" ]; then
  echo "skipped: $data/garment/rumba missing (the dancer's frames are in ../shared/data)"
  exit 77
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$python" "$example" "$out/run" --data "$data"
"$invfem" check "$out/run"
