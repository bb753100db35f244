#include "invfem/collisions/colliders/body_sequence.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/core/io/surface_io.hpp"

namespace invfem {

std::vector<std::string> expand_frame_pattern(const std::string& pattern, int first, int last) {
  const std::string what = "frame pattern \"" + pattern + "\": ";
  const std::size_t open = pattern.find('{');
  if (open == std::string::npos)
    throw std::invalid_argument(what + "no {N} or {N:0W} placeholder for the frame number");
  const std::size_t close = pattern.find('}', open);
  if (close == std::string::npos) throw std::invalid_argument(what + "a '{' without its '}'");
  if (pattern.find_first_of("{}", close + 1) != std::string::npos || pattern.find('}') < open)
    throw std::invalid_argument(what + "more than one placeholder (or a stray brace)");
  const std::string inside = pattern.substr(open + 1, close - open - 1);
  // {N}: no padding; {N:0W}: W digits, 1 to 9 (what a frame number plausibly needs).
  int width = 0;
  const bool padded = inside.size() == 4 && inside.compare(0, 3, "N:0") == 0 && inside[3] >= '1' && inside[3] <= '9';
  if (padded) width = inside[3] - '0';
  else if (inside != "N")
    throw std::invalid_argument(what + "the placeholder must be {N} or {N:0W} with a width W of 1 to 9, not {" +
                                inside + "}");
  if (first < 0 || last < first)
    throw std::invalid_argument(what + "frames first = " + std::to_string(first) + ", last = " + std::to_string(last) +
                                ": need 0 <= first <= last");
  std::vector<std::string> files;
  files.reserve(static_cast<std::size_t>(last - first + 1));
  for (int n = first; n <= last; ++n) {
    std::string number = std::to_string(n);
    if (static_cast<int>(number.size()) < width) number.insert(0, static_cast<std::size_t>(width) - number.size(), '0');
    files.push_back(pattern.substr(0, open) + number + pattern.substr(close + 1));
  }
  return files;
}

TriangleSurface read_sequence_frame(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".obj") return read_obj_surface(path);  // file vertex order; ObjError is a MeshError
  try {
    return load_triangle_surface(path);
  } catch (const MeshError&) {
    throw;
  } catch (const std::exception& e) {  // the loader's messages name the file
    throw MeshError(e.what());
  }
}

BodySequence::BodySequence(std::string name, BodySequenceSettings settings)
    : AnimatedMeshBody(name, settings.friction, settings.mesh, "body sequence \"" + name + "\": "),
      settings_(std::move(settings)) {
  const std::string what = "body sequence \"" + this->name() + "\": ";
  if (settings_.files.empty()) throw std::invalid_argument(what + "no frames");
  if (!std::isfinite(settings_.fps) || !(settings_.fps > 0)) throw std::invalid_argument(what + "fps must be > 0");
  if (!std::isfinite(settings_.start_time)) throw std::invalid_argument(what + "start_time must be finite");
  if (!settings_.linear.allFinite() || !settings_.translation.allFinite() || !(std::abs(settings_.linear.determinant()) > 0))
    throw std::invalid_argument(what + "the transform must be finite and invertible");
  if (settings_.cache_frames < 2) throw std::invalid_argument(what + "cache_frames must be >= 2");
  cache_.reserve(settings_.cache_frames);

  const TriangleSurface first = read_sequence_frame(settings_.files[0]);
  tris_ = first.tris;
  vertices_ = first.x.rows();
  cache_.push_back({0, posed(first.x, settings_.files[0]), ++clock_});
  loads_ = 1;
  TriangleSurface shape;
  shape.tris = tris_;
  shape.x = cache_.back().x;
  set_surface(std::move(shape));
}

BodySequence::Bracket BodySequence::bracket(double t) const {
  const int n = frame_count();
  double s = (t - settings_.start_time) * settings_.fps;
  // A frame time computed in floating point (start + k / fps) lands on k, not a hair before it.
  const double nearest = std::round(s);
  if (std::abs(s - nearest) <= 1e-9 * std::max(1.0, std::abs(s))) s = nearest;
  if (n == 1 || s < 0) return {0, 0, 0, false};
  if (settings_.after_end == AnimationEnd::Hold) {
    if (s >= n - 1) return {n - 1, n - 1, 0, false};
    const int k = static_cast<int>(std::floor(s));
    return {k, k + 1, s - k, true};
  }
  s = std::fmod(s, static_cast<double>(n));  // loop: period n frames, the last interval wraps to frame 0
  int k = static_cast<int>(std::floor(s));
  if (k >= n) k = n - 1;
  return {k, (k + 1) % n, std::clamp(s - k, 0.0, 1.0), true};
}

