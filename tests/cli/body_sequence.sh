#!/usr/bin/env bash
# A "sequence" collider (a body from a mesh sequence) in the scene file: bad fields and bad frames
# give a message naming the file and exit code 2, whether found at load (pattern, missing file,
# frame 0) or when the run reaches the frame (its later frames are read lazily); a good one runs
# and writes the body's frames.
#   body_sequence.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
mkdir -p "$work/seq"

for k in 0 1 2 3 4 5 6; do cp "$src/apps/scenes/data/moving_box/box$k.obj" "$work/seq/box$k.obj"; done
# A frame with one vertex more than frame 0, and a frame 0 with a NaN.
mkdir -p "$work/more" "$work/nan"
cp "$work/seq/box0.obj" "$work/more/box0.obj"
cp "$work/seq/box1.obj" "$work/more/box1.obj"
{ cat "$work/seq/box2.obj"; echo "v 5 5 5"; } > "$work/more/box2.obj"
sed '2s/^v [^ ]*/v nan/' "$work/seq/box0.obj" > "$work/nan/box0.obj"
cp "$work/seq/box1.obj" "$work/nan/box1.obj"

scene() {  # scene NAME SEQUENCE_FIELDS: a small cloth above a sequence collider with these fields
  printf '{"fps": 10, "frames": 12, "cloths": [{"name": "c", "grid": {"width": 0.3, "height": 0.3, "nx": 3, "ny": 3}, "transform": {"translate": [0, 0.4, 0]}}], "colliders": [{"name": "box", "type": "sequence", %s}]}\n' "$2" \
    > "$work/$1.json"
  echo "$work/$1.json"
}
at='$.colliders[0]'
expect 2 "$at.frames.pattern: expected a pattern with one {N} or {N:0W} placeholder" -- \
  run "$(scene nopat '"frames": {"pattern": "seq/box.obj", "first": 0, "last": 6}, "fps": 2')" --out "$work/o"
expect 2 "$at.frames.pattern: expected existing frame files, found \"$work/seq/box7.obj\" (frame 7)" -- \
  run "$(scene absent '"frames": {"pattern": "seq/box{N}.obj", "first": 0, "last": 7}, "fps": 2')" --out "$work/o"
expect 2 "$at.frames: expected either" -- \
  run "$(scene both '"frames": {"pattern": "seq/box{N}.obj", "last": 1}, "files": ["seq/box0.obj"], "fps": 2')" --out "$work/o"
expect 2 "$at.fps: expected the sequence's frame rate" -- \
  run "$(scene nofps '"files": ["seq/box0.obj", "seq/box1.obj"]')" --out "$work/o"
expect 2 "$at.start_frame: expected either start_time or start_frame" -- \
  run "$(scene start '"files": ["seq/box0.obj"], "fps": 2, "start_time": 1, "start_frame": 0')" --out "$work/o"
expect 2 "$at.after_end: expected \"hold\" or \"loop\"" -- \
  run "$(scene end '"files": ["seq/box0.obj"], "fps": 2, "after_end": "bounce"')" --out "$work/o"
expect 2 "$at.motion: expected no \"motion\" on a sequence" -- \
  run "$(scene motion '"files": ["seq/box0.obj"], "fps": 2, "motion": {"velocity": [1, 0, 0]}')" --out "$work/o"
# Frame 0 is read when the world is built.
expect 2 "$work/nan/box0.obj:2:" -- \
  run "$(scene nan '"frames": {"pattern": "nan/box{N}.obj", "first": 0, "last": 1}, "fps": 2')" --out "$work/o"
# A later bad frame stops the run when it is reached (t = 0.5 s: the interval [1, 2) needs it).
expect 2 "$work/more/box2.obj: 27 vertices, but frame 0 ($work/more/box0.obj) has 26" -- \
  run "$(scene more '"frames": {"pattern": "more/box{N}.obj", "first": 0, "last": 2}, "fps": 2')" --out "$work/o_more" --quiet
if [ ! -f "$work/o_more/frames/c/0004.obj" ] || [ -f "$work/o_more/frames/c/0005.obj" ]; then
  echo "FAIL: the run stopped by a bad frame should have written frames 0..4 and no more"; fail=1
fi
# check-scene reads every frame, so it finds the bad one before a run does.
expect 2 "collider \"box\": $work/more/box2.obj: 27 vertices" -- check-scene "$work/more.json"
# A good sequence, by list, started at its frame 2 and looped: the body's frames are written.
expect 0 "" -- run "$(scene good '"files": ["seq/box0.obj", "seq/box2.obj", "seq/box4.obj"], "fps": 5, "start_frame": 2, "after_end": "loop", "transform": {"scale": 0.5}')" --out "$work/o_good" --quiet
for f in 0000 0012; do
  [ -f "$work/o_good/frames/box/$f.obj" ] || { echo "FAIL: no frames/box/$f.obj"; fail=1; }
done
expect_output 0 "sequence \"box\": 3 frames read and checked" -- check-scene "$work/good.json"
[ $fail -eq 0 ] && echo "all body sequence CLI checks passed"
exit $fail
