#!/usr/bin/env bash
# Issue 12, class 3: a damaged checkpoint is never resumed from. One flipped bit in a node position
# or in the time field, a NaN written with a valid checksum, a directory in a checkpoint's place,
# an older format: each is skipped with a warning naming the file, the previous valid checkpoint
# is used, and the resumed frames are bit-identical to the uninterrupted run. A checkpoint of
# another scene says what differs.
#   checkpoint_integrity.sh INVFEM SCENE WORKDIR
set -uo pipefail
invfem="$1" scene="$2" work="$3"
rm -rf "$work" && mkdir -p "$work"
fail=0
common=(--quick --set frames=12 --checkpoint-every 4 --threads 2 --format obj)
"$invfem" run "$scene" "${common[@]}" --quiet --out "$work/reference" || { echo "FAIL: the reference run"; exit 1; }

# edit RUN FRAME WHAT: damage RUN/checkpoints/FRAME.ckpt (python: the layout of checkpoint.hpp).
edit() {
  /usr/bin/python3 - "$work/$1/checkpoints/$2.ckpt" "$3" <<'PY'
import struct, sys
path, what = sys.argv[1], sys.argv[2]
b = bytearray(open(path, 'rb').read())
# magic 8, version u32, scene hash u64, frame i64, time f64, csv (u64 n + bytes), state (u64 n + bytes)
time_at = 8 + 4 + 8 + 8
csv_len, = struct.unpack_from('<Q', b, time_at + 8)
state_at = time_at + 8 + 8 + csv_len + 8
# world state: u64 pass count and each pass's state (u64 n + bytes), u64 object count, name
# (u64 n + bytes), positions (u64 n + n doubles)
passes, = struct.unpack_from('<Q', b, state_at)
state_at += 8
for _ in range(passes):
    n, = struct.unpack_from('<Q', b, state_at)
    state_at += 8 + n
name_len, = struct.unpack_from('<Q', b, state_at + 8)
x_at = state_at + 8 + 8 + name_len + 8
def fnv(data):
    h = 1469598103934665603
    for c in data:
        h = ((h ^ c) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h
if what == 'position_bit':
    b[x_at + 8 * 7 + 2] ^= 0x04        # a low mantissa bit of node 2's z
elif what == 'time_bit':
    b[time_at] ^= 0x01                 # the lowest bit of the time
elif what in ('nan', 'time_nan'):
    struct.pack_into('<d', b, x_at + 8 * 4 if what == 'nan' else time_at, float('nan'))
    struct.pack_into('<Q', b, len(b) - 16, fnv(b[:len(b) - 16]))  # a valid checksum
elif what == 'version2':
    struct.pack_into('<I', b, 8, 2)
open(path, 'wb').write(b)
PY
}

# resume_case NAME DAMAGE... : copy the reference, keep checkpoints 0004 and 0008, damage 0008
# (each DAMAGE is an edit or "dir"), resume; want exit 0, a warning naming 0008.ckpt and PATTERN,
# a resume from frame 4, and frames identical to the reference.
resume_case() {
  local name="$1" damage="$2" pattern="$3"
  cp -r "$work/reference" "$work/$name"
  rm "$work/$name/checkpoints/0012.ckpt"
  if [ "$damage" = dir ]; then
    rm "$work/$name/checkpoints/0008.ckpt" && mkdir "$work/$name/checkpoints/0008.ckpt"
  else
    edit "$name" 0008 "$damage"
  fi
  local out
  out=$("$invfem" run "$scene" "${common[@]}" --out "$work/$name" --resume 2>&1)
  local rc=$?
  if [ "$rc" -ne 0 ] || ! grep -qF "warning: skipping $work/$name/checkpoints/0008.ckpt: checkpoint $pattern" <<<"$out" ||
     ! grep -qF "resuming from the checkpoint of frame 4" <<<"$out"; then
    echo "FAIL: $name: exit $rc, output: $(head -c 2000 <<<"$out") (want a warning with: $pattern)"
    fail=1
  fi
  if ! diff -r -q "$work/reference/frames" "$work/$name/frames" >/dev/null ||
     ! cmp -s "$work/reference/energies.csv" "$work/$name/energies.csv"; then
    echo "FAIL: $name: the resumed frames differ from the uninterrupted run"
    fail=1
  fi
}
resume_case position_bit position_bit "is damaged (its checksum does not match its content)"
resume_case time_bit time_bit "is damaged (its checksum does not match its content)"
resume_case nan nan "does not fit this scene: the position of node 1 of \"torus\" is not finite"
resume_case time_nan time_nan "holds time nan s, not the time of frame 8"
resume_case directory dir "cannot be read: is a directory, not a regular file"
resume_case version2 version2 "has format version 2, this invfem reads version 5"

# Another scene: refused before any work (the folder holds this scene's run), saying what differs.
cp -r "$work/reference" "$work/other"
out=$("$invfem" run "$scene" "${common[@]}" --quiet --out "$work/other" --resume --set gravity=[0,-5,0] 2>&1)
code=$?
if [ "$code" != 2 ] || ! grep -qF "holds a run of another scene (/gravity/1 is -5.0 now, -9.81 in the folder's run)" <<<"$out"; then
  echo "FAIL: another scene: exit $code: $(head -c 2000 <<<"$out")"
  fail=1
fi
cmp -s "$work/reference/energies.csv" "$work/other/energies.csv" || { echo "FAIL: the refused run changed the folder"; fail=1; }
if [ "$fail" -ne 0 ]; then exit 1; fi
echo "damaged checkpoints are skipped with a warning naming them; resumes stay bit-identical"
