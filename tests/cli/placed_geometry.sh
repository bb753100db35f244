#!/usr/bin/env bash
# Issue 12, class 8: an object's transform is checked where it is applied (every solid, cloth,
# initial shape and mesh collider): a coordinate that is not finite or beyond 1e6 m names the
# transform, not the mesh; and a cloth's size gets the solids' plausible range (1e-5 to 1e4 m).
#   placed_geometry.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
torus="$src/apps/scenes/torus_puddle.json"
cloth="$src/apps/scenes/cloth_drape.json"

# A transform field outside its own range is refused where it is read (scene_limits.sh); here,
# in-range fields whose combination places a node beyond 1e6 m: the transform is named.
expect 2 "solid \"torus\": the transform (scale 1, translate [1e+06, 0, 0]) puts node 0 at (1e+06, 0, 0), beyond the 1e+06 m" -- \
  check-scene "$torus" --quick --set 'solids.0.transform.translate=[999999.9,0,0]'
expect 2 "cloth \"cloth\": the transform (scale 1000, translate [999900, 1, 0]) puts node 10 at" -- \
  check-scene "$cloth" --quick --set 'cloths.0.transform.translate=[999900,1,0]' --set cloths.0.transform.scale=1000
expect 2 "cloth \"cloth\": bounding-box diagonal 141421 m exceeds 10000 m; the mesh is probably in other units (mm?) or its scale is wrong: e.g. \"scale\": 0.1" -- \
  check-scene "$cloth" --quick --set cloths.0.transform.scale=1e5
expect 2 "cloth \"cloth\": bounding-box diagonal 1.41421e-07 m is below 1e-05 m" -- \
  check-scene "$cloth" --quick --set cloths.0.transform.scale=1e-7
expect 2 "cloth \"cloth\": the transform (scale 1000, translate [999900, 1, 0])" -- \
  run "$cloth" --quick --out "$work/o" --set 'cloths.0.transform.translate=[999900,1,0]' --set cloths.0.transform.scale=1000
# Plausible placements still pass.
expect_output 0 "" -- check-scene "$cloth" --quick --set 'cloths.0.transform.translate=[1000,1,0]'
expect_output 0 "" -- check-scene "$torus" --quick --set solids.0.transform.scale=100
if [ "$fail" -ne 0 ]; then exit 1; fi
echo "transforms and cloth sizes are checked, naming the transform"
