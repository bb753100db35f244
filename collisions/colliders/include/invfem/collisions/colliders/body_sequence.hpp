#pragma once
// A kinematic body animated elsewhere and brought in as a sequence of meshes with one topology
// (a dancer's body from motion capture): frame k is a file, shown at time start_time + k / fps.
//
// Between two frames positions are interpolated linearly in time and the velocity is that
// interpolation's derivative, constant over the interval:
//   s = (t - start_time) * fps,  k = floor(s),  a = s - k,
//   x(t) = (1 - a) X_k + a X_{k+1},   v(t) = (X_{k+1} - X_k) * fps.
// At a frame time t = start_time + k/fps the position is X_k exactly and the velocity is the one of
// the interval that starts there ([k, k+1)): a step ending there has moved along the interval
// before it, and the collision processing at that time sees the motion about to happen.
// Before start_time the body holds frame 0 (velocity 0). Past the last frame N-1:
//   hold: it holds frame N-1 with velocity 0;
//   loop: the sequence repeats with period N / fps; the wrap interval [N-1, N) goes from the last
//         frame back to the first, linearly like any other, with velocity (X_0 - X_{N-1}) * fps.
//         (A capture whose last frame repeats its first should list it only once.)
//
// The body acts on the cloth as every animated mesh body does (animated_mesh_body.hpp).
//
// Frames are streamed: frame 0 is read at construction (its triangles are the topology every
// frame must have), then only the frames an interpolation needs, kept in a cache of a few frames
// (the two bracketing ones and the ones just before). A long sequence is never held whole.
//
// Reading a frame: an OBJ file is read in file vertex order (core obj_file.hpp; vertex i of the
// file is body point i in every frame, nothing is welded or dropped); any other format assimp
// reads goes through load_triangle_surface, which welds coincident vertices and drops zero-area
// triangles: a frame where that changes the topology is reported as such.
//
// Frames may come from a function instead of files (set_frame_source: a body computed by a
// script, the Python module's drive_body): the same interpolation, checks and cache; frame 0's
// file still gives the topology.
//
// Errors (MeshError, naming the file): a missing or unreadable file, a non-finite coordinate, a
// frame whose vertex count or triangles differ from frame 0's. They are thrown by the constructor
// (frame 0, and the frame it starts on) or by move_to when it first needs the bad frame; the body
// then stays where it was.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "invfem/collisions/colliders/animated_mesh_body.hpp"

namespace invfem {

struct BodySequenceSettings {
  std::vector<std::string> files;  // frame k = files[k]; at least one
  double fps = 25;                 // frames per second of the sequence (> 0)
  double start_time = 0;           // [s] simulation time at which frame 0 is shown (may be < 0)
  // Applied to every frame's vertices: x_world = linear * x_file + translation (scale and
  // rotation); velocities transform with `linear` alone.
  Mat3 linear = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  AnimationEnd after_end = AnimationEnd::Hold;
  double friction = 0.3;           // Coulomb coefficient for the collision processing
  MeshSurfaceOptions mesh;         // contact search radius
  std::size_t cache_frames = 3;    // frames kept in memory besides frame 0's topology (>= 2)
};

// The files of a frame pattern: `{N}` is replaced by the frame number, `{N:0W}` (W = 1..9) by the
// number zero-padded to W digits (`frame_{N:04}.ply`: frame_0007.ply). Exactly one placeholder;
// first <= last, both >= 0. Throws std::invalid_argument naming the pattern otherwise.
std::vector<std::string> expand_frame_pattern(const std::string& pattern, int first, int last);

// One frame as read for a sequence (see above: OBJ in file vertex order). Throws MeshError naming
// the file.
TriangleSurface read_sequence_frame(const std::string& path);

class BodySequence final : public AnimatedMeshBody {
 public:
  // Reads frame 0 (topology), checks the settings, and moves the body to t = 0. Throws
  // std::invalid_argument for bad settings and MeshError for a bad frame.
  BodySequence(std::string name, BodySequenceSettings settings);

  int frame_count() const { return static_cast<int>(settings_.files.size()); }
  // Files read so far (frame 0 at construction counts once); a test's measure of the streaming.
  long long frames_loaded() const { return loads_; }
  // Frames currently held in the cache.
  std::size_t frames_cached() const { return cache_.size(); }

  // Frame k's vertices as a file would hold them (#V x 3, before the transform).
  using FrameSource = std::function<Points(int k)>;
  // From now on frames come from `source` (called once per frame the cache lacks; what it throws
  // goes through move_to), checked as a file's frame is (frame 0's vertex count, finite and in
  // range); `what` names the source in errors. The cache is emptied and the body placed again at
  // the time of its last move_to. An empty source returns to the files.
  void set_frame_source(FrameSource source, std::string what);

  // Reads and checks every frame now, one at a time (none is kept; the cache is untouched): a
  // long run's bad frame found before the run. Throws MeshError naming the first bad file.
  void check_frames() const;

  // Which two frames time t interpolates between, and the weight of the second (see the header
  // comment). `moving` is false when the body holds still (before the start, past the end with
  // hold, or a single frame).
  struct Bracket {
    int first = 0, second = 0;
    double weight = 0;
    bool moving = false;
  };
  Bracket bracket(double t) const;

 private:
  // The interpolation at t (loads the frames it needs; MeshError for a bad one).
  void evaluate(double t, Points& x, Points& v) override;
  // Frame k in world coordinates, from the cache or read (and checked) now.
  const Points& frame(int k);
  // Frame k read, checked against frame 0's topology, and transformed.
  Points load(int k) const;
  Points posed(const Points& file_x, const std::string& file) const;

  BodySequenceSettings settings_;
  Tris tris_;  // frame 0's, every frame's
  Eigen::Index vertices_ = 0;
  struct Cached {
    int index;
    Points x;  // world coordinates
    unsigned long long used;
  };
  std::vector<Cached> cache_;
  FrameSource source_;          // set_frame_source; empty: the files
  std::string source_what_;
  unsigned long long clock_ = 0;
  long long loads_ = 0;
};

}  // namespace invfem
