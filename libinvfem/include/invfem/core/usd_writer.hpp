#pragma once
// USD ASCII (.usda) animation of one triangle surface: fixed topology, time-sampled points.
#include <map>
#include <string>

#include "invfem/core/types.hpp"

namespace invfem {

// Collects frames and rewrites the whole .usda atomically on every add_frame, so a killed run
// leaves a valid file holding the frames written so far. Layer metadata: upAxis "Y",
// metersPerUnit 1, timeCodesPerSecond = framesPerSecond = fps, start/endTimeCode = first/last
// frame. Prims: /<name> (Xform, the defaultPrim) and /<name>/mesh (Mesh, subdivisionScheme
// "none", rightHanded = counter-clockwise seen from outside) with faceVertexCounts,
// faceVertexIndices, points (first frame) plus points.timeSamples and extent(.timeSamples).
// Time code = frame number. Points are point3f (USD's schema type), written with 9 digits.
// Cost: the text of each frame is formatted once and kept, but the file write grows with the
// number of frames (quadratic over a run).
class UsdaAnimationWriter {
 public:
  // `object_name` becomes the prim name: characters outside [A-Za-z0-9_] become '_', and a
  // leading digit (or an empty name) gets a '_' prefix. Throws std::invalid_argument for
  // fps <= 0 or non-finite, no triangles, or a negative index.
  UsdaAnimationWriter(std::string path, const std::string& object_name, Tris tris, double fps);

  // Adds (or replaces) frame `frame` >= 0 and rewrites the file. Throws std::invalid_argument
  // naming the path and frame for a negative frame, a point count different from the first
  // frame's, an index in tris outside [0, n) or a non-finite position; std::runtime_error if
  // the file cannot be written (the frame is then not kept).
  void add_frame(int frame, const Points& x);

  const std::string& path() const { return path_; }
  const std::string& prim_name() const { return prim_; }
  std::size_t num_frames() const { return frames_.size(); }

 private:
  struct Frame {
    std::string points;  // "[(x, y, z), ...]"
    std::string extent;  // "[(min), (max)]"
  };
  std::string render() const;

  std::string path_;
  std::string prim_;
  Tris tris_;
  double fps_;
  Eigen::Index num_points_ = -1;  // fixed by the first frame
  std::map<int, Frame> frames_;
};

// A valid USD identifier made from `name` (see UsdaAnimationWriter's constructor).
std::string usd_identifier(const std::string& name);

}  // namespace invfem
