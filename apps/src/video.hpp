#pragma once
// Rendered previews (OUT/png/NNNN.png) encoded into a video with ffmpeg, for `invfem render --mp4`
// and `invfem batch --mp4`. ffmpeg is run directly (no shell), so any path works.
#include <filesystem>

namespace invfem::app {

// True when an `ffmpeg` executable is on the PATH.
bool have_ffmpeg();

// Encodes png_dir/NNNN.png for frames first..last, shown at `fps` frames per second, into `mp4`
// (H.264, yuv420p, width and height rounded down to even: what players require). Throws
// std::runtime_error naming the file and ffmpeg's exit status when ffmpeg cannot run or fails.
void encode_mp4(const std::filesystem::path& png_dir, int first, int last, double fps, const std::filesystem::path& mp4);

}  // namespace invfem::app
