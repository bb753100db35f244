#!/usr/bin/env bash
# `invfem bench` rejects bad arguments before running any unit: each case must give its message
# and exit code 2. It never runs a benchmark (every case fails during argument checking, and
# --list only prints the units).
#   bench_args.sh INVFEM WORKDIR
set -uo pipefail
invfem="$1" work="$2"
source "$(dirname "$0")/lib.sh"
cli_setup

expect 2 "--units: unknown unit \"bogus\"" -- bench --units bogus
expect 2 "the units: force_pass_1t," -- bench --units svd,bogus
expect 2 "--units: expected unit names separated by commas" -- bench --units svd,,torus_115k
expect 2 "--json: cannot write \"$work/missing/out.json\": no folder" -- bench --units svd --json "$work/missing/out.json"
expect 2 "--json: cannot write \"$work\": it is a folder" -- bench --units svd --json "$work"
expect 2 "bench: unknown option \"--bogus\"" -- bench --bogus
expect 2 "bench: option --units needs a value" -- bench --units
expect 2 "bench: unexpected argument \"svd\"" -- bench svd
expect 2 "bench: --linear: expected cg or direct, found \"lu\"" -- bench --units svd --linear lu
expect 2 "bench: --preconditioner: expected auto, block_jacobi or amg, found \"ilu\"" -- bench --units svd --preconditioner ilu
# Nothing was written by the failed runs.
if [ -n "$(ls -A "$work")" ]; then
  echo "FAIL: a rejected bench left files in $work: $(ls -A "$work")"
  fail=1
fi
# --list names every bench unit, the n/a ones with their reason.
list=$("$invfem" bench --list) || { echo "FAIL: invfem bench --list exited $?"; fail=1; }
for unit in force_pass_1t force_pass_2t force_stiffness_1t svd torus_115k cloth_drape_50 cloth_drape_100 \
            dress_dance scaling_10k scaling_100k scaling_1m; do
  grep -q "^$unit " <<<"$list" || { echo "FAIL: bench --list does not name $unit"; fail=1; }
done
# dress_dance runs the shipped scene on ../shared/data: available exactly when the data is there.
if [ -f "$(dirname "$0")/../../../shared/data/garment/rumba/shell120.obj" ]; then
  grep -q "^dress_dance .*n/a" <<<"$list" && { echo "FAIL: dress_dance is n/a in --list though ../shared/data is present"; fail=1; }
else
  grep -q "^dress_dance .*n/a: needs ../shared/data" <<<"$list" || { echo "FAIL: dress_dance is not n/a without ../shared/data"; fail=1; }
fi
if [ "$fail" -ne 0 ]; then exit 1; fi
echo "invfem bench rejects bad arguments with exit code 2 and a clear message"
