#!/usr/bin/env bash
# Issue 45: nothing skipped quietly, every input as its reader should take it, one meaning per exit
# code. `render` and `check` name every missing or unreadable frame of the range asked for and
# exit 2 (render draws the others first); a UTF-8 byte order mark is skipped by the OBJ, CCD query
# and welds readers; a key given twice in a scene is an error naming it; output files that cannot
# be written (check --json, bench --json, a frame folder, render's png/) are exit 2 before any
# work, and so is a write that fails on the way (a full disk).
#   frames_and_inputs.sh INVFEM SOURCE_DIR WORKDIR
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
scene="$src/apps/scenes/cloth_drape.json"
timeout 120 "$invfem" run "$scene" --quick --quiet --threads 2 --set frames=5 --out "$work/run" ||
  { echo "FAIL: the run"; exit 1; }

# A frame deleted: render draws the others and names it; check names it and checks nothing.
cp -r "$work/run" "$work/gap"
rm "$work/gap/frames/cloth/0002.obj" "$work/gap/png" -rf
expect_output 2 "frame 2 of 0-5 missing or unreadable, not rendered (first: $work/gap/frames/cloth/0002.obj is missing)" \
  -- render "$work/gap" --width 32 --height 24
[ "$(ls "$work/gap/png" | wc -l)" = 5 ] || { echo "FAIL: render drew $(ls "$work/gap/png" | wc -l) frames, want the 5 present"; fail=1; }
expect 2 "frame 2 of 0-5 missing (first: frames/cloth/0002.obj); the run wrote frames 0-1, 3-5; nothing was checked" \
  -- check "$work/gap"
expect 2 "frames 6-9 of 2-9 missing" -- check "$work/run" --frames 2-9
# A frame that cannot be read (a NaN): named, exit 2, the others drawn.
cp -r "$work/run" "$work/nan"
sed -i '1s/.*/v nan 0 0/' "$work/nan/frames/cloth/0003.obj"
expect_output 2 "frame 3 of 1-4 missing or unreadable" -- render "$work/nan" --frames 1-4 --width 32 --height 24 --camera 0,1,3,0,0,0

# Output files that cannot be written: exit 2, before any work.
# A write that fails mid-run (a full disk, simulated by a file-size limit with SIGXFSZ ignored, so
# the write returns EFBIG as on a full disk) is bad output too: exit 2, naming the file.
code=$( (trap '' XFSZ; ulimit -f 8; timeout 60 "$invfem" run "$scene" --quick --quiet --set frames=2 --out "$work/full" 2>"$work/full.err"); echo $?)
if [ "$code" != 2 ] || ! grep -qF "cannot write $work/full/frames/cloth/0000.obj: writing $work/full/frames/cloth/0000.obj.tmp failed (disk full? free space or choose another folder)" "$work/full.err"; then
  echo "FAIL: a write to a full disk: exit $code (want 2), stderr: $(cat "$work/full.err")"
  fail=1
fi
# render where OUT/png is a file: exit 2 naming it.
cp -r "$work/run" "$work/pngfile" && rm -rf "$work/pngfile/png" && echo "mine" > "$work/pngfile/png"
expect 2 "the previews' folder $work/pngfile/png: is a file, not a folder (move it away, or give another folder)" \
  -- render "$work/pngfile" --width 32 --height 24
expect 2 "check: --json: cannot write \"/proc/x.json\"" -- check "$work/run" --json /proc/x.json
expect 2 "bench: --json: cannot write \"/proc/x.json\"" -- bench --quick --json /proc/x.json
expect 2 "check: --json: cannot write \"$work\": it is a folder" -- check "$work/run" --json "$work"
cp -r "$work/run" "$work/blocked" && rm -r "$work/blocked/frames/cloth" && touch "$work/blocked/frames/cloth"
expect 2 "--out $work/blocked/frames/cloth: is a file, not a folder" -- run "$scene" --quick --set frames=5 --out "$work/blocked" --resume
# Without a run there, the same file is in the run's way, and not invfem's to replace.
rm "$work/blocked/invfem-manifest.txt"
expect 2 "holds scene.json, energies.csv, stats.jsonl, checkpoints, which this run would write, but no run of invfem" \
  -- run "$scene" --quick --set frames=5 --out "$work/blocked"

# A key twice in one object: an error naming it.
sed 's/"fps": *\([0-9.]*\),/"fps": \1, "fps": 50,/' "$scene" > "$work/twice.json"
grep -q '"fps": 50' "$work/twice.json" || { echo "FAIL: could not make the duplicate-key scene"; fail=1; }
cp -r "$src/apps/scenes/data" "$work/" 2>/dev/null
expect 2 "the key \"fps\" appears twice in one object" -- check-scene "$work/twice.json"

