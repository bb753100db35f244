#!/usr/bin/env bash
# Issue 13: a run resumed from a checkpoint taken after a fracture (plate_tear tears at frame 2;
# the checkpoint of frame 6 holds the cut mesh; with the implicit integrator, that of frame 2, whose
# last step tore) writes the same frames (OBJ and VTU, each with its
# own topology, and the USD animation with its time-varying topology) and energies, bit for bit, as
# the run that was never stopped.
#   fracture_resume.sh INVFEM SCENE WORKDIR
set -uo pipefail
invfem="$1" scene="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
# resume_matches LABEL REFERENCE RESUMED FRAME RUN...: `RUN... --out RESUMED --resume` resumes from
# the checkpoint of FRAME and writes REFERENCE's frames and energies, bit for bit; else FAIL, fail=1.
resume_matches() {
  local label="$1" reference="$2" resumed="$3" frame="$4"
  shift 4
  local out
  out=$("$@" --out "$resumed" --resume 2>&1) || { echo "FAIL: $label: the resumed run failed: $out"; fail=1; }
  if ! grep -qF "resuming from the checkpoint of frame $frame" <<<"$out"; then
    echo "FAIL: $label: no resume from frame $frame: $out"
    fail=1
  fi
  if ! diff -r -q "$reference/frames" "$resumed/frames" || ! cmp -s "$reference/energies.csv" "$resumed/energies.csv"; then
    echo "FAIL: $label: the resumed frames differ from the uninterrupted run"
    fail=1
  fi
}
run() { "$invfem" run "$scene" --quick --set frames=12 --threads 1 --checkpoint-every 3 --format obj,vtu,usd "$@"; }
run --out "$work/reference" > "$work/reference.log" 2>&1 || { echo "FAIL: the reference run failed"; exit 1; }
cells=$(grep -a -o 'NumberOfCells="[0-9]*"' "$work/reference/frames/slab/0012.vtu")
if [ "$cells" != 'NumberOfCells="1056"' ]; then echo "FAIL: the slab did not tear as expected: $cells"; fail=1; fi
# The USD animation: one topology sample before the tear, one more at each frame that changed it.
usd="$work/reference/frames/slab.usda"
if ! grep -q "faceVertexIndices.timeSamples" "$usd" || [ "$(sed -n '/faceVertexCounts.timeSamples/,/}/p' "$usd" | grep -c '^ *[0-9]*: \[')" -lt 2 ]; then
  echo "FAIL: $usd has no time-varying topology"; fail=1
fi
# The ParaView series: OUT/slab.pvd names every VTU frame by a path that exists from OUT.
pvd="$work/reference/slab.pvd"
listed=$(grep -o 'file="[^"]*"' "$pvd" | sed 's/file="//; s/"$//')
if [ "$(echo "$listed" | grep -c .)" -ne 13 ]; then echo "FAIL: $pvd lists $(echo "$listed" | grep -c .) frames, expected 13"; fail=1; fi
for f in $listed; do [ -f "$work/reference/$f" ] || { echo "FAIL: $pvd names $f, which does not exist"; fail=1; }; done
cp -r "$work/reference" "$work/resumed"
rm "$work/resumed/checkpoints/0009.ckpt" "$work/resumed/checkpoints/0012.ckpt"
rm "$work/resumed/frames/slab/"00{07,08,09,10,11,12}.*
resume_matches itf04 "$work/reference" "$work/resumed" 6 run
# The implicit integrator keeps per-node state between steps (lagged contact forces, the last
# accelerations): a checkpoint of a frame whose last step tore (frame 2) must hold it for the new
# nodes, or none, and resume to the same bits (not refuse it with "contact forces for another
# number of nodes").
run_implicit() { "$invfem" run "$scene" --quick --set frames=4 --set solver.integrator=implicit --threads 1 --checkpoint-every 1 "$@"; }
run_implicit --out "$work/implicit" > "$work/implicit.log" 2>&1 || { echo "FAIL: the implicit reference run failed"; exit 1; }
cp -r "$work/implicit" "$work/implicit_resumed"
rm "$work/implicit_resumed/checkpoints/"000{3,4}.ckpt "$work/implicit_resumed/frames/slab/"000{3,4}.*
resume_matches implicit "$work/implicit" "$work/implicit_resumed" 2 run_implicit
if [ "$fail" -ne 0 ]; then exit 1; fi
echo "a run resumed after a fracture is bit-identical (ITF04 and implicit steps)"
