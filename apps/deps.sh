#!/usr/bin/env bash
# Installs the Debian 12 packages invfem needs, only those missing (a second run takes a second).
# Run by apps/quickstart.sh and tests/run.sh; `deps.sh --tests` adds the readers the tests judge
# outputs with (VTK's Python module, ffmpeg), venv (pip install ./apps/python into a venv, offline)
# and mypy (the type stubs checked as a type checker reads them). assimp-testmodels holds the rigged
# characters the skinned scenes and tests use (/usr/share/assimp/models); pybind11, Python's
# headers and NumPy build the Python module (apps/python); SuiteSparse's CHOLMOD and OpenBLAS (the
# BLAS its supernodal factorization runs on) make the implicit step's direct solve.
set -euo pipefail
INVFEM_PACKAGES=(build-essential cmake pkg-config libeigen3-dev libassimp-dev libembree-dev
                 libosmesa6-dev libtbb-dev libpng-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev
                 libgmp-dev assimp-testmodels pybind11-dev python3-dev python3-numpy
                 libsuitesparse-dev libopenblas-dev)
if [ "${1:-}" = "--tests" ]; then INVFEM_PACKAGES+=(python3-vtk9 ffmpeg python3-venv python3-mypy); fi
missing=()
for p in "${INVFEM_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
