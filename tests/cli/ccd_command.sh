#!/usr/bin/env bash
# `invfem ccd`: the answers of a small query file (hits and misses, comments and blank lines),
# --min-distance, and the errors: a malformed line named by file and line, a bad option.
#   ccd_command.sh INVFEM WORKDIR
set -uo pipefail
invfem="$1" work="$2"
source "$(dirname "$0")/lib.sh"
cli_setup

cat > "$work/q.txt" <<'Q'
# vertex falling through a static triangle's interior: hit
vf 0.25 0.25 1  0 0 0  1 0 0  0 1 0   0.25 0.25 -1  0 0 0  1 0 0  0 1 0

# the same, 0.07 beyond the hypotenuse: miss
vf 0.55 0.55 1  0 0 0  1 0 0  0 1 0   0.55 0.55 -1  0 0 0  1 0 0  0 1 0
   # edge falling across another: hit
ee 0 -1 1  0 1 1  -1 0 0  1 0 0   0 -1 -1  0 1 -1  -1 0 0  1 0 0
# the same, shifted 0.01 beyond the end of edge b: miss
ee 1.01 -1 1  1.01 1 1  -1 0 0  1 0 0   1.01 -1 -1  1.01 1 -1  -1 0 0  1 0 0
Q
got=$("$invfem" ccd "$work/q.txt" 2>"$work/err.txt")
code=$?
if [ "$code" -ne 0 ] || [ "$got" != "$(printf '1\n0\n1\n0')" ]; then
  echo "FAIL: ccd q.txt: exit $code, answers: $got (want 1 0 1 0)"; fail=1
fi
grep -q "4 queries (2 vf, 2 ee), 2 hits" "$work/err.txt" || { echo "FAIL: summary: $(cat "$work/err.txt")"; fail=1; }
# Within 0.1 the misses (0.07 and 0.01 away) are hits too.
got=$("$invfem" ccd "$work/q.txt" --min-distance 0.1 2>/dev/null)
[ "$got" = "$(printf '1\n1\n1\n1')" ] || { echo "FAIL: --min-distance 0.1: $got"; fail=1; }

{ head -n 3 "$work/q.txt"; echo "vf 0 0 0  1 0 0  0 1 0  0 0 0  1 0 0  0 1 0  0 0 0  1 0"; } > "$work/short.txt"
expect 2 "short.txt:4: expected 24 numbers after \"vf\" (8 points x y z), found 23" -- ccd "$work/short.txt"
printf 'vf 1 2 3 4 5 6 7 8 9 1 2 3 4 5 6 7 8 9 1 2 3 4 5 6 7\n' > "$work/long.txt"
expect 2 "long.txt:1: more than 24 numbers" -- ccd "$work/long.txt"
printf '# c\nxx 1 2 3\n' > "$work/tag.txt"
expect 2 "tag.txt:2: expected a query tag vf or ee, found \"xx\"" -- ccd "$work/tag.txt"
printf 'ee 1 2 3 4 5 6 7 8 9 1 2 3 4 5 6 7 8 9 1 2 3 4 5 six\n' > "$work/nan.txt"
expect 2 "nan.txt:1: not a number: \"six\"" -- ccd "$work/nan.txt"
printf 'ee 1 2 3 4 5 6 7 8 9 1 2 3 4 5 6 7 8 9 1 2 3 4 5 inf\n' > "$work/inf.txt"
expect 2 "inf.txt:1: number 24 is not finite" -- ccd "$work/inf.txt"
expect 2 "cannot open the query file" -- ccd "$work/missing.txt"
expect 2 "--min-distance: expected a distance >= 0" -- ccd "$work/q.txt" --min-distance -1
expect 2 "ccd: expected one query file" -- ccd
exit $fail
