#!/usr/bin/env bash
# A run killed with SIGKILL mid-frame and resumed gives results bit-identical to a run that was
# never stopped (same --threads). Also: two runs with the same thread count are identical, and
# so are runs with different thread counts (ordered reductions).
#   resume_after_sigkill.sh INVFEM SCENE WORKDIR [FRAMES [RUN OPTIONS...]]
set -euo pipefail
invfem="$1" scene="$2" work="$3" frames="${4:-60}"
shift $(( $# < 4 ? $# : 4 ))
rm -rf "$work" && mkdir -p "$work"
common=(--quick --set frames="$frames" --checkpoint-every 5 --quiet --format obj,vtu "$@")
kill_after=$(printf '%04d' $(( (frames / 2) / 5 * 5 )))  # a checkpoint half-way through
last=$(printf '%04d' "$frames")

"$invfem" run "$scene" "${common[@]}" --threads 2 --out "$work/reference"
"$invfem" run "$scene" "${common[@]}" --threads 2 --out "$work/again"
"$invfem" run "$scene" "${common[@]}" --threads 1 --out "$work/one_thread"

"$invfem" run "$scene" "${common[@]}" --threads 2 --out "$work/killed" &
pid=$!
# Kill it once the half-way checkpoint exists, i.e. in the middle of a later frame.
for _ in $(seq 1 6000); do
  [ -f "$work/killed/checkpoints/$kill_after.ckpt" ] && break
  sleep 0.05
done
kill -9 "$pid" 2>/dev/null || true
wait "$pid" 2>/dev/null || true
if [ -f "$work/killed/checkpoints/$last.ckpt" ]; then
  echo "the run finished before it could be killed: the test proves nothing" >&2
  exit 1
fi
# Nothing half-written: no temporary files are left as outputs and every frame parses.
"$invfem" run "$scene" "${common[@]}" --threads 2 --out "$work/killed" --resume

for run in again one_thread killed; do
  diff -r -q "$work/reference/frames" "$work/$run/frames"
  cmp "$work/reference/energies.csv" "$work/$run/energies.csv"
done
echo "resumed, repeated and single-thread runs are bit-identical to the reference"
