#!/usr/bin/env bash
# A run owns its output folder (apps/src/run_folder.hpp): a folder holding another run is refused
# before any work (exit 2, naming it and the way on) unless --resume or --frames continues it (the
# same scene, no shorter) or --overwrite clears it first (the run's files only); a resumed finished
# run repairs its energies.csv from its checkpoint; a batch into folders with earlier runs likewise.
#   run_folder.sh INVFEM SCENE WORKDIR
invfem="$1" scene="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
run() { timeout 120 "$invfem" run "$scene" --quick --quiet --threads 2 --checkpoint-every 2 "$@"; }
frames() { ls "$work/$1/frames/cloth" | grep -c '\.obj$'; }

run --set frames=6 --out "$work/a" || { echo "FAIL: first run"; exit 1; }
echo "notes" > "$work/a/notes.txt"
# Another run into it, the same scene or another: refused, nothing touched.
expect 2 "--out $work/a holds a run of \"cloth_drape\" (frames 0-6): --resume continues it, --overwrite clears it first" \
  -- run "$scene" --quick --out "$work/a"
expect 2 "holds a run of \"cloth_drape\"" -- run "$scene" --quick --set gravity=[0,-1,0] --out "$work/a"
[ "$(frames a)" = 7 ] || { echo "FAIL: a refused run changed the frames"; fail=1; }
# Continuing it with another scene: refused, with what differs.
expect 2 "holds a run of another scene (/gravity/1 is -1.0 now, -9.81 in the folder's run)" \
  -- run "$scene" --quick --set frames=6 --set gravity=[0,-1,0] --out "$work/a" --resume
expect 2 "holds a run of another scene" -- run "$scene" --quick --set frames=6 --set gravity=[0,-1,0] --frames 2-3 --out "$work/a"
# Shortening it: refused.
expect 2 "longer than this scene's 4 frames: it would be left mixed" -- run "$scene" --quick --set frames=4 --out "$work/a" --resume
expect 2 "--overwrite clears the earlier run, --resume continues it: give one of them" \
  -- run "$scene" --quick --out "$work/a" --resume --overwrite
# A finished run resumed repairs a truncated energies.csv from its last checkpoint.
head -3 "$work/a/energies.csv" > "$work/a/e" && mv "$work/a/e" "$work/a/energies.csv"
run --set frames=6 --out "$work/a" --resume > /dev/null || { echo "FAIL: resuming the finished run"; fail=1; }
[ "$(wc -l < "$work/a/energies.csv")" = 8 ] || { echo "FAIL: energies.csv not repaired: $(wc -l < "$work/a/energies.csv") lines"; fail=1; }
# --overwrite: the earlier run's files go (frames 4-6 of the longer run too), the user's stay.
out=$(run --set frames=3 --out "$work/a" --overwrite 2>&1) || { echo "FAIL: --overwrite: $out"; fail=1; }
[ "$(frames a)" = 4 ] || { echo "FAIL: --overwrite left $(frames a) frames, want 4"; fail=1; }
[ ! -e "$work/a/checkpoints/0006.ckpt" ] || { echo "FAIL: --overwrite left the earlier checkpoint"; fail=1; }
[ -f "$work/a/notes.txt" ] || { echo "FAIL: --overwrite removed a file that was not the run's"; fail=1; }
# A batch into folders holding earlier runs: refused before any scene starts, or cleared.
mkdir -p "$work/batch/cloth_drape/frames"
expect 2 "holds an earlier run of cloth_drape: --overwrite clears the batch's earlier runs first" \
  -- batch "$scene" --quick --out "$work/batch"
[ "$fail" = 0 ] || exit 1
echo "a run owns its output folder"
