#!/usr/bin/env bash
# Found by the scene fuzzer (tests/fuzz/scene_fuzz.cpp, case 1312 of seed 12): the quick
# plastic_sphere_gears with its ground plane through [10001, 10001, 10001] would run for hours
# (the sphere, 10 km under the plane, is flattened onto it in one step, and the self-collision
# layer then meets every pair of its surface in every step). An object that starts wholly inside a rigid
# collider (deepest node deeper than the object measures across) is bad input, exit 2 naming both.
#   inside_collider.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
gears="$src/apps/scenes/plastic_sphere_gears.json"
drape="$src/apps/scenes/cloth_drape.json"

expect 2 "object \"sphere\" starts inside collider \"ground\": its node" -- \
  check-scene "$gears" --quick --set 'colliders.1.point=[10001,10001,10001]'
expect 2 "more than the object measures across" -- \
  run "$gears" --quick --out "$work/o" --frames 0-1 --set 'colliders.1.point=[10001,10001,10001]'
# A sphere collider around a cloth: the cloth (1 m across) inside a ball of radius 100.
expect 2 "object \"cloth\" starts inside collider \"ball\"" -- \
  check-scene "$drape" --quick --set colliders.0.radius=100
# Touching or partly inside is allowed (collision processing pushes those nodes out).
expect_output 0 "" -- check-scene "$gears" --quick --set 'colliders.1.point=[0,1.6,0]'
expect_output 0 "" -- check-scene "$drape" --quick --set 'cloths.0.transform.translate=[0,0,0]'
if [ "$fail" -ne 0 ]; then exit 1; fi
echo "objects that start inside a collider are refused, naming both"
