#include "invfem/core/usd_writer.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "invfem/core/atomic_file.hpp"
#include "output_checks.hpp"

namespace invfem {

namespace {

void append_real(std::string& out, double v) {
  char buf[32];
  const int len = std::snprintf(buf, sizeof buf, "%.9g", v);
  out.append(buf, static_cast<std::size_t>(len));
}

void append_vec(std::string& out, double a, double b, double c) {
  out += '(';
  append_real(out, a);
  out += ", ";
  append_real(out, b);
  out += ", ";
  append_real(out, c);
  out += ')';
}

}  // namespace

std::string usd_identifier(const std::string& name) {
  std::string id;
  for (char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    id += ok ? c : '_';
  }
  if (id.empty() || (id[0] >= '0' && id[0] <= '9')) id = "_" + id;
  return id;
}

UsdaAnimationWriter::UsdaAnimationWriter(std::string path, const std::string& object_name, Tris tris,
                                         double fps)
    : path_(std::move(path)), prim_(usd_identifier(object_name)), tris_(std::move(tris)), fps_(fps) {
  const std::string who = "UsdaAnimationWriter(" + path_ + ")";
  if (!(std::isfinite(fps) && fps > 0)) throw std::invalid_argument(who + ": fps must be finite and > 0");
  if (tris_.rows() == 0) throw std::invalid_argument(who + ": no triangles");
  if (tris_.minCoeff() < 0) throw std::invalid_argument(who + ": negative triangle index");
}

void UsdaAnimationWriter::add_frame(int frame, const Points& x) {
  const std::string who = "UsdaAnimationWriter(" + path_ + ") frame " + std::to_string(frame);
  if (frame < 0) throw std::invalid_argument(who + ": negative frame number");
  if (num_points_ >= 0 && x.rows() != num_points_)
    throw std::invalid_argument(who + ": " + std::to_string(x.rows()) + " points, the first frame had " +
                                std::to_string(num_points_));
  if (x.rows() == 0) throw std::invalid_argument(who + ": no points");
  detail::check_finite_points(who, x);
  if (num_points_ < 0) detail::check_indices(who, "triangle", tris_, x.rows());

  Frame f;
  f.points.reserve(static_cast<std::size_t>(x.rows()) * 40);
  f.points += '[';
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (i) f.points += ", ";
    append_vec(f.points, x(i, 0), x(i, 1), x(i, 2));
  }
  f.points += ']';
  const Vec3 lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose();
  f.extent += '[';
  append_vec(f.extent, lo.x(), lo.y(), lo.z());
  f.extent += ", ";
  append_vec(f.extent, hi.x(), hi.y(), hi.z());
  f.extent += ']';

  // Keep the state unchanged if the write fails.
  const auto previous = frames_.find(frame);
  const bool had = previous != frames_.end();
  Frame old = had ? previous->second : Frame{};
  frames_[frame] = std::move(f);
  try {
    atomic_write(path_, render());
  } catch (...) {
    if (had) frames_[frame] = std::move(old);
    else frames_.erase(frame);
    throw;
  }
  num_points_ = x.rows();
}

std::string UsdaAnimationWriter::render() const {
  const int first = frames_.begin()->first, last = frames_.rbegin()->first;
  std::size_t size = 1024 + 16 * static_cast<std::size_t>(tris_.rows());
  for (const auto& [k, f] : frames_) size += f.points.size() + f.extent.size() + 32;
  std::string out;
  out.reserve(size);
  char fps[32];
  std::snprintf(fps, sizeof fps, "%.17g", fps_);
  out += "#usda 1.0\n(\n    defaultPrim = \"" + prim_ + "\"\n    endTimeCode = " + std::to_string(last) +
         "\n    framesPerSecond = " + fps + "\n    metersPerUnit = 1\n    startTimeCode = " +
         std::to_string(first) + "\n    timeCodesPerSecond = " + fps + "\n    upAxis = \"Y\"\n)\n\n";
  out += "def Xform \"" + prim_ + "\"\n{\n    def Mesh \"mesh\"\n    {\n";
  out += "        float3[] extent = " + frames_.begin()->second.extent + "\n";
  out += "        float3[] extent.timeSamples = {\n";
  for (const auto& [k, f] : frames_) out += "            " + std::to_string(k) + ": " + f.extent + ",\n";
  out += "        }\n        int[] faceVertexCounts = [";
  for (Eigen::Index t = 0; t < tris_.rows(); ++t) out += t ? ", 3" : "3";
  out += "]\n        int[] faceVertexIndices = [";
  for (Eigen::Index t = 0; t < tris_.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      if (t || k) out += ", ";
      out += std::to_string(tris_(t, k));
    }
  out += "]\n        uniform token orientation = \"rightHanded\"\n";
  out += "        point3f[] points = " + frames_.begin()->second.points + "\n";
  out += "        point3f[] points.timeSamples = {\n";
  for (const auto& [k, f] : frames_) {
    out += "            " + std::to_string(k) + ": ";
    out += f.points;
    out += ",\n";
  }
  out += "        }\n        uniform token subdivisionScheme = \"none\"\n    }\n}\n";
  return out;
}

}  // namespace invfem
