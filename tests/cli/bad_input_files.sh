#!/usr/bin/env bash
# Issue 12, class 7: a path that is not a readable regular file (a directory, a device, a symbolic
# link loop, a damaged mesh) and an output folder that cannot be used are bad input: exit 2 and a
# message naming the file and its problem, never a raw library message or exit 1.
#   bad_input_files.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
good="$src/apps/scenes/torus_puddle.json"
cd "$work" || exit 1
mkdir adir
ln -s loop_b loop_a && ln -s loop_a loop_b
ln -s nowhere.obj dangling.obj
head -c 3000 /dev/zero > binary.obj  # NUL bytes: assimp fails and gives no reason
touch afile
cloth() { printf '{"frames": 2, "cloths": [{"name": "c", "mesh": "%s"}]}\n' "$1" > "$2.json"; echo "$work/$2.json"; }
solid() { printf '{"frames": 2, "solids": [{"name": "s", "mesh": "%s"}]}\n' "$1" > "$2.json"; echo "$work/$2.json"; }

# The scene itself.
expect 2 "adir: cannot open the scene file: is a directory, not a regular file" -- run adir --out o
expect 2 "/dev/zero: cannot open the scene file: is not a regular file" -- check-scene /dev/zero
expect 2 "loop_a: cannot open the scene file: is a symbolic link loop" -- check-scene loop_a
expect 2 "no such scene file (is a directory" -- batch adir --out b
# A mesh: the scene's field names the path and the problem.
expect 2 "\"$work/adir\", which is a directory, not a regular file" -- check-scene "$(cloth adir dir_mesh)"
expect 2 "\"$work/adir\", which is a directory, not a regular file" -- run "$(solid adir dir_solid)" --out o
expect 2 "\"$work/loop_a\", which is a symbolic link loop" -- check-scene "$(cloth loop_a loop_mesh)"
expect 2 "\"/dev/zero\", which is not a regular file (a device, FIFO or socket)" -- check-scene "$(cloth /dev/zero zero_mesh)"
expect 2 "\"$work/dangling.obj\", which is a symbolic link to a file that does not exist" -- \
  check-scene "$(solid dangling.obj dangling_mesh)"
# A damaged surface read by assimp: its reason, or a stated lack of one, never an empty one.
expect 2 "binary.obj: assimp could not read the file: no reason given (the file is damaged, or is not a valid .obj file)" -- \
  check-scene "$(solid binary.obj binary_mesh)"
# Mesh files named on the command line.
expect 2 "adir: cannot open the mesh: is a directory, not a regular file" -- check adir afile
expect 2 "loop_a: cannot open the query file: is a symbolic link loop" -- ccd loop_a
# The output folder: empty, a file, under a file, not creatable.
expect 2 "--out: empty folder name" -- run "$good" --quick --out ''
expect 2 "--out afile: is a file, not a folder" -- run "$good" --quick --out afile
expect 2 "--out afile/sub: cannot create the folder" -- run "$good" --quick --out afile/sub
expect 2 "--out: empty folder name" -- batch "$good" --out ''
expect 2 "--out afile: is a file, not a folder" -- batch "$good" --out afile
# render --camera: non-finite numbers, and a position equal to the target.
mkdir -p r && cp "$good" r/scene.json
expect 2 "--camera: number 2 (\"0,nan,0,1,1,1\") is not finite" -- render r --camera 0,nan,0,1,1,1
expect 2 "--camera: number 4 (\"0,0,0,inf,1,1\") is not finite" -- render r --camera 0,0,0,inf,1,1
expect 2 "--camera: the position equals the target" -- render r --camera 1,2,3,1,2,3
expect 2 "r2/scene.json: cannot open (is a directory, not a regular file" -- render "$(mkdir -p r2/scene.json && echo r2)"
if [ "$fail" -ne 0 ]; then exit 1; fi
echo "bad input files and output folders: exit 2 naming the file and the problem"
