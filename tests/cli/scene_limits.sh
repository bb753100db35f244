#!/usr/bin/env bash
# Hostile scene values (issue 12): each class of input that once crashed, wrote inf or escaped
# its folder is rejected or stopped with its documented exit code and a message naming it.
#   scene_limits.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
torus="$src/apps/scenes/torus_puddle.json"
drape="$src/apps/scenes/cloth_drape.json"

nested() { python3 -c "import sys; n = int(sys.argv[1]); print('[' * n + ']' * n)" "$1"; }

# 1. Deeply nested values: the parser bounds the depth (naming the file or the --set), and a
#    value echoed in a message is cut to a few levels and characters.
printf '{"fps": %s, "solids": []}\n' "$(nested 70000)" > "$work/deep.json"
expect 2 "deep.json: JSON nested more than 64 levels deep" -- check-scene "$work/deep.json"
expect 2 "deep.json: JSON nested more than 64 levels deep" -- run "$work/deep.json" --out "$work/o"
expect 2 "--set: fps: JSON nested more than 64 levels deep" -- check-scene "$torus" --set "fps=$(nested 65000)"
expect 2 "--set: fps: JSON nested more than 64 levels deep" -- run "$torus" --quick --out "$work/o" --set "fps=$(nested 65000)"
# 64 levels parse; the message shows four of them.
expect 2 '$.fps: expected a number, found array [[[[...]]]]' -- check-scene "$torus" --set "fps=$(nested 64)"
long=$(python3 -c "print('\"' + 'a' * 100000 + '\"')")
err=$("$invfem" check-scene "$torus" --set "fps=$long" 2>&1)
if [ $? -ne 2 ] || [ "${#err}" -gt 300 ]; then echo "FAIL: a 100,000-character value: ${#err} characters of message"; fail=1; fi
expect 2 "--set: name: the value is neither JSON nor valid UTF-8 text" -- check-scene "$torus" --set $'name=\xff\xfe'

# 4. Object names are one plain path component: every named kind goes through one validator.
for name in . .. a/b 'a\\b' ''; do
  expect 2 '$.solids[0].name: expected a name that can be a folder name' -- \
    check-scene "$torus" --quick --set "solids.0.name=\"$name\""
done
expect 2 "it holds a control character (byte 0)" -- check-scene "$torus" --set 'solids.0.name="a\u0000b"'
expect 2 "it holds a control character (byte 10)" -- check-scene "$torus" --set 'solids.0.name="a\nb"'
expect 2 "it is longer than 100 bytes" -- check-scene "$torus" --set "solids.0.name=$(printf 'n%.0s' {1..101})"
expect 2 '$.cloths[0].name: expected a name that can be a folder name' -- check-scene "$drape" --set cloths.0.name=..
expect 2 '$.colliders[0].name: expected a name that can be a folder name' -- check-scene "$drape" --set colliders.0.name=.
expect 2 '".." names a folder' -- run "$torus" --quick --out "$work/names" --set solids.0.name=..
if [ -e "$work/names" ] && [ -n "$(ls -A "$work/names")" ]; then echo "FAIL: a refused name wrote $(ls "$work/names")"; fail=1; fi
expect_output 0 "valid (1 objects" -- check-scene "$torus" --quick --set 'solids.0.name="torus 2 (draft)"'

# 5. Indices and integers are read in 64 bits and checked (against the mesh for vertices) before
#    they are narrowed: 4294967297 is not vertex 1, 99999999999 is not vertex 1215752191.
for v in 4294967297 99999999999; do
  expect 2 "cloth \"cloth\": pin_vertices: vertex $v but the mesh has 289 vertices" -- \
    check-scene "$drape" --quick --set "cloths.0.pin_vertices=[$v]"
done
expect 2 'pins[0]: vertex 4294967297 but the mesh has 289 vertices' -- \
  check-scene "$drape" --quick --set 'cloths.0.pins=[{"vertices": [4294967297]}]'
expect 2 'stitches.list[0]: vertex 4294967298 but the mesh has 289 vertices' -- \
  check-scene "$drape" --quick --set 'cloths.0.stitches.list=[[0, 1, 4294967298, 0.5]]'
