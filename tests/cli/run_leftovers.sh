#!/usr/bin/env bash
# Issue 12, class 9: a batch child killed by a signal is reported with the signal (in the summary
# and in its log, which is otherwise empty); temporaries left by a killed run (NNNN.obj.tmp, ...)
# are removed when the next run or resume starts.
#   run_leftovers.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
rm -rf "$work" && mkdir -p "$work"
scene="$src/apps/scenes/torus_puddle.json"
fail=0

# Stale temporaries: planted where atomic_write puts them, removed by the resume; the user's own
# *.tmp files, which the run's manifest does not list, and every other file stay.
"$invfem" run "$scene" --quick --set frames=4 --checkpoint-every 2 --quiet --out "$work/run" || { echo "FAIL: run"; exit 1; }
touch "$work/run/frames/torus/0003.obj.tmp" "$work/run/checkpoints/0004.ckpt.tmp" "$work/run/energies.csv.tmp"
touch "$work/run/keep.txt" "$work/run/mine.tmp" "$work/run/frames/torus/notes.tmp"
out=$("$invfem" run "$scene" --quick --set frames=4 --checkpoint-every 2 --out "$work/run" --resume 2>&1)
if ! grep -qF "removed 3 stale temporary files (*.tmp) left by a stopped run in $work/run" <<<"$out"; then
  echo "FAIL: no report of the removed temporaries: $out"
  fail=1
fi
left=$(find "$work/run" -name '*.tmp' | sort)
want=$(printf '%s\n' "$work/run/frames/torus/notes.tmp" "$work/run/mine.tmp" | sort)
if [ "$left" != "$want" ] || [ ! -f "$work/run/keep.txt" ]; then
  echo "FAIL: temporaries left are ($left), want only the user's ($want), or another file was removed"
  fail=1
fi

# A batch child killed by a signal: SIGXCPU from a soft CPU-time limit the child inherits (the
# batch process itself only waits; a hard limit would send SIGKILL). The scene's 90 quick frames
# take several CPU seconds.
mkdir -p "$work/scenes"
sed 's|"data/|"'"$src"'/apps/scenes/data/|g' "$scene" > "$work/scenes/slow.json"
out=$( (ulimit -S -t 1; "$invfem" batch "$work/scenes/slow.json" --quick --out "$work/batch" 2>&1) )
rc=$?
sig="killed by signal 24 (SIGXCPU: CPU time limit exceeded)"
if [ "$rc" -ne 1 ] || ! grep -qF "FAILED slow ($sig)" <<<"$out" || ! grep -qF "scenes failed: slow ($sig)" <<<"$out"; then
  echo "FAIL: batch with a killed child: exit $rc, output: $out (want: $sig)"
  fail=1
fi
if ! grep -qF "invfem batch: the run was $sig" "$work/batch/slow/log.txt"; then
  echo "FAIL: the killed child's log does not name the signal: $(tail -3 "$work/batch/slow/log.txt")"
  fail=1
fi
if [ "$fail" -ne 0 ]; then exit 1; fi
echo "killed batch children name their signal; stale temporaries are removed at the start of a run"
