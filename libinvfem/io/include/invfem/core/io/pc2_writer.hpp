#pragma once
// A point cache in the PC2 layout (Blender's Mesh Cache modifier, 3ds Max's Point Cache, Maya's
// plug-ins): one object's vertex positions per frame, played over its frame-0 mesh (same vertex
// order). Little-endian:
//   char[12] "POINTCACHE2\0"; int32 version = 1; int32 points; float32 start frame;
//   float32 sample rate (frames per sample); int32 samples;
//   then per sample, per point, float32 x, y, z.
// Written as frames come: each add appends a sample and then updates the header's sample count,
// so the file is a valid cache of the frames so far after every frame.
#include <cstdint>
#include <cstdio>
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem {

class Pc2Writer {
 public:
  // A cache of `points` vertices at `path` whose next sample is frame first_frame. An existing
  // cache of as many points holding the frames before it (a resumed run) is continued, its later
  // samples dropped; otherwise a new cache starts at first_frame (its header's start frame).
  // Throws OutputError (output_error.hpp) naming the file when it cannot be written or is no PC2 cache.
  Pc2Writer(std::string path, Eigen::Index points, int first_frame = 0);
  ~Pc2Writer();
  Pc2Writer(const Pc2Writer&) = delete;
  Pc2Writer& operator=(const Pc2Writer&) = delete;

  // Appends x (points x 3). Throws std::invalid_argument for another vertex count or a non-finite
  // position, std::runtime_error when the file cannot be written.
  void add(const Points& x);
  Eigen::Index points() const { return points_; }
  int samples() const { return samples_; }
  int start_frame() const { return start_; }

  static constexpr long kHeaderBytes = 32;

 private:
  std::string path_;
  Eigen::Index points_;
  int start_ = 0;    // the frame of sample 0
  int samples_ = 0;
  std::FILE* file_ = nullptr;
};

}  // namespace invfem
