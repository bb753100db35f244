#!/usr/bin/env bash
# The baseline comparison of the README (section "Baselines"): the torus puddle, the Buddha through the gears and
# the Buddha's cape, each under the scene's own ITF04 model and the survey's two baselines
# (material.model corotated, mass_spring), at --quick resolution on one thread, with 320x240
# previews; then one contact sheet per scene (rows: methods, columns: the same moments) and the
# table (peak inverted fraction, whether it recovers, time per frame) from each run's stats.jsonl.
#   renders/baselines/compare.sh INVFEM OUTDIR [JOBS]     e.g. build/apps/invfem out/baselines 2
# JOBS runs at a time (default 2, one per core; each run is --threads 1). Writes OUTDIR/<scene>_<method>/
# (the runs), OUTDIR/<scene>.png (the sheets) and OUTDIR/table.md.
set -euo pipefail
invfem=$(realpath "$1") out=$2 jobs=${3:-2}
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
methods=(itf04 corotated mass_spring)
scenes=(torus_puddle buddha_gears buddha_cape)
declare -A moments=([torus_puddle]="0 30 45 60 90" [buddha_gears]="0 25 50 75 100" [buddha_cape]="0 8 12 16 24")

run_one() {  # run_one SCENE METHOD
  local scene=$1 method=$2 sets=()
  if [ "$method" != itf04 ]; then
    sets+=(--set "solids.0.material.model=$method")
    [ "$scene" = buddha_cape ] && sets+=(--set "cloths.0.material.model=$method")
  fi
  "$invfem" run "$root/apps/scenes/$scene.json" --quick --threads 1 --render --set render.width=320 \
    --set render.height=240 "${sets[@]}" --out "$out/${scene}_$method" --quiet
}
export -f run_one
export invfem root out
printf '%s\n' "${scenes[@]}" | while read -r s; do for m in "${methods[@]}"; do echo "$s $m"; done; done |
  xargs -P "$jobs" -L 1 bash -c 'run_one "$0" "$1"'

for scene in "${scenes[@]}"; do
  images=() labels=()
  for m in "${methods[@]}"; do
    fps=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['fps'])" "$out/${scene}_$m/scene.json")
    for f in ${moments[$scene]}; do
      images+=("$out/${scene}_$m/png/$(printf %04d "$f").png")
      labels+=(--label "$m t=$(python3 -c "print(f'{$f / $fps:.1f}')")s")
    done
  done
  "$invfem" sheet "${images[@]}" "${labels[@]}" --columns 5 --out "$out/$scene.png"
done

python3 - "$out" "${scenes[@]}" > "$out/table.md" <<'PY'
import json, sys
out, scenes = sys.argv[1], sys.argv[2:]
print("| scene | method | tets | peak inverted | at frame | last frame inverted | recovers | s/frame |")
print("|---|---|---|---|---|---|---|---|")
for scene in scenes:
    for m in ["itf04", "corotated", "mass_spring"]:
        rows = [json.loads(l) for l in open(f"{out}/{scene}_{m}/stats.jsonl")]
        n = rows[0]["elements"]
        peak = max(rows, key=lambda r: r["inverted"])
        last = rows[-1]["inverted"]
        # time per frame: simulation and self-collision seconds (not writing or rendering), frames 1..N
        sec = [r["seconds"]["simulate"] + r["seconds"].get("self_collision", 0) for r in rows[1:]]
        recovers = "yes" if last == 0 else "no" if peak["inverted"] > 0 else "never inverted"
        print(f"| {scene} | {m} | {n} | {peak['inverted']} ({100 * peak['inverted'] / n:.1f}%) | {peak['frame']} | "
              f"{last} ({100 * last / n:.1f}%) | {recovers} | {sum(sec) / len(sec):.2f} |")
PY
cat "$out/table.md"
