#!/usr/bin/env bash
# `invfem render --mp4`: the rendered frames encoded into OUT/<scene name>.mp4 at the scene's
# frame rate, as many video frames as rendered (read back by ffprobe); without ffmpeg on the PATH
# it stops before rendering, naming the missing program (exit 2). Skipped where ffmpeg is absent.
#   render_mp4.sh INVFEM SCENE WORKDIR
set -euo pipefail
invfem="$1" scene="$2" work="$3"
rm -rf "$work" && mkdir -p "$work"
"$invfem" run "$scene" --quick --quiet --threads 2 --set frames=4 --out "$work/run"
# No ffmpeg: a PATH holding only what the command itself needs.
mkdir -p "$work/bin"
set +e
PATH="$work/bin" "$invfem" render "$work/run" --mp4 --width 64 --height 48 > "$work/no_ffmpeg.txt" 2>&1
code=$?
set -e
[ "$code" = 2 ] || { echo "FAIL: render --mp4 without ffmpeg exited $code, expected 2"; cat "$work/no_ffmpeg.txt"; exit 1; }
grep -q "ffmpeg is not installed" "$work/no_ffmpeg.txt" || { echo "FAIL: no message naming ffmpeg"; exit 1; }
[ ! -e "$work/run/png" ] || { echo "FAIL: frames were rendered before the missing ffmpeg was reported"; exit 1; }
if ! command -v ffmpeg >/dev/null || ! command -v ffprobe >/dev/null; then
  echo "skipped: ffmpeg (Debian ffmpeg) is not installed"
  exit 0
fi
"$invfem" render "$work/run" --mp4 --frames 1-4 --width 96 --height 72
read -r name fps < <(python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); print(s["name"], s["fps"])' \
                      "$work/run/scene.json")
video="$work/run/$name.mp4"
[ -s "$video" ] || { echo "FAIL: $video was not written"; exit 1; }
frames=$(ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$video")
rate=$(ffprobe -v error -select_streams v:0 -show_entries stream=r_frame_rate -of csv=p=0 "$video")
[ "$frames" = 4 ] || { echo "FAIL: $video has $frames frames, rendered 4"; exit 1; }
[ "$(awk -v r="$rate" -v f="$fps" 'BEGIN { split(r, a, "/"); print (a[1] / a[2] == f) ? "same" : "differs" }')" = same ] ||
  { echo "FAIL: $video plays at $rate, the scene at $fps fps"; exit 1; }
echo "render --mp4: $frames frames at $rate fps"
