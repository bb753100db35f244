#include "invfem/core/io/usd_writer.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "invfem/core/geometry/surface.hpp"
#include "invfem/core/io/atomic_file.hpp"
#include "output_checks.hpp"

namespace invfem {

namespace {

void append_real(std::string& out, double v) {
  char buf[32];
  const int len = std::snprintf(buf, sizeof buf, "%.9g", v);
  out.append(buf, static_cast<std::size_t>(len));
}

// A coordinate as the file holds it (9 significant digits): what the normals are computed from,
// so that they agree with the points written, and a resumed run rebuilding earlier frames from
// their OBJ files (also 9 digits) writes the same normals.
double as_written(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return std::strtod(buf, nullptr);
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

std::string usda_stage(const std::vector<std::pair<std::string, std::string>>& layers, int first, int last, double fps) {
  if (!(std::isfinite(fps) && fps > 0)) throw std::invalid_argument("usda_stage: fps must be finite and > 0");
  if (last < first) throw std::invalid_argument("usda_stage: last frame before first");
  std::string rate;
  append_real(rate, fps);
  std::string out = "#usda 1.0\n(\n    defaultPrim = \"shot\"\n    endTimeCode = " + std::to_string(last) +
                    "\n    framesPerSecond = " + rate + "\n    metersPerUnit = 1\n    startTimeCode = " +
                    std::to_string(first) + "\n    timeCodesPerSecond = " + rate + "\n    upAxis = \"Y\"\n)\n\n";
  out += "def Xform \"shot\"\n{\n";
  for (const auto& [name, path] : layers)
    out += "    def \"" + usd_identifier(name) + "\" (\n        prepend references = @" + path + "@\n    )\n    {\n    }\n";
  out += "}\n";
  return out;
}

std::map<int, Points> read_usda_velocities(const std::string& path) {
  std::map<int, Points> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line) && line.find("vector3f[] velocities.timeSamples = {") == std::string::npos) {
  }
  while (std::getline(in, line)) {
    const auto colon = line.find(": [");
    if (colon == std::string::npos) break;  // the closing brace
    const int frame = std::atoi(line.c_str());
    std::string numbers = line.substr(colon + 2);
    for (char& c : numbers)
      if (c == '[' || c == ']' || c == '(' || c == ')' || c == ',') c = ' ';
    std::istringstream values(numbers);
    std::vector<double> v;
    for (double d; values >> d;) v.push_back(d);
    if (v.size() % 3) return {};  // not a layer this writer wrote: keep nothing
    Points p(static_cast<Eigen::Index>(v.size() / 3), 3);
    for (std::size_t i = 0; i < v.size(); ++i) p(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) = v[i];
    out[frame] = std::move(p);
  }
  return out;
}

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
    : path_(std::move(path)), prim_(usd_identifier(object_name)), fps_(fps) {
  const std::string who = "UsdaAnimationWriter(" + path_ + ")";
  if (!(std::isfinite(fps) && fps > 0)) throw std::invalid_argument(who + ": fps must be finite and > 0");
  if (tris.rows() == 0) throw std::invalid_argument(who + ": no triangles");
  if (tris.minCoeff() < 0) throw std::invalid_argument(who + ": negative triangle index");
  topology_of(tris);
}

int UsdaAnimationWriter::topology_of(const Tris& tris) {
  for (std::size_t k = 0; k < topologies_.size(); ++k)
    if (topologies_[k].tris.rows() == tris.rows() && topologies_[k].tris == tris) return static_cast<int>(k);
  Topology t;
  t.tris = tris;
  t.counts.reserve(static_cast<std::size_t>(tris.rows()) * 3 + 2);
  t.counts += '[';
  for (Eigen::Index f = 0; f < tris.rows(); ++f) t.counts += f ? ", 3" : "3";
  t.counts += ']';
  t.indices += '[';
  for (Eigen::Index f = 0; f < tris.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      if (f || k) t.indices += ", ";
      t.indices += std::to_string(tris(f, k));
    }
  t.indices += ']';
  topologies_.push_back(std::move(t));
  return static_cast<int>(topologies_.size()) - 1;
}

void UsdaAnimationWriter::set_texture_coordinates(const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>& uv,
                                                  const Tris& uv_tris) {
  const Tris& tris = topologies_.front().tris;
  const std::string who = "UsdaAnimationWriter(" + path_ + ")";
  if (uv_tris.rows() != tris.rows())
    throw std::invalid_argument(who + ": " + std::to_string(uv_tris.rows()) + " uv triangles for " +
                                std::to_string(tris.rows()) + " triangles");
  if (!uv.allFinite()) throw std::invalid_argument(who + ": a non-finite texture coordinate");
  std::string st = "[", indices = "[";
  for (Eigen::Index i = 0; i < uv.rows(); ++i) {
    if (i) st += ", ";
    st += '(';
    append_real(st, uv(i, 0));
    st += ", ";
    append_real(st, uv(i, 1));
    st += ')';
  }
  for (Eigen::Index t = 0; t < uv_tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int j = uv_tris(t, k);
      if (j < 0 || j >= uv.rows())
        throw std::invalid_argument(who + ": triangle " + std::to_string(t) + " uv index " + std::to_string(j) +
                                    " outside [0, " + std::to_string(uv.rows()) + ")");
      if (t || k) indices += ", ";
      indices += std::to_string(j);
    }
  st_ = st + "]";
  st_indices_ = indices + "]";
}

void UsdaAnimationWriter::set_panels(const std::vector<std::string>& names, const std::vector<int>& triangle_group) {
  if (names.empty()) {
    panels_.clear();
    panels_type_.clear();
    return;
  }
  const Tris& tris = topologies_.front().tris;
  if (triangle_group.size() != static_cast<std::size_t>(tris.rows()))
    throw std::invalid_argument("UsdaAnimationWriter(" + path_ + "): " + std::to_string(triangle_group.size()) +
                                " panel entries for " + std::to_string(tris.rows()) + " triangles");
  std::vector<std::vector<int>> faces(names.size());
  std::size_t in_panels = 0;
  for (std::size_t t = 0; t < triangle_group.size(); ++t) {
    const int g = triangle_group[t];
    if (g < 0 || g >= static_cast<int>(names.size()) || names[static_cast<std::size_t>(g)].empty()) continue;
    faces[static_cast<std::size_t>(g)].push_back(static_cast<int>(t));
    ++in_panels;
  }
  std::set<std::string> taken;
  std::string subsets;
  for (std::size_t g = 0; g < names.size(); ++g) {
    if (faces[g].empty()) continue;
    const std::string base = usd_identifier(names[g]);
    std::string id = base;
    for (int k = 2; !taken.insert(id).second; ++k) id = base + "_" + std::to_string(k);
    subsets += "\n        def GeomSubset \"" + id + "\"\n        {\n";
    subsets += "            uniform token elementType = \"face\"\n            uniform token familyName = \"panels\"\n";
    subsets += "            int[] indices = [";
    for (std::size_t i = 0; i < faces[g].size(); ++i) subsets += (i ? ", " : "") + std::to_string(faces[g][i]);
    subsets += "]\n        }\n";
  }
  panels_ = subsets;
  panels_type_ = subsets.empty() ? "" : in_panels == triangle_group.size() ? "partition" : "nonOverlapping";
}

bool UsdaAnimationWriter::topology_varies() const {
  for (const auto& [k, f] : frames_)
    if (f.topology != 0) return true;
  return false;
}

void UsdaAnimationWriter::add_frame(int frame, const Points& x, const Points* velocities) {
  const std::string who = "UsdaAnimationWriter(" + path_ + ") frame " + std::to_string(frame);
  if (num_points_ >= 0 && x.rows() != num_points_)
    throw std::invalid_argument(who + ": " + std::to_string(x.rows()) + " points, the first frame had " +
                                std::to_string(num_points_));
  add(frame, x, 0, velocities);
}

void UsdaAnimationWriter::add_frame(int frame, const Points& x, const Tris& tris, const Points* velocities) {
  const std::string who = "UsdaAnimationWriter(" + path_ + ") frame " + std::to_string(frame);
  if (tris.rows() == 0) throw std::invalid_argument(who + ": no triangles");
  if (frame < 0) throw std::invalid_argument(who + ": negative frame number");
  if (x.rows() == 0) throw std::invalid_argument(who + ": no points");
  detail::check_indices(who, "triangle", tris, x.rows());
  const std::size_t known = topologies_.size();
  const int topology = topology_of(tris);
  try {
    add(frame, x, topology, velocities);
  } catch (...) {
    topologies_.resize(known);
    throw;
  }
}

void UsdaAnimationWriter::add(int frame, const Points& x, int topology, const Points* velocities) {
  const std::string who = "UsdaAnimationWriter(" + path_ + ") frame " + std::to_string(frame);
  if (frame < 0) throw std::invalid_argument(who + ": negative frame number");
  if (x.rows() == 0) throw std::invalid_argument(who + ": no points");
  detail::check_finite_points(who, x);
  const Tris& tris = topologies_[static_cast<std::size_t>(topology)].tris;
  detail::check_indices(who, "triangle", tris, x.rows());
  if (velocities) {
    if (velocities->rows() != x.rows())
      throw std::invalid_argument(who + ": " + std::to_string(velocities->rows()) + " velocities for " +
                                  std::to_string(x.rows()) + " points");
    if (!velocities->allFinite()) throw std::invalid_argument(who + ": a non-finite velocity");
  }

  Frame f;
  f.topology = topology;
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

  // Per-vertex normals: the sum of the triangles' area-weighted normals (of the points as
  // written), normalized.
  const Points written = x.unaryExpr(&as_written);
  Points n = Points::Zero(x.rows(), 3);
  for (Eigen::Index t = 0; t < tris.rows(); ++t) {
    const Vec3 a = triangle_normal(written, tris, t);
    for (int k = 0; k < 3; ++k) n.row(tris(t, k)) += a.transpose();
  }
  auto append_rows = [](std::string& out, const Points& p, bool unit) {
    out.reserve(static_cast<std::size_t>(p.rows()) * 40);
    out += '[';
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      if (i) out += ", ";
      Vec3 r = p.row(i).transpose();
      if (unit) r = r.norm() > 0 ? Vec3(r / r.norm()) : Vec3::Zero();
      append_vec(out, r.x(), r.y(), r.z());
    }
    out += ']';
  };
  append_rows(f.normals, n, true);
  if (velocities) append_rows(f.velocities, *velocities, false);

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
  if (num_points_ < 0) num_points_ = x.rows();
}

