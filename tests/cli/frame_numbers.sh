#!/usr/bin/env bash
# The scene's first_frame_number numbers every file a run writes, for DCC timelines that start at
# 1: frame k is NNNN = k + 1 in frames/<object>/ (OBJ, PLY, VTU and the ParaView series' entries),
# png/, the USD layers' time codes and the stage's range, and the point caches' start frame; the
# checkpoints, --frames and energies.csv count frames from 0. check and render read the numbered
# files; --resume extends the numbering; resuming with another numbering is another scene.
#   frame_numbers.sh INVFEM SCENE WORKDIR
invfem="$1" scene="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
out="$work/run"
run() { timeout 120 "$invfem" run "$scene" --quick --quiet --threads 2 --checkpoint-every 2 --set first_frame_number=1 "$@"; }
run --set frames=3 --format obj,ply,vtu,usd,pc2 --render --out "$out" || { echo "FAIL: the run"; exit 1; }
names() { ls "$1" | grep -E "^[0-9]{4}\.$2$" | tr '\n' ' '; }
for ext in obj ply vtu; do
  [ "$(names "$out/frames/cloth" $ext)" = "0001.$ext 0002.$ext 0003.$ext 0004.$ext " ] ||
    { echo "FAIL: .$ext frames are $(names "$out/frames/cloth" $ext)"; fail=1; }
done
[ "$(names "$out/png" png)" = "0001.png 0002.png 0003.png 0004.png " ] || { echo "FAIL: previews $(names "$out/png" png)"; fail=1; }
[ "$(ls "$out/checkpoints")" = "$(printf '0002.ckpt\n0003.ckpt')" ] || { echo "FAIL: checkpoints $(ls "$out/checkpoints")"; fail=1; }
[ "$(tail -n +2 "$out/energies.csv" | cut -d, -f1 | tr '\n' ' ')" = "0 1 2 3 " ] || { echo "FAIL: energies.csv frames"; fail=1; }
grep -q 'startTimeCode = 1$' "$out/shot.usda" && grep -q 'endTimeCode = 4$' "$out/shot.usda" ||
  { echo "FAIL: shot.usda's range: $(grep TimeCode "$out/shot.usda")"; fail=1; }
grep -q '^ *1: \[' "$out/frames/cloth.usda" && ! grep -q '^ *0: \[' "$out/frames/cloth.usda" ||
  { echo "FAIL: the cloth's layer is not sampled from time code 1"; fail=1; }
[ "$(grep -o 'file="[^"]*"' "$out/cloth.pvd" | head -1)" = 'file="frames/cloth/0001.vtu"' ] ||
  { echo "FAIL: cloth.pvd's first entry: $(grep -o 'file="[^"]*"' "$out/cloth.pvd" | head -1)"; fail=1; }
pc2() { python3 -c "import struct, sys; h = open(sys.argv[1], 'rb').read(32); print(struct.unpack('<ff', h[20:28])[0], struct.unpack('<i', h[28:32])[0])" "$1"; }
[ "$(pc2 "$out/cloth.pc2")" = "1.0 4" ] || { echo "FAIL: cloth.pc2 starts at, holds: $(pc2 "$out/cloth.pc2"), want 1.0 4"; fail=1; }
# check and render work on the numbered files.
expect_output 0 "no intersecting triangle pairs" -- check "$out"
expect_output 0 "rendered $out/png/0004.png  (4/4" -- render "$out" --width 32 --height 24
expect 2 "--frames: frame 0 was not written (the run has frames 1-4, numbered as its files)" -- render "$out" --frames 0-2
# A scene whose camera is framed on frame 0 (its files numbered 1): rendered as it runs.
torus="$(dirname "$scene")/torus_puddle.json"
timeout 120 "$invfem" run "$torus" --quick --quiet --set frames=1 --set first_frame_number=1 --render --out "$work/torus" ||
  { echo "FAIL: a run with an automatic camera and numbered files"; fail=1; }
[ "$(names "$work/torus/png" png)" = "0001.png 0002.png " ] || { echo "FAIL: the torus's previews $(names "$work/torus/png" png)"; fail=1; }
# Extended by --resume: the numbering goes on, every format continues.
run --set frames=5 --format obj,ply,vtu,usd,pc2 --render --out "$out" --resume > /dev/null || { echo "FAIL: the resume"; fail=1; }
[ "$(names "$out/frames/cloth" obj)" = "0001.obj 0002.obj 0003.obj 0004.obj 0005.obj 0006.obj " ] ||
  { echo "FAIL: after the resume, frames $(names "$out/frames/cloth" obj)"; fail=1; }
grep -q 'startTimeCode = 1$' "$out/shot.usda" && grep -q 'endTimeCode = 6$' "$out/shot.usda" ||
  { echo "FAIL: shot.usda's range after the resume: $(grep TimeCode "$out/shot.usda")"; fail=1; }
[ "$(pc2 "$out/cloth.pc2")" = "1.0 6" ] || { echo "FAIL: cloth.pc2 after the resume: $(pc2 "$out/cloth.pc2")"; fail=1; }
# Another numbering is another scene.
expect 2 "holds a run of another scene (/first_frame_number is 0 now, 1 in the folder's run)" -- \
  run "$scene" --quick --set frames=5 --out "$out" --resume
# A batch's contact sheet takes the last preview, whatever its number.
mkdir -p "$work/scenes"
sed 's/"frames": *[0-9]*,/"frames": 2, "first_frame_number": 1,/' "$scene" |
  sed 's|"data/|"'"$(dirname "$scene")"'/data/|g' > "$work/scenes/numbered.json"
expect_output 0 "contact sheet: $work/batch/contact_sheet.png (1 scenes)" -- batch "$work/scenes/numbered.json" --out "$work/batch"
[ -f "$work/batch/numbered/png/0003.png" ] && [ ! -e "$work/batch/numbered/png/0000.png" ] ||
  { echo "FAIL: the batch's previews: $(ls "$work/batch/numbered/png")"; fail=1; }
[ "$fail" = 0 ] || exit 1
echo "first_frame_number numbers every file and time code; check, render, resume and batch follow it"
