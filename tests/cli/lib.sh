# Shared by the CLI test scripts: set `invfem` (the binary) and `work` (the script's folder), source
# this file, then call cli_setup.

# cli_setup: an empty $work folder (any earlier run's files removed) and fail=0.
cli_setup() {
  rm -rf "$work" && mkdir -p "$work" || { echo "FAIL: cannot make the folder $work"; exit 1; }
  fail=0
}

# expect CODE PATTERN -- ARGS...: run invfem with ARGS (60 s at most), want exit CODE and PATTERN
# in its stderr; a mismatch prints FAIL with what came and sets fail=1.
expect() {
  local code="$1" pattern="$2"
  shift 3
  local err
  err=$(timeout 60 "$invfem" "$@" 2>&1 >/dev/null)
  local got=$?
  if [ "$got" -ne "$code" ] || ! grep -qF -- "$pattern" <<<"$err"; then
    echo "FAIL: invfem $*: exit $got (want $code), stderr: $err (want: $pattern)"
    fail=1
  fi
}

# expect_output CODE PATTERN -- ARGS...: the same with PATTERN looked for in stdout and stderr.
expect_output() {
  local code="$1" pattern="$2"
  shift 3
  local out
  out=$(timeout 60 "$invfem" "$@" 2>&1)
  local got=$?
  if [ "$got" -ne "$code" ] || ! grep -qF -- "$pattern" <<<"$out"; then
    echo "FAIL: invfem $*: exit $got (want $code), output: $out (want: $pattern)"
    fail=1
  fi
}

# write_tet_pair FILE: two 10 cm tets sharing face 123, 5 nodes (legacy VTK), the smallest solid.
write_tet_pair() {
  cat > "$1" <<'VTK'
# vtk DataFile Version 3.0
two tets
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 5 double
0 0 0
0.1 0 0
0 0.1 0
0 0 0.1
0.1 0.1 0.1
CELLS 2 10
4 0 1 2 3
4 4 3 2 1
CELL_TYPES 2
10
10
VTK
}