expect 2 'expected vertex indices (integers >= 0), found element 0: number 18446744073709551615' -- \
  check-scene "$drape" --quick --set 'cloths.0.pin_vertices=[18446744073709551615]'
expect 2 '$.frames: expected an integer in [0, 1000000], found number 4294967297' -- check-scene "$drape" --set frames=4294967297
expect 2 '$.frames: expected an integer in [0, 1000000], found number 18446744073709551615' -- \
  check-scene "$drape" --set frames=18446744073709551615
expect_output 0 "valid (1 objects, 289 nodes" -- check-scene "$drape" --quick --set 'cloths.0.pin_vertices=[288]'

# 2. Every vector and scalar has a physical range (json_reader.hpp `limits`): what once wrote inf
#    with exit 0 (a velocity of 1e300 m/s) or froze the scene (gravity 1e300) is refused. The
#    state check after each frame (World::non_finite_state, unit test World.NonFiniteState...)
#    names the object when a run goes non-finite anyway.
magnitude='expected an array of 3 finite numbers of magnitude <= 10000'
expect 2 "\$.solids[0].velocity: $magnitude" -- run "$torus" --quick --out "$work/inf" --set 'solids.0.velocity=[1e300,0,0]'
if [ -e "$work/inf/energies.csv" ]; then echo "FAIL: a refused velocity wrote energies"; fail=1; fi
expect 2 "\$.cloths[0].velocity: $magnitude" -- check-scene "$drape" --quick --set 'cloths.0.velocity=[0,0,-1e300]'
expect 2 "\$.gravity: $magnitude" -- check-scene "$torus" --quick --set 'gravity=[0,-1e300,0]'
expect 2 "\$.solids[0].velocity: $magnitude" -- check-scene "$torus" --quick --set 'solids.0.velocity=[8000,8000,0]'
expect 2 '$.solids[0].transform.translate: expected an array of 3 finite numbers of magnitude <= 1e+06' -- \
  check-scene "$torus" --quick --set 'solids.0.transform.translate=[1e300,0,0]'
expect 2 '$.cloths[0].transform.scale: expected a scale in (0, 1e6]' -- \
  check-scene "$drape" --quick --set cloths.0.transform.scale=1e30
expect 2 '$.colliders[0].point: expected an array of 3 finite numbers of magnitude <= 1e+06' -- \
  check-scene "$torus" --quick --set 'colliders.0.point=[0,-1e7,0]'
expect 2 '$.solids[0].material.density: expected a density > 0 and <= 1e6' -- \
  check-scene "$torus" --quick --set solids.0.material.density=1e300
expect 2 '$.colliders[0].motion.spin_rate: expected a number in [-10000, 10000]' -- \
  check-scene "$drape" --quick --set 'colliders.0.motion={"spin_rate": 1e300}'
expect 2 '$.colliders[0].motion.translate_keys: expected positions: an array of 3 finite numbers of magnitude <= 1e+06' -- \
  check-scene "$drape" --quick --set 'colliders.0.motion={"translate_keys": [[0, [0, 0, 0]], [1, [1e300, 0, 0]]]}'
expect_output 0 "valid (1 objects" -- check-scene "$torus" --quick --set 'solids.0.velocity=[0,-9999,0]'

# 6. Parameters that would make a run crawl: the start reports the step size and substeps a frame
#    and refuses past solver.max_substeps_per_frame (exit 1, nothing written); a frame that
#    reaches the limit later (the strength ramps up) stops the run naming the frame.
for s in solids.0.material.young=1e12 solids.0.material.density=1e-12; do
  rm -rf "$work/stiff"
  expect 1 "more than solver.max_substeps_per_frame (20000); the itf04 step is limited" -- \
    run "$torus" --quick --out "$work/stiff" --set "$s" --set solids.0.material.strength=1
  if [ -e "$work/stiff/frames" ]; then echo "FAIL: $s: frames written before the refusal"; fail=1; fi
