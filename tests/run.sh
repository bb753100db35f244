#!/usr/bin/env bash
# One command from a fresh clone: install what is missing, build everything (Release), and run
# the test suite through CTest, all but the tests labelled "long". INVFEM_UPDATE_GOLDEN=1 rewrites
# the golden files instead of comparing against them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/apps/deps.sh" --tests
build="$root/build"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)"
cd "$build"
# The long tests (label "long": the whole dress dance) run on request: ctest --test-dir build -L long
ctest --output-on-failure -j"$(nproc)" -LE long "$@"