std::string UsdaAnimationWriter::render() const {
  const int first = frames_.begin()->first, last = frames_.rbegin()->first;
  std::size_t size = 1024;
  for (const Topology& t : topologies_) size += t.counts.size() + t.indices.size() + 64;
  for (const auto& [k, f] : frames_) size += f.points.size() + f.normals.size() + f.velocities.size() + f.extent.size() + 96;
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
  // The topology: one value; with a topology that varies also its samples where it changes.
  const bool varies = topology_varies();
  const Topology& first_topology = topologies_[static_cast<std::size_t>(frames_.begin()->second.topology)];
  auto samples = [&](const char* name, std::string Topology::*text) {
    out += std::string("        int[] ") + name + ".timeSamples = {\n";
    int previous = -1;
    for (const auto& [k, f] : frames_) {
      if (f.topology == previous) continue;
      previous = f.topology;
      out += "            " + std::to_string(k) + ": " + topologies_[static_cast<std::size_t>(f.topology)].*text + ",\n";
    }
    out += "        }\n";
  };
  out += "        }\n        int[] faceVertexCounts = " + first_topology.counts + "\n";
  if (varies) samples("faceVertexCounts", &Topology::counts);
  out += "        int[] faceVertexIndices = " + first_topology.indices + "\n";
  if (varies) samples("faceVertexIndices", &Topology::indices);
  out += "        uniform token orientation = \"rightHanded\"\n";
  if (!st_.empty() && !varies) {
    out += "        texCoord2f[] primvars:st = " + st_ + " (\n            interpolation = \"faceVarying\"\n        )\n";
    out += "        int[] primvars:st:indices = " + st_indices_ + "\n";
  }
  out += "        normal3f[] normals (\n            interpolation = \"vertex\"\n        )\n";
  out += "        normal3f[] normals.timeSamples = {\n";
  for (const auto& [k, f] : frames_) out += "            " + std::to_string(k) + ": " + f.normals + ",\n";
  out += "        }\n";
  out += "        point3f[] points = " + frames_.begin()->second.points + "\n";
  out += "        point3f[] points.timeSamples = {\n";
  for (const auto& [k, f] : frames_) {
    out += "            " + std::to_string(k) + ": ";
    out += f.points;
    out += ",\n";
  }
  out += "        }\n        uniform token subdivisionScheme = \"none\"\n";
  if (!panels_type_.empty() && !varies)
    out += "        uniform token subsetFamily:panels:familyType = \"" + panels_type_ + "\"\n";
  bool moving = false;
  for (const auto& [k, f] : frames_) moving = moving || !f.velocities.empty();
  if (moving) {
    out += "        vector3f[] velocities.timeSamples = {\n";
    for (const auto& [k, f] : frames_)
      if (!f.velocities.empty()) out += "            " + std::to_string(k) + ": " + f.velocities + ",\n";
    out += "        }\n";
  }
  if (!varies) out += panels_;
  out += "    }\n}\n";
  return out;
}

}  // namespace invfem
