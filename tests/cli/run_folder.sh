#!/usr/bin/env bash
# A run owns its output folder (apps/src/run_folder.hpp): a folder holding another run (its
# invfem-manifest.txt) is refused before any work (exit 2, naming it and the way on) unless --resume
# or --frames continues it (the same scene, no shorter) or --overwrite clears it first (the files
# its manifest lists, nothing else); a folder holding no run is used only when none of the run's
# files are there; --frames into a finished run keeps every row; a resumed finished run repairs
# its energies.csv from its checkpoint; a batch into folders with earlier runs likewise.
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
# --frames A-B into a finished run keeps the rows of every frame on disk (from a checkpoint, and
# from frame 0 where none comes before A).
rows() { tail -n +2 "$work/$1/energies.csv" | cut -d, -f1 | tr '\n' ' '; }
run --set frames=6 --out "$work/a" --frames 4-5 > /dev/null || { echo "FAIL: --frames 4-5"; fail=1; }
[ "$(rows a)" = "0 1 2 3 4 5 6 " ] || { echo "FAIL: --frames 4-5 left the rows $(rows a)"; fail=1; }
[ "$(wc -l < "$work/a/stats.jsonl")" = 7 ] || { echo "FAIL: --frames 4-5 left $(wc -l < "$work/a/stats.jsonl") stats lines"; fail=1; }
run --set frames=6 --out "$work/a" --frames 1-1 --checkpoint-every 0 > /dev/null || { echo "FAIL: --frames 1-1"; fail=1; }
[ "$(rows a)" = "0 1 2 3 4 5 6 " ] || { echo "FAIL: --frames 1-1 left the rows $(rows a)"; fail=1; }
# --resume where scene.json is a folder: bad output, named (exit 2).
cp -r "$work/a" "$work/d" && rm "$work/d/scene.json" && mkdir "$work/d/scene.json"
expect 2 "--out $work/d: scene.json is a folder, not the run's scene file: move it away" -- run "$scene" --quick --set frames=6 --out "$work/d" --resume
# --overwrite: the earlier run's files go (frames 4-6 of the longer run too), the user's stay,
# whatever their names: files a run also writes (a video, a point cache, a ParaView series, a
# preview) but that the run did not write.
mkdir -p "$work/a/png"
for f in holiday.mp4 cache.pc2 report.pvd check.json png/family.png; do echo "mine" > "$work/a/$f"; done
out=$(run --set frames=3 --out "$work/a" --overwrite 2>&1) || { echo "FAIL: --overwrite: $out"; fail=1; }
[ "$(frames a)" = 4 ] || { echo "FAIL: --overwrite left $(frames a) frames, want 4"; fail=1; }
[ ! -e "$work/a/checkpoints/0006.ckpt" ] || { echo "FAIL: --overwrite left the earlier checkpoint"; fail=1; }
for f in notes.txt holiday.mp4 cache.pc2 report.pvd check.json png/family.png; do
  [ "$(cat "$work/a/$f" 2>/dev/null)" = mine ] || [ "$f" = notes.txt ] || { echo "FAIL: --overwrite removed or changed the user's $f"; fail=1; }
done
[ -f "$work/a/notes.txt" ] || { echo "FAIL: --overwrite removed a file that was not the run's"; fail=1; }
grep -qx "frames/cloth/0003.obj" "$work/a/invfem-manifest.txt" || { echo "FAIL: the manifest does not list frame 3"; fail=1; }
# A folder without a manifest is no run: files the run would write there are not overwritten nor
# removed (--overwrite either), other files do not matter.
mkdir -p "$work/u/frames/holiday" && echo "jpg" > "$work/u/frames/holiday/0001.jpg" && echo "mine" > "$work/u/energies.csv"
expect 2 "--out $work/u holds energies.csv, which this run would write, but no run of invfem (no invfem-manifest.txt)" \
  -- run "$scene" --quick --out "$work/u"
expect 2 "they are not invfem's to overwrite or remove" -- run "$scene" --quick --out "$work/u" --overwrite
[ "$(cat "$work/u/energies.csv")" = mine ] && [ -f "$work/u/frames/holiday/0001.jpg" ] || { echo "FAIL: a folder without a run lost a file"; fail=1; }
rm "$work/u/energies.csv"
run --set frames=1 --out "$work/u" > /dev/null || { echo "FAIL: a run beside the user's frames/holiday"; fail=1; }
[ -f "$work/u/frames/holiday/0001.jpg" ] && [ "$(frames u)" = 2 ] || { echo "FAIL: the run beside frames/holiday"; fail=1; }
# A batch into folders holding earlier runs: refused before any scene starts, or cleared.
run --set frames=1 --out "$work/batch/cloth_drape" > /dev/null || { echo "FAIL: the batch's earlier run"; fail=1; }
expect 2 "holds an earlier run of cloth_drape: --overwrite clears the batch's earlier runs first" \
  -- batch "$scene" --quick --out "$work/batch"
[ "$fail" = 0 ] || exit 1
echo "a run owns its output folder"
