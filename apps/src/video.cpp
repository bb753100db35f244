#include "video.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace invfem::app {

bool have_ffmpeg() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string d; std::getline(dirs, d, ':');)
    if (!d.empty() && ::access((std::filesystem::path(d) / "ffmpeg").c_str(), X_OK) == 0) return true;
  return false;
}

void encode_mp4(const std::filesystem::path& png_dir, int first, int last, double fps, const std::filesystem::path& mp4) {
  std::ostringstream rate;
  rate.precision(17);
  rate << fps;
  const std::vector<std::string> argv{"ffmpeg", "-loglevel", "error", "-y", "-framerate", rate.str(),
                                      "-start_number", std::to_string(first), "-i", (png_dir / "%04d.png").string(),
                                      "-frames:v", std::to_string(last - first + 1), "-pix_fmt", "yuv420p", "-vf",
                                      "scale=trunc(iw/2)*2:trunc(ih/2)*2", mp4.string()};
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  if (const int rc = posix_spawnp(&pid, "ffmpeg", nullptr, nullptr, args.data(), environ); rc != 0)
    throw std::runtime_error(mp4.string() + ": cannot run ffmpeg: " + std::strerror(rc));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error(mp4.string() + ": waiting for ffmpeg failed: " + std::strerror(errno));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(mp4.string() + ": ffmpeg failed (" +
                             (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                                : "killed by signal " + std::to_string(WTERMSIG(status))) +
                             ")");
}

}  // namespace invfem::app
