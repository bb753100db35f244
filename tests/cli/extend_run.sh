#!/usr/bin/env bash
# A finished run extended with a longer `frames` and --resume continues from its last checkpoint,
# and gives the bits of a run of that length from the start; any other change of the scene is
# still refused (the checkpoint is not used: the run starts from frame 0 and says why).
#   extend_run.sh INVFEM SCENE WORKDIR
set -euo pipefail
invfem="$1" scene="$2" work="$3"
rm -rf "$work" && mkdir -p "$work"
common=(--quick --checkpoint-every 2 --threads 2)  # not --quiet: it would hide "resuming from"

"$invfem" run "$scene" "${common[@]}" --quiet --set frames=6 --out "$work/whole"
"$invfem" run "$scene" "${common[@]}" --quiet --set frames=4 --out "$work/extended"
[ ! -f "$work/extended/frames/cloth/0005.obj" ] || { echo "FAIL: a 4-frame run wrote frame 5"; exit 1; }
log=$("$invfem" run "$scene" "${common[@]}" --set frames=6 --out "$work/extended" --resume 2>&1)
grep -q "resuming from the checkpoint of frame 4" <<<"$log" || { echo "FAIL: not resumed from frame 4: $log"; exit 1; }
diff -r -q "$work/whole/frames" "$work/extended/frames"
cmp "$work/whole/energies.csv" "$work/extended/energies.csv"

# Another field changed: the checkpoints are not used, and the difference is named.
log=$("$invfem" run "$scene" "${common[@]}" --set frames=6 --set gravity='[0,-9,0]' --out "$work/extended" --resume 2>&1 || true)
grep -q "gravity" <<<"$log" || { echo "FAIL: a changed gravity was not named: $log"; exit 1; }
if grep -q "resuming from the checkpoint" <<<"$log"; then echo "FAIL: resumed a different scene: $log"; exit 1; fi
echo "an extended run is bit-identical to the longer run; other changes are still refused"
