#!/usr/bin/env bash
# The survey's baselines behind material.model (corotated, mass_spring): the combinations they do
# not support give their message and exit code 2; a two-tet solid started as its mirror image runs
# under each model, and only ITF04's rotated_linear brings it back (the baselines read a mirror
# image as a rest state: every edge keeps its length, the plain polar decomposition's R is a
# reflection); a cloth runs with each.
#   baselines.sh INVFEM WORKDIR
set -uo pipefail
invfem="$1" work="$2"
source "$(dirname "$0")/lib.sh"
cli_setup

write_tet_pair "$work/pair.vtk"
scene() {  # scene NAME SOLID_FIELDS
  printf '{"frames": 8, "gravity": [0, 0, 0], "solids": [{"name": "p", "mesh": "pair.vtk", %s}]}\n' "$2" \
    > "$work/$1.json"
  echo "$work/$1.json"
}
cloth() {  # cloth NAME CLOTH_FIELDS
  printf '{"frames": 3, "cloths": [{"name": "c", "grid": {"width": 0.2, "height": 0.2, "nx": 4, "ny": 4}, %s}]}\n' \
    "$2" > "$work/$1.json"
  echo "$work/$1.json"
}

expect 2 '$.solids[0].material.model: expected one of rotated_linear, neo_hookean, stvk, spline (ITF04) or the baselines corotated, mass_spring' -- \
  run "$(scene bad '"material": {"model": "springs"}')" --out "$work/o"
for key in plasticity fiber; do
  expect 2 "\$.solids[0].$key: expected no \"$key\" block with material.model \"mass_spring\"" -- \
    run "$(scene "ms_$key" "\"material\": {\"model\": \"mass_spring\"}, \"$key\": {}")" --out "$work/o"
done
expect 2 '$.cloths[0].inversion_test: expected "none" with the baseline material.model "corotated"' -- \
  run "$(cloth co_inv '"material": {"model": "corotated"}, "inversion_test": "rest"')" --out "$work/o"
expect 2 '$.cloths[0].plasticity: expected no in-plane plasticity with material.model "mass_spring"' -- \
  run "$(cloth ms_pl '"material": {"model": "mass_spring"}, "plasticity": {}')" --out "$work/o"

# inverted/elements of the first and last frame (energies.csv columns 7, 8).
for model in rotated_linear corotated mass_spring; do
  if "$invfem" run "$(scene "mirror_$model" "\"initial_shape\": {\"scramble\": \"mirror\", \"seed\": 5},
      \"material\": {\"model\": \"$model\", \"damping\": 0.01}")" --out "$work/mirror_$model" --quiet 2>/dev/null; then
    first=$(awk -F, 'NR == 2 {print $7 "/" $8}' "$work/mirror_$model/energies.csv")
    last=$(awk -F, 'END {print $7 "/" $8}' "$work/mirror_$model/energies.csv")
    want_last=2/2
    [ "$model" = rotated_linear ] && want_last=0/2
    [ "$first" = "2/2" ] || { echo "FAIL: $model: frame 0 has $first inverted, want 2/2"; fail=1; }
    [ "$last" = "$want_last" ] || { echo "FAIL: $model: last frame has $last inverted, want $want_last"; fail=1; }
    grep -q "\"model\": \"$model\"" "$work/mirror_$model/scene.json" ||
      { echo "FAIL: $model: scene.json does not name the model"; fail=1; }
  else
    echo "FAIL: the mirrored start with $model did not run"; fail=1
  fi
done

for model in corotated mass_spring; do
  for integrator in itf04 implicit; do
    "$invfem" run "$(cloth "cloth_${model}_$integrator" "\"material\": {\"model\": \"$model\"}")" \
      --set "solver.integrator=$integrator" --out "$work/cloth_${model}_$integrator" --quiet 2>/dev/null ||
      { echo "FAIL: a $model cloth did not run with the $integrator integrator"; fail=1; }
  done
done

# `invfem sheet` tiles chosen frames (the README comparison's contact sheets): one row of two
# 64x48 previews with captions; a label count that does not match is exit 2.
sheet_run="$work/cloth_sheet"
if "$invfem" run "$(cloth cloth_sheet '"material": {"model": "mass_spring"}')" --render --set render.width=64 \
    --set render.height=48 --out "$sheet_run" --quiet 2>/dev/null &&
   "$invfem" sheet "$sheet_run/png/0000.png" "$sheet_run/png/0003.png" --label first --label last \
    --out "$work/sheet.png" 2>/dev/null; then
  [ -s "$work/sheet.png" ] || { echo "FAIL: invfem sheet wrote no sheet.png"; fail=1; }
else
  echo "FAIL: the rendered mass_spring cloth or its contact sheet did not run"; fail=1
fi
expect 2 "sheet: 1 --label options for 2 images" -- \
  sheet "$sheet_run/png/0000.png" "$sheet_run/png/0003.png" --label one --out "$work/sheet2.png"

if [ "$fail" -ne 0 ]; then exit 1; fi
echo "baselines: every error gives its message and exit code 2; only ITF04 restores the mirrored solid"
