#!/usr/bin/env bash
# --format pc2: each object's and body's point cache, read back by a PC2 reader written here from
# the format's published layout (not from the writer), holds every frame's OBJ positions (float32),
# in the frame-0 OBJ's vertex order; a run extended with --resume continues its caches.
#   point_cache.sh INVFEM SCENE WORKDIR
set -euo pipefail
invfem="$1" scene="$2" work="$3"
rm -rf "$work" && mkdir -p "$work"
command -v python3 >/dev/null || { echo "skipped: no python3"; exit 0; }
common=(--quick --checkpoint-every 2 --threads 2 --quiet --format obj,pc2)
"$invfem" run "$scene" "${common[@]}" --set frames=4 --out "$work/run"
"$invfem" run "$scene" "${common[@]}" --set frames=6 --out "$work/run" --resume
python3 - "$work/run" <<'PY'
import glob, os, struct, sys
out = sys.argv[1]
def read_pc2(path):
    # PC2: char[12] "POINTCACHE2\0", int32 version, int32 points, float32 start frame,
    # float32 sample rate, int32 samples, then samples x points x 3 float32, little-endian.
    data = open(path, "rb").read()
    sig, version, points, start, rate, samples = struct.unpack_from("<12sii2fi", data, 0)
    assert sig == b"POINTCACHE2\0" and version == 1, (path, sig, version)
    assert len(data) == 32 + 12 * points * samples, (path, len(data), points, samples)
    frames = [struct.unpack_from("<%df" % (3 * points), data, 32 + 12 * points * k) for k in range(samples)]
    return points, start, rate, frames
def obj_vertices(path):
    return [tuple(float(w) for w in l.split()[1:4]) for l in open(path) if l.startswith("v ")]
caches = sorted(glob.glob(os.path.join(out, "*.pc2")))
assert caches, "no point cache written"
for path in caches:
    name = os.path.basename(path)[:-4]
    points, start, rate, frames = read_pc2(path)
    assert start == 0 and rate == 1, (path, start, rate)
    assert len(frames) == 7, (path, len(frames))  # frames 0..6, the last two after --resume
    for f, sample in enumerate(frames):
        v = obj_vertices(os.path.join(out, "frames", name, "%04d.obj" % f))
        assert len(v) == points, (path, f, len(v), points)
        worst = max(abs(a - b) / max(1.0, abs(b)) for k, p in enumerate(v) for a, b in zip(sample[3 * k:3 * k + 3], p))
        assert worst < 1e-6, (path, f, worst)
    print("%s: %d points, %d frames, as the OBJ frames" % (os.path.basename(path), points, len(frames)))
PY
echo "point caches hold every frame, and a resumed run continues them"
