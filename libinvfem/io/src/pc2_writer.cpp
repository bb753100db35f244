#include "invfem/core/io/pc2_writer.hpp"

#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "invfem/core/io/output_error.hpp"

namespace invfem {

namespace {
// The layout is little-endian; so is every machine this builds for (x86-64, aarch64 Linux).
static_assert(sizeof(float) == 4 && sizeof(std::int32_t) == 4);

void write_all(std::FILE* f, const void* data, std::size_t bytes, const std::string& path) {
  if (std::fwrite(data, 1, bytes, f) != bytes)
    throw OutputError(path + ": cannot write the point cache (disk full? free space or choose another folder)");
}
}  // namespace

Pc2Writer::Pc2Writer(std::string path, Eigen::Index points, int first_frame)
    : path_(std::move(path)), points_(points), start_(first_frame) {
  if (points <= 0 || points > 0x7fffffff) throw std::invalid_argument(path_ + ": a point cache needs 1 to 2^31 - 1 points");
  if (first_frame > 0 && std::filesystem::exists(path_)) {
    // Resuming: keep the existing cache's samples before first_frame, if it holds them all.
    file_ = std::fopen(path_.c_str(), "r+b");
    if (!file_) throw OutputError(path_ + ": cannot reopen the point cache to resume it (check its permissions)");
    char head[kHeaderBytes];
    std::int32_t stored_points = 0, stored_samples = 0;
    float stored_start = 0;
    if (std::fread(head, 1, sizeof head, file_) != sizeof head || std::memcmp(head, "POINTCACHE2\0", 12) != 0)
      throw OutputError(path_ + ": not a PC2 point cache, so a resumed run cannot continue it: move it away");
    std::memcpy(&stored_points, head + 16, 4);
    std::memcpy(&stored_start, head + 20, 4);
    std::memcpy(&stored_samples, head + 28, 4);
    const long long keep = first_frame - static_cast<long long>(stored_start);
    std::fclose(file_);
    file_ = nullptr;
    if (stored_points == points_ && keep >= 0 && keep <= stored_samples) {
      std::filesystem::resize_file(path_, static_cast<std::uintmax_t>(kHeaderBytes + 12LL * points_ * keep));
      file_ = std::fopen(path_.c_str(), "r+b");
      start_ = static_cast<int>(stored_start);
      samples_ = static_cast<int>(keep);
    }
  }
  if (!file_) file_ = std::fopen(path_.c_str(), "w+b");  // a new cache from first_frame on
  if (!file_) throw OutputError(path_ + ": cannot write the point cache (check the folder's permissions)");
  char head[kHeaderBytes] = {};
  std::memcpy(head, "POINTCACHE2\0", 12);
  const std::int32_t version = 1, n = static_cast<std::int32_t>(points_), samples = samples_;
  const float start = static_cast<float>(start_), rate = 1.0f;  // one sample per frame
  std::memcpy(head + 12, &version, 4);
  std::memcpy(head + 16, &n, 4);
  std::memcpy(head + 20, &start, 4);
  std::memcpy(head + 24, &rate, 4);
  std::memcpy(head + 28, &samples, 4);
  std::fseek(file_, 0, SEEK_SET);
  write_all(file_, head, sizeof head, path_);
  std::fflush(file_);
}

Pc2Writer::~Pc2Writer() {
  if (file_) std::fclose(file_);
}

void Pc2Writer::add(const Points& x) {
  if (x.rows() != points_)
    throw std::invalid_argument(path_ + ": " + std::to_string(x.rows()) + " points where the cache holds " +
                                std::to_string(points_));
  if (!x.allFinite()) throw std::invalid_argument(path_ + ": a non-finite position");
  std::vector<float> data(static_cast<std::size_t>(3 * points_));
  for (Eigen::Index i = 0; i < points_; ++i)
    for (int c = 0; c < 3; ++c) data[static_cast<std::size_t>(3 * i + c)] = static_cast<float>(x(i, c));
  std::fseek(file_, kHeaderBytes + 12L * points_ * samples_, SEEK_SET);
  write_all(file_, data.data(), data.size() * sizeof(float), path_);
  ++samples_;
  const std::int32_t samples = samples_;
  std::fseek(file_, 28, SEEK_SET);
  write_all(file_, &samples, 4, path_);
  if (std::fflush(file_) != 0)
    throw OutputError(path_ + ": cannot write the point cache (disk full? free space or choose another folder)");
}

}  // namespace invfem