Points BodySequence::posed(const Points& file_x, const std::string& file) const {
  Points x(file_x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    x.row(i) = (settings_.linear * file_x.row(i).transpose() + settings_.translation).transpose();
  check_positions(x, file);
  return x;
}

void BodySequence::set_frame_source(FrameSource source, std::string what) {
  source_ = std::move(source);
  source_what_ = std::move(what);
  cache_.clear();
  replace_animation();
}

Points BodySequence::load(int k) const {
  if (source_) {
    const std::string where = source_what_ + ", frame " + std::to_string(k);
    const Points x = source_(k);
    if (x.rows() != vertices_)
      throw MeshError(where + ": " + std::to_string(x.rows()) + " vertices, but frame 0 (" + settings_.files[0] +
                      ") has " + std::to_string(vertices_) + "; every frame of body sequence \"" + name() +
                      "\" must have frame 0's vertices");
    return posed(x, where);
  }
  const std::string& file = settings_.files[static_cast<std::size_t>(k)];
  const TriangleSurface f = read_sequence_frame(file);
  const std::string body = "; every frame of body sequence \"" + name() + "\" must have frame 0's vertices and triangles";
  if (f.x.rows() != vertices_)
    throw MeshError(file + ": " + std::to_string(f.x.rows()) + " vertices, but frame 0 (" + settings_.files[0] +
                    ") has " + std::to_string(vertices_) + body);
  if (f.tris.rows() != tris_.rows() || f.tris != tris_) {
    std::string detail = std::to_string(f.tris.rows()) + " triangles, frame 0 has " + std::to_string(tris_.rows());
    if (f.tris.rows() == tris_.rows())
      for (Eigen::Index i = 0; i < tris_.rows(); ++i)
        if (f.tris.row(i) != tris_.row(i)) {
          detail = "triangle " + std::to_string(i) + " is (" + std::to_string(f.tris(i, 0)) + ", " +
                   std::to_string(f.tris(i, 1)) + ", " + std::to_string(f.tris(i, 2)) + "), frame 0's is (" +
                   std::to_string(tris_(i, 0)) + ", " + std::to_string(tris_(i, 1)) + ", " +
                   std::to_string(tris_(i, 2)) + ")";
          break;
        }
    const bool obj = std::filesystem::path(file).extension() == ".obj";
    throw MeshError(file + ": other triangles than frame 0 (" + settings_.files[0] + "): " + detail + body +
                    (obj ? "" : " (formats other than OBJ are read through assimp, which welds coincident vertices "
                                "and drops zero-area triangles)"));
  }
  return posed(f.x, file);
}

void BodySequence::check_frames() const {
  if (source_) return;  // a function's frames are checked as they come
  for (int k = 1; k < frame_count(); ++k) (void)load(k);
}

const Points& BodySequence::frame(int k) {
  for (Cached& c : cache_)
    if (c.index == k) {
      c.used = ++clock_;
      return c.x;
    }
  Points x = load(k);
  ++loads_;
  if (cache_.size() < settings_.cache_frames) {
    cache_.push_back({k, std::move(x), ++clock_});
    return cache_.back().x;
  }
  auto oldest =
      std::min_element(cache_.begin(), cache_.end(), [](const Cached& a, const Cached& b) { return a.used < b.used; });
  *oldest = {k, std::move(x), ++clock_};
  return oldest->x;
}

void BodySequence::evaluate(double t, Points& x, Points& v) {
  const Bracket b = bracket(t);
  // Copies: reading the second frame may evict the cache entry of the first.
  const Points a = frame(b.first);
  if (b.moving) {
    const Points& c = frame(b.second);
    x = (1 - b.weight) * a + b.weight * c;
    v = (c - a) * settings_.fps;
  } else {
    x = a;
    v = Points::Zero(a.rows(), 3);
  }
}

}  // namespace invfem