done
expect 1 'solver.integrator "implicit" takes steps of max_dt instead' -- \
  run "$torus" --quick --out "$work/stiff" --set solids.0.material.young=1e9 --set solids.0.material.strength=1 \
  --set solver.max_substeps_per_frame=5000
expect_output 0 "substeps per frame; the itf04 step is limited" -- run "$torus" --quick --out "$work/note" --frames 0-0 \
  --set solids.0.material.young=1e9 --set solids.0.material.strength=1
# check-scene says the same without running: the step (max_dt when the soft start allows it:
# 1/30 s / 0.001 s = 33.3, so 34 steps), the note, and the refusal a run would meet.
expect 0 "torus_puddle.json: step size 0.001 s, about 34 substeps per frame" -- \
  check-scene "$torus" --quick --set solver.max_dt=0.001
expect 0 "substeps per frame; the itf04 step is limited" -- \
  check-scene "$torus" --quick --set solids.0.material.young=1e9 --set solids.0.material.strength=1
expect 0 "a run would stop before its first frame; the itf04 step is limited" -- \
  check-scene "$torus" --quick --set solids.0.material.young=1e9 --set solids.0.material.strength=1 \
  --set solver.max_substeps_per_frame=100
rm -rf "$work/ramp"
expect 1 "more than solver.max_substeps_per_frame (100); the itf04" -- \
  run "$torus" --quick --out "$work/ramp" --set solids.0.material.young=1e7 --set solver.max_substeps_per_frame=100
err=$("$invfem" run "$torus" --quick --out "$work/ramp" --overwrite --quiet --set solids.0.material.young=1e7 \
  --set solver.max_substeps_per_frame=100 2>&1)
frame=$(sed -n 's/.*: frame \([0-9]*\) (t = .*/\1/p' <<<"$err")
if [ -z "$frame" ] || [ "$frame" -lt 2 ] || ! grep -qF "frames up to $((frame - 1)) are in $work/ramp" <<<"$err" ||
   [ ! -e "$work/ramp/frames/torus/$(printf %04d $((frame - 1))).obj" ] ||
   [ -e "$work/ramp/frames/torus/$(printf %04d "$frame").obj" ]; then
  echo "FAIL: the substep limit reached later in the run: $err"; fail=1
fi
expect 2 '$.solver.max_substeps_per_frame: expected an integer in [1, 2147483647]' -- \
  check-scene "$torus" --set solver.max_substeps_per_frame=0

# 7. Memory inside the allowed ranges: a scene is estimated before anything is built (check-scene
#    prints it) and one over the budget (--memory-limit, default a share of the machine's memory)
#    is refused with the estimate and the field to change; the refusal comes at once, before the
#    BCC mesher would take gigabytes.
muscle="$src/apps/scenes/muscle.json"
start=$(date +%s)
expect 2 "the scene needs about 335 GB" -- run "$muscle" --out "$work/mem" --set solids.0.mesh_resolution=1000
expect 2 "solids[0].mesh_resolution: mesh_resolution" -- check-scene "$muscle" --set solids.0.mesh_resolution=1000
[ $(( $(date +%s) - start )) -lt 30 ] || { echo "FAIL: the refusals of a 335 GB scene took $(( $(date +%s) - start )) s"; fail=1; }
[ ! -e "$work/mem/frames" ] || { echo "FAIL: a refused scene wrote frames"; fail=1; }
expect 2 "more than the limit of 50 MB (--memory-limit 50M): cloths[0].grid.nx: nx and ny scaled by" -- \
  run "$drape" --quick --out "$work/mem" --set cloths.0.grid.nx=400 --set cloths.0.grid.ny=400 --memory-limit 50M
expect 2 "--memory-limit: expected a size such as 16G, 512M or 2000000000 (bytes), or none; found \"12Q\"" -- \
  run "$drape" --quick --out "$work/mem" --memory-limit 12Q
expect_output 0 "memory: about 8" -- check-scene "$muscle"
expect_output 0 "limit none" -- check-scene "$muscle" --memory-limit none
expect_output 0 "valid" -- check-scene "$muscle" --set solids.0.mesh_resolution=48 --memory-limit 1G

exit $fail