# Byte order marks: an OBJ, a query file and a welds file start with one and read as without.
printf '\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n' > "$work/bom.obj"
expect_output 0 "no intersecting triangle pairs" -- check "$work/bom.obj"
printf '\xef\xbb\xbf1 2\n' > "$work/bom_welds.txt"
expect_output 0 "no intersecting triangle pairs" -- check "$work/bom.obj" --welds "$work/bom_welds.txt"
printf '\xef\xbb\xbfvf 0 0 1  -1 -1 0  1 -1 0  0 1 0  0 0 -1  -1 -1 0  1 -1 0  0 1 0\n' > "$work/bom.q"
expect_output 0 "1 hit" -- ccd "$work/bom.q"
# Numbers range-checked where they are read, naming the file (and line) and the bound.
garment() {  # garment NAME SCALE V1X: a two-triangle garment whose pattern is its shape times SCALE
  printf 'v %s 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nvt 0 0\nvt %s 0\nvt %s %s\nvt 0 %s\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n' \
    "$3" "$2" "$2" "$2" "$2" > "$work/$1.obj"
  printf '{ "frames": 1, "cloths": [ { "name": "g", "mesh": "%s.obj", "rest_shape": "pattern",
    "transform": { "translate": [0, 1, 0] } } ] }\n' "$1" > "$work/$1.json"
  echo "$work/$1.json"
}
expect 2 "$work/far.obj:1: vertex 1: x: '1e300' is outside [-1e9, 1e9]" -- check-scene "$(garment far 1 1e300)"
expect 2 "the pattern's edges (vt) are a median 1e-08 times the mesh's, outside [1e-3, 1e3]" -- check-scene "$(garment tiny 1e-8 0)"
expect_output 0 "" -- check-scene "$(garment fine 1 0)"
mkdir -p "$work/seq"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$work/seq/f0.obj"
printf 'v 5e6 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$work/seq/f1.obj"
printf '{ "frames": 1, "cloths": [ { "name": "c", "grid": {"nx": 2, "ny": 2}, "transform": {"translate": [0, 2, 0]} } ],
  "colliders": [ { "name": "body", "type": "sequence", "files": ["seq/f0.obj", "seq/f1.obj"], "fps": 25 } ] }\n' > "$work/seq.json"
expect 2 "$work/seq/f1.obj: vertex 0 is at (5e+06, 0, 0) m after the body's transform, not finite or beyond 1e6 m" \
  -- check-scene "$work/seq.json"
expect 2 "\$.self_collision.thickness: expected a thickness below the median edge length of \"cloth\"" \
  -- check-scene "$scene" --quick --set self_collision.thickness=1
expect 2 "expected a distance below the thickness (1e-9 m), found 1e-5 (its default)" \
  -- check-scene "$scene" --quick --set self_collision.thickness=1e-9
# Messages that say what is wrong: a step count that would take hours (refused at the start,
# with the run's total), CCD lines with a + sign, a trailing comment, a NUL byte; CR-only line
# endings; a null where an object belongs; a folder that takes no files; a mesh output that is
# not a mesh file, before the meshing; an empty checkpoint.
expect 1 "substeps of 1e-06 s (3.33e+05 for the 10 frames), more than solver.max_substeps_per_frame (20000)" \
  -- run "$scene" --quick --set solver.max_dt=1e-6 --set frames=10 --out "$work/slow"
[ ! -e "$work/slow/frames/cloth/0000.obj" ] || { echo "FAIL: the refused run wrote a frame"; fail=1; }
printf 'vf +0 0 1  -1 -1 0  1 -1 0  0 1 0  0 0 -1  -1 -1 0  1 -1 0  0 1 0  # through the middle\n' > "$work/plus.q"
expect_output 0 "1" -- ccd "$work/plus.q"
printf 'vf 0 0 1 \0 0\n' > "$work/nul.q"
expect 2 "$work/nul.q:1: not a number: \"\\x00\"" -- ccd "$work/nul.q"
printf 'v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r' > "$work/cr.obj"
printf '{ "frames": 1, "cloths": [ { "name": "c", "mesh": "cr.obj" } ] }\n' > "$work/cr.json"
expect 2 "$work/cr.obj:1: a carriage return without a line feed: lines end with CR only" -- check-scene "$work/cr.json"
expect 2 "\$.cloths[0].material: expected an object, found null" -- check-scene "$scene" --set cloths.0.material=null
expect 2 "--out /proc: cannot write into the folder: it does not take new files" -- run "$scene" --quick --out /proc
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' > "$work/tet.obj"
expect 2 "mesh: --out $work: expected a file name ending in .vtk or .mesh (it is a folder)" -- mesh "$work/tet.obj" --out "$work"
cp -r "$work/run" "$work/emptyckpt" && : > "$work/emptyckpt/checkpoints/0005.ckpt"
expect_output 0 "0005.ckpt: checkpoint is empty" -- run "$scene" --quick --quiet --set frames=5 --out "$work/emptyckpt" --resume
printf '{ "name": "caf\xe9", "frames": 1 }\n' > "$work/latin1.json"
expect 2 "$work/latin1.json: not UTF-8 text: byte 0xE9 at line 1, column 15" -- check-scene "$work/latin1.json"
for scale in 1e300 1e-300; do
  printf 'v 0 0 0\nv %s 0 0\nv 0 %s 0\nv 0 0 %s\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' $scale $scale $scale > "$work/tet$scale.obj"
done
expect 2 "is not finite (a NaN, or a coordinate beyond the 3.4e38 of the single precision assimp reads in" \
  -- mesh "$work/tet1e300.obj" --out "$work/big.vtk"
expect 2 "every triangle has zero area (every vertex at one point: coordinates below the 1e-38" \
  -- mesh "$work/tet1e-300.obj" --out "$work/small.vtk"
[ "$fail" = 0 ] || exit 1
echo "frames named, byte order marks skipped, duplicate keys refused, output paths checked first"
