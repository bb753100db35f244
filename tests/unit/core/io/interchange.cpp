// Interchange writers: binary/ASCII PLY (read back through assimp), the ParaView .pvd (checked
// with a strict XML parser of our own), USD ASCII animation (structural check of our own). The
// binary .vtu frames have their own decoder (vtu_writer.cpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "invfem/core/io/obj_file.hpp"
#include "invfem/core/io/obj_writer.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/shells/shapes.hpp"
#include "invfem/core/io/ply_writer.hpp"
#include "invfem/core/io/usd_writer.hpp"
#include "invfem/core/io/vtu_writer.hpp"
#include "xml_check.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace invfem;
using invfem::test::XmlNode;
using invfem::test::XmlParser;

namespace {

using test::TempDir;
using test::slurp;

// A curved sheet: a grid whose nodes are lifted by a smooth bump, so no coordinate is trivial.
TriangleSurface curved_sheet(int nx, int ny) {
  TriangleSurface m = make_grid(1.3, 0.7, nx, ny, Vec3(-0.4, 0.2, 0.1));
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) m.x(i, 2) += 0.1 * std::sin(3 * m.x(i, 0)) * std::cos(2 * m.x(i, 1));
  return m;
}

std::vector<double> numbers(const std::string& text) {
  std::vector<double> v;
  std::istringstream in(text);
  std::string tok;
  while (in >> tok) {
    char* end = nullptr;
    const double d = std::strtod(tok.c_str(), &end);
    if (end != tok.c_str() + tok.size()) throw std::runtime_error("not a number: " + tok);
    v.push_back(d);
  }
  return v;
}

// Loads `path` through assimp and checks it holds exactly the sheet `m`, positions to float
// precision. The loader reorders vertices (first use), so match them by position.
void expect_same_surface(const std::string& path, const TriangleSurface& m) {
  SurfaceLoadReport report;
  const TriangleSurface back = load_triangle_surface(path, &report);
  ASSERT_EQ(back.x.rows(), m.x.rows());
  ASSERT_EQ(back.tris.rows(), m.tris.rows());
  EXPECT_EQ(report.removed_triangles, 0);
  std::vector<int> to_original(back.x.rows(), -1);
  std::set<int> used;
  for (Eigen::Index i = 0; i < back.x.rows(); ++i) {
    Eigen::Index best = 0;
    const double d = (m.x.rowwise() - back.x.row(i)).rowwise().norm().minCoeff(&best);
    EXPECT_LT(d, 1e-6) << "vertex " << i;  // assimp keeps float positions
    to_original[i] = static_cast<int>(best);
    used.insert(static_cast<int>(best));
  }
  EXPECT_EQ(used.size(), static_cast<std::size_t>(m.x.rows()));
  // Same triangles with the same winding: compare rotations to the smallest index first.
  auto canon = [](int a, int b, int c) {
    if (b < a && b < c) return std::array<int, 3>{b, c, a};
    if (c < a && c < b) return std::array<int, 3>{c, a, b};
    return std::array<int, 3>{a, b, c};
  };
  std::set<std::array<int, 3>> want, got;
  for (Eigen::Index t = 0; t < m.tris.rows(); ++t) want.insert(canon(m.tris(t, 0), m.tris(t, 1), m.tris(t, 2)));
  for (Eigen::Index t = 0; t < back.tris.rows(); ++t)
    got.insert(canon(to_original[back.tris(t, 0)], to_original[back.tris(t, 1)], to_original[back.tris(t, 2)]));
  EXPECT_EQ(got, want);
}

}  // namespace

// ---------------------------------------------------------------------------------------- PLY

TEST(PlyWriter, BinaryRoundTripThroughAssimp) {
  TempDir dir;
  const TriangleSurface m = curved_sheet(7, 5);
  const std::string p = dir.path("sheet.ply");
  write_ply(p, m.x, m.tris);
  expect_same_surface(p, m);
}

TEST(PlyWriter, AsciiRoundTripThroughAssimp) {
  TempDir dir;
  const TriangleSurface m = curved_sheet(4, 6);
  const std::string p = dir.path("sheet.ply");
  write_ply(p, m.x, m.tris, PlyEncoding::ascii);
  expect_same_surface(p, m);
  // ASCII uses 17 digits: the doubles come back exactly when parsed directly.
  const std::string text = slurp(p);
  const std::size_t body = text.find("end_header\n") + 11;
  const std::vector<double> v = numbers(text.substr(body));
  ASSERT_EQ(v.size(), static_cast<std::size_t>(3 * m.x.rows() + 4 * m.tris.rows()));
  for (Eigen::Index i = 0; i < 3 * m.x.rows(); ++i) EXPECT_EQ(v[i], m.x.data()[i]);
}

TEST(PlyWriter, BinaryLayoutIsExactLittleEndian) {
  TempDir dir;
  const TriangleSurface m = curved_sheet(3, 2);
  const std::string p = dir.path("sheet.ply");
  write_ply(p, m.x, m.tris);
  const std::string bytes = slurp(p);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by invfem\nelement vertex " +
      std::to_string(m.x.rows()) + "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
      std::to_string(m.tris.rows()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  ASSERT_EQ(bytes.size(), header.size() + 24 * m.x.rows() + 13 * m.tris.rows());
  auto le = [&](std::size_t at, int size) {
    std::uint64_t u = 0;
    for (int b = size - 1; b >= 0; --b) u = (u << 8) | static_cast<unsigned char>(bytes[at + b]);
    return u;
  };
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t u = le(header.size() + 24 * i + 8 * k, 8);
      double d;
      std::memcpy(&d, &u, 8);
      EXPECT_EQ(d, m.x(i, k));
    }
  const std::size_t faces = header.size() + 24 * m.x.rows();
  for (Eigen::Index t = 0; t < m.tris.rows(); ++t) {
    EXPECT_EQ(le(faces + 13 * t, 1), 3u);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(static_cast<std::int32_t>(le(faces + 13 * t + 1 + 4 * k, 4)), m.tris(t, k));
  }
}

// Per-vertex texture coordinates (a garment with one vt per vertex) follow z as s and t; a
// per-corner layout with a seam vertex gives no per-vertex uv, and the file none.
TEST(PlyWriter, TextureCoordinatesPerVertexAreSAndT) {
  TempDir dir;
  TriangleSurface m = curved_sheet(3, 2);
  m.uv.resize(m.x.rows(), 2);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) m.uv.row(i) << 0.5 * static_cast<double>(i), 0.25;
  m.uv_tris = m.tris;
  const auto uv = per_vertex_uv(m);
  ASSERT_EQ(uv.rows(), m.x.rows());
  const std::string p = dir.path("uv.ply");
  write_ply(p, m.x, m.tris, PlyEncoding::ascii, &uv);
  std::istringstream in(slurp(p));
  std::string line;
  std::vector<std::string> header;
  while (std::getline(in, line) && line != "end_header") header.push_back(line);
  EXPECT_NE(std::find(header.begin(), header.end(), "property double s"), header.end());
  EXPECT_NE(std::find(header.begin(), header.end(), "property double t"), header.end());
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    double v[5];
    in >> v[0] >> v[1] >> v[2] >> v[3] >> v[4];
    for (int k = 0; k < 3; ++k) EXPECT_EQ(v[k], m.x(i, k));
    EXPECT_EQ(v[3], uv(i, 0));
    EXPECT_EQ(v[4], uv(i, 1));
  }
  // A vertex of two triangles given another uv in one of them: two uv on one vertex.
  std::vector<int> uses(static_cast<std::size_t>(m.x.rows()), 0);
  for (Eigen::Index t = 0; t < m.tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) ++uses[static_cast<std::size_t>(m.tris(t, k))];
  int corner = 0;
  while (uses[static_cast<std::size_t>(m.tris(0, corner))] < 2) ++corner;
  m.uv_tris(0, corner) = (m.uv_tris(0, corner) + 1) % static_cast<int>(m.uv.rows());
  EXPECT_EQ(per_vertex_uv(m).rows(), 0);
}

TEST(PlyWriter, RejectsBadInputWithoutTouchingTheFile) {
  TempDir dir;
  TriangleSurface m = curved_sheet(2, 2);
  const std::string p = dir.path("sheet.ply");
  write_ply(p, m.x, m.tris);
  const std::string before = slurp(p);
  Points bad = m.x;
  bad(3, 1) = std::nan("");
  try {
    write_ply(p, bad, m.tris);
    FAIL() << "NaN accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
  Tris t = m.tris;
  t(1, 2) = static_cast<int>(m.x.rows());
  EXPECT_THROW(write_ply(p, m.x, t, PlyEncoding::ascii), std::invalid_argument);
  EXPECT_EQ(slurp(p), before);
  EXPECT_THROW(write_ply(dir.path("missing/dir/x.ply"), m.x, m.tris), std::runtime_error);
}

// ---------------------------------------------------------------------------------------- PVD

TEST(PvdWriter, XmlCheckerRejectsMalformedDocuments) {
  // The checker above must be able to fail: each of these is broken in one way.
  for (const char* bad : {"<a><b></a>", "<a x=\"1\" x=\"2\"/>", "<a>&bogus;</a>", "<a x=\"<\"/>",
                          "<a></a><b/>", "<a>", "<a x=1/>"})
    EXPECT_THROW(XmlParser(bad).document(), std::runtime_error) << bad;
  EXPECT_NO_THROW(XmlParser("<?xml version=\"1.0\"?>\n<a q=\"&amp;\"><b/>t</a>\n").document());
}

TEST(PvdWriter, RewritesTheWholeCollectionOnEveryAdd) {
  TempDir dir;
  PvdWriter pvd(dir.path("run.pvd"));
  const std::vector<std::pair<double, std::string>> frames = {
      {0.0, "frames/a&b/0000.vtu"}, {1.0 / 30, "frames/a&b/0001.vtu"}, {2.0 / 30, "frames/a&b/0002.vtu"}};
  for (std::size_t k = 0; k < frames.size(); ++k) {
    pvd.add(frames[k].first, frames[k].second);
    const XmlNode root = XmlParser(slurp(pvd.path())).document();
    EXPECT_EQ(root.attr("type"), "Collection");
    const auto sets = root.one("Collection").all("DataSet");
    ASSERT_EQ(sets.size(), k + 1);
    for (std::size_t i = 0; i <= k; ++i) {
      EXPECT_EQ(std::strtod(sets[i]->attr("timestep").c_str(), nullptr), frames[i].first);
      EXPECT_EQ(sets[i]->attr("file"), frames[i].second);
    }
  }
  const std::string before = slurp(pvd.path());
  EXPECT_THROW(pvd.add(0.01, "late.vtu"), std::invalid_argument);
  EXPECT_THROW(pvd.add(NAN, "nan.vtu"), std::invalid_argument);
  EXPECT_EQ(pvd.size(), 3u);
  EXPECT_EQ(slurp(pvd.path()), before);
}

// ---------------------------------------------------------------------------------------- USD

namespace {

struct UsdaSummary {
  std::map<std::string, std::string> layer;  // layer metadata, values unquoted
  std::vector<double> counts, indices, points, extent;
  std::map<int, std::vector<double>> point_samples, extent_samples;
  std::map<int, std::vector<double>> count_samples, index_samples;  // a topology that varies
  std::map<int, std::vector<double>> normal_samples, velocity_samples;
  bool normals_per_vertex = false;  // normals declared with interpolation = "vertex"
};

// Numbers in "[(a, b, c), ...]" or "[1, 2, ...]": strips brackets, parens and commas, and
// parses every remaining token strictly.
std::vector<double> usda_numbers(std::string s) {
  for (char& c : s)
    if (c == '[' || c == ']' || c == '(' || c == ')' || c == ',') c = ' ';
  return numbers(s);
}

// The structural checks: header line, balanced (), [], {} outside strings, then the attribute
// lines this writer emits. Throws std::runtime_error on anything unexpected.
UsdaSummary check_usda(const std::string& text) {
  if (text.rfind("#usda 1.0\n", 0) != 0) throw std::runtime_error("no #usda 1.0 header");
  std::vector<char> stack;
  bool in_string = false;
  for (char c : text) {
    if (c == '"') in_string = !in_string;
    if (in_string) continue;
    if (c == '(' || c == '[' || c == '{') stack.push_back(c);
    if (c == ')' || c == ']' || c == '}') {
      const char open = c == ')' ? '(' : c == ']' ? '[' : '{';
      if (stack.empty() || stack.back() != open) throw std::runtime_error(std::string("unbalanced ") + c);
      stack.pop_back();
    }
  }
  if (!stack.empty() || in_string) throw std::runtime_error("unclosed bracket or string");

  UsdaSummary s;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::getline(in, line);
  if (line != "(") throw std::runtime_error("no layer metadata block");
  while (std::getline(in, line) && line != ")") {
    const auto eq = line.find(" = ");
    if (eq == std::string::npos) throw std::runtime_error("bad metadata line: " + line);
    std::string key = line.substr(0, eq), value = line.substr(eq + 3);
    key.erase(0, key.find_first_not_of(' '));
    if (!value.empty() && value.front() == '"') value = value.substr(1, value.size() - 2);
    s.layer[key] = value;
  }
  auto value_of = [](const std::string& l) { return l.substr(l.find(" = ") + 3); };
  auto sample = [&](std::map<int, std::vector<double>>& into) {
    while (std::getline(in, line)) {
      const auto first = line.find_first_not_of(' ');
      if (line.substr(first) == "}") return;
      const auto colon = line.find(": ");
      if (colon == std::string::npos || line.back() != ',') throw std::runtime_error("bad sample: " + line);
      const int frame = std::stoi(line.substr(first, colon - first));
      into[frame] = usda_numbers(line.substr(colon + 2, line.size() - colon - 3));
    }
    throw std::runtime_error("unterminated timeSamples");
  };
  while (std::getline(in, line)) {
    if (line.find("int[] faceVertexCounts = ") != std::string::npos) s.counts = usda_numbers(value_of(line));
    else if (line.find("int[] faceVertexIndices = ") != std::string::npos) s.indices = usda_numbers(value_of(line));
    else if (line.find("point3f[] points = ") != std::string::npos) s.points = usda_numbers(value_of(line));
    else if (line.find("float3[] extent = ") != std::string::npos) s.extent = usda_numbers(value_of(line));
    else if (line.find("point3f[] points.timeSamples = {") != std::string::npos) sample(s.point_samples);
    else if (line.find("float3[] extent.timeSamples = {") != std::string::npos) sample(s.extent_samples);
    else if (line.find("int[] faceVertexCounts.timeSamples = {") != std::string::npos) sample(s.count_samples);
    else if (line.find("int[] faceVertexIndices.timeSamples = {") != std::string::npos) sample(s.index_samples);
    else if (line.find("normal3f[] normals.timeSamples = {") != std::string::npos) sample(s.normal_samples);
    else if (line.find("vector3f[] velocities.timeSamples = {") != std::string::npos) sample(s.velocity_samples);
    else if (line.find("normal3f[] normals (") != std::string::npos) {
      std::getline(in, line);
      s.normals_per_vertex = line.find("interpolation = \"vertex\"") != std::string::npos;
    }
  }
  return s;
}

// The GeomSubsets of a layer: name -> (elementType, familyName, indices), in file order.
struct UsdaSubset {
  std::string name, element_type, family;
  std::vector<double> indices;
};
std::vector<UsdaSubset> usda_subsets(const std::string& text) {
  std::vector<UsdaSubset> out;
  std::istringstream in(text);
  auto quoted = [](const std::string& l) {
    const auto a = l.find('"'), b = l.rfind('"');
    return l.substr(a + 1, b - a - 1);
  };
  for (std::string line; std::getline(in, line);) {
    if (line.find("def GeomSubset \"") == std::string::npos) continue;
    UsdaSubset s;
    s.name = quoted(line);
    while (std::getline(in, line) && line.find('}') == std::string::npos) {
      if (line.find("uniform token elementType = ") != std::string::npos) s.element_type = quoted(line);
      else if (line.find("uniform token familyName = ") != std::string::npos) s.family = quoted(line);
      else if (line.find("int[] indices = ") != std::string::npos)
        s.indices = usda_numbers(line.substr(line.find(" = ") + 3));
    }
    out.push_back(s);
  }
  return out;
}

// The value of `uniform token subsetFamily:panels:familyType`, "" when absent.
std::string panels_family_type(const std::string& text) {
  const std::string key = "uniform token subsetFamily:panels:familyType = \"";
  const auto at = text.find(key);
  return at == std::string::npos ? "" : text.substr(at + key.size(), text.find('"', at + key.size()) - at - key.size());
}

Points wobble(const Points& X, int frame) {
  Points x = X;
  for (Eigen::Index i = 0; i < x.rows(); ++i) x(i, 1) += 0.05 * frame * std::sin(x(i, 0) + frame);
  return x;
}

}  // namespace

TEST(UsdaWriter, EveryIntermediateFileIsStructurallyValid) {
  TempDir dir;
  const TriangleSurface m = curved_sheet(5, 4);
  const Eigen::Index n = m.x.rows(), nt = m.tris.rows();
  const std::string p = dir.path("cloth.usda");
  UsdaAnimationWriter usd(p, "9 cape-left", m.tris, 24);
  EXPECT_EQ(usd.prim_name(), "_9_cape_left");
  const int frames = 5;
  for (int f = 0; f < frames; ++f) {
    usd.add_frame(f, wobble(m.x, f));
    // What a killed run would leave behind: a complete file with frames 0..f.
    const UsdaSummary s = check_usda(slurp(p));
    EXPECT_EQ(s.layer.at("upAxis"), "Y");
    EXPECT_EQ(s.layer.at("metersPerUnit"), "1");
    EXPECT_EQ(s.layer.at("timeCodesPerSecond"), "24");
    EXPECT_EQ(s.layer.at("defaultPrim"), "_9_cape_left");
    EXPECT_EQ(s.layer.at("startTimeCode"), "0");
    EXPECT_EQ(s.layer.at("endTimeCode"), std::to_string(f));
    ASSERT_EQ(s.counts.size(), static_cast<std::size_t>(nt));
    for (double c : s.counts) EXPECT_EQ(c, 3);
    ASSERT_EQ(s.indices.size(), static_cast<std::size_t>(3 * nt));
    for (Eigen::Index i = 0; i < 3 * nt; ++i) EXPECT_EQ(s.indices[i], m.tris.data()[i]);
    ASSERT_EQ(s.points.size(), static_cast<std::size_t>(3 * n));
    ASSERT_EQ(s.point_samples.size(), static_cast<std::size_t>(f + 1));
    ASSERT_EQ(s.extent_samples.size(), static_cast<std::size_t>(f + 1));
    for (const auto& [k, v] : s.point_samples) {
      ASSERT_EQ(v.size(), static_cast<std::size_t>(3 * n)) << "frame " << k;
      const Points want = wobble(m.x, k);
      for (Eigen::Index i = 0; i < 3 * n; ++i) EXPECT_NEAR(v[i], want.data()[i], 1e-8) << "frame " << k;
      const auto& e = s.extent_samples.at(k);
      ASSERT_EQ(e.size(), 6u);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(e[c], want.col(c).minCoeff(), 1e-8);
        EXPECT_NEAR(e[3 + c], want.col(c).maxCoeff(), 1e-8);
      }
    }
    EXPECT_EQ(s.points, s.point_samples.at(0));
    EXPECT_EQ(s.extent, s.extent_samples.at(0));
  }
  EXPECT_EQ(usd.num_frames(), static_cast<std::size_t>(frames));
  // Optional: the real USD parser, when it is installed (it is not by default).
  if (std::system("command -v usdcat > /dev/null 2>&1") == 0) {
    EXPECT_EQ(std::system(("usdcat '" + p + "' > /dev/null").c_str()), 0);
  }
}

// Normals per vertex, every frame: unit, the area-weighted mean of the triangles' normals (on a
// sheet in the x-z plane wound counter-clockwise from +y, +y); velocities for the frames given
// them, as given.
TEST(UsdaWriter, NormalsAndVelocitiesAreTimeSampledPerVertex) {
  TempDir dir;
  const TriangleSurface m = curved_sheet(5, 4);
  const std::string p = dir.path("cloth.usda");
  UsdaAnimationWriter usd(p, "cloth", m.tris, 25);
  Points v = Points::Random(m.x.rows(), 3);
  usd.add_frame(0, m.x);  // no velocities (a resumed run's earlier frames)
  usd.add_frame(1, wobble(m.x, 1), &v);
  const UsdaSummary s = check_usda(slurp(p));
  EXPECT_TRUE(s.normals_per_vertex);
  ASSERT_EQ(s.normal_samples.size(), 2u);
  for (const auto& [f, n] : s.normal_samples) {
    const Points x = wobble(m.x, f);
    ASSERT_EQ(n.size(), static_cast<std::size_t>(3 * x.rows()));
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      Vec3 want = Vec3::Zero();
      for (Eigen::Index t = 0; t < m.tris.rows(); ++t)
        for (int k = 0; k < 3; ++k)
          if (m.tris(t, k) == i) want += triangle_normal(x, m.tris, t);
      want.normalize();
      const Vec3 got(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
      EXPECT_LT((got - want).norm(), 1e-7) << "frame " << f << ", vertex " << i;
    }
  }
  ASSERT_EQ(s.velocity_samples.size(), 1u);
  const auto& w = s.velocity_samples.at(1);
  ASSERT_EQ(w.size(), static_cast<std::size_t>(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i) EXPECT_NEAR(w[i], v.data()[i], 1e-8);
  Points short_v = Points::Zero(2, 3);
  EXPECT_THROW(usd.add_frame(2, m.x, &short_v), std::invalid_argument);
  v(0, 0) = std::nan("");
  EXPECT_THROW(usd.add_frame(2, m.x, &v), std::invalid_argument);
}

// A garment's texture coordinates reach the layer as the indexed face-varying primvar st: one
// index per face corner, into the uv list as the surface holds them.
TEST(UsdaWriter, TextureCoordinatesAreAFaceVaryingPrimvar) {
  TempDir dir;
  const TriangleSurface m = curved_sheet(3, 2);
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> uv(m.x.rows(), 2);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) uv.row(i) << 0.25 * static_cast<double>(i), 1.0 - 0.125 * static_cast<double>(i);
  const std::string p = dir.path("dress.usda");
  UsdaAnimationWriter usd(p, "dress", m.tris, 25);
  usd.set_texture_coordinates(uv, m.tris);  // one uv per vertex: the corners index it as the faces do
  usd.add_frame(0, m.x);
  const std::string text = slurp(p);
  ASSERT_NO_THROW(check_usda(text));
  std::string st, indices;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.find("texCoord2f[] primvars:st = ") != std::string::npos) st = line.substr(line.find(" = ") + 3);
    if (line.find("int[] primvars:st:indices = ") != std::string::npos) indices = line.substr(line.find(" = ") + 3);
  }
  EXPECT_NE(text.find("interpolation = \"faceVarying\""), std::string::npos);
  const std::vector<double> values = usda_numbers(st.substr(0, st.rfind(" (")));
  ASSERT_EQ(values.size(), static_cast<std::size_t>(2 * uv.rows()));
  for (Eigen::Index i = 0; i < uv.rows(); ++i) {
    EXPECT_EQ(values[static_cast<std::size_t>(2 * i)], uv(i, 0));
    EXPECT_EQ(values[static_cast<std::size_t>(2 * i + 1)], uv(i, 1));
  }
  const std::vector<double> corners = usda_numbers(indices);
  ASSERT_EQ(corners.size(), static_cast<std::size_t>(3 * m.tris.rows()));
  for (Eigen::Index t = 0; t < m.tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(corners[static_cast<std::size_t>(3 * t + k)], m.tris(t, k));
  EXPECT_THROW(usd.set_texture_coordinates(uv, Tris(1, 3)), std::invalid_argument);
}

// A garment's panels reach the layer as GeomSubsets of its mesh, each with the faces the OBJ
// writer groups under that panel's `g` (read back by the OBJ reader).
TEST(UsdaWriter, PanelsAreGeomSubsetsWithTheObjGroupsFaces) {
  TempDir dir;
  TriangleSurface m = curved_sheet(4, 3);
  // Runs of panels that come back ("back-left" and "back_left" share an identifier), and a panel
  // with no triangles.
  m.groups = {"front", "back-left", "back_left", "sleeve"};
  for (Eigen::Index t = 0; t < m.tris.rows(); ++t) m.triangle_group.push_back(t % 3 == 0 ? 0 : t < 12 ? 1 : 2);
  write_obj(dir.path("poncho.obj"), m);
  const ObjFile obj = read_obj_file(dir.path("poncho.obj"));
  std::map<std::string, std::vector<double>> obj_groups;
  for (std::size_t f = 0; f < obj.face_group.size(); ++f)
    obj_groups[obj.groups[obj.face_group[f]]].push_back(static_cast<double>(f));
  ASSERT_EQ(obj_groups.size(), 3u);

  const std::string p = dir.path("poncho.usda");
  UsdaAnimationWriter usd(p, "poncho", m.tris, 25);
  usd.set_panels(m.groups, m.triangle_group);
  usd.add_frame(0, m.x);
  usd.add_frame(1, wobble(m.x, 1));
  const std::string text = slurp(p);
  ASSERT_NO_THROW(check_usda(text));
  const std::vector<UsdaSubset> subsets = usda_subsets(text);
  const std::vector<std::pair<std::string, std::string>> names = {
      {"front", "front"}, {"back_left", "back-left"}, {"back_left_2", "back_left"}};
  ASSERT_EQ(subsets.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    EXPECT_EQ(subsets[k].name, names[k].first);
    EXPECT_EQ(subsets[k].element_type, "face");
    EXPECT_EQ(subsets[k].family, "panels");
    EXPECT_EQ(subsets[k].indices, obj_groups.at(names[k].second)) << names[k].second;
  }
  EXPECT_EQ(panels_family_type(text), "partition");
  // The subsets are the mesh's children: after its attributes, before it closes.
  EXPECT_LT(text.find("uniform token subsetFamily:panels:familyType"), text.find("def GeomSubset"));
  EXPECT_GT(text.find("def GeomSubset"), text.find("def Mesh \"mesh\""));
  EXPECT_EQ(text.substr(text.size() - 18), "        }\n    }\n}\n");
  if (std::system("command -v usdcat > /dev/null 2>&1") == 0) {
    EXPECT_EQ(std::system(("usdcat '" + p + "' > /dev/null").c_str()), 0);
  }

  // Triangles in no panel (an index outside the names, an unnamed panel): the family no longer
  // covers every face.
  std::vector<std::string> some = m.groups;
  some.push_back("");
  std::vector<int> partial = m.triangle_group;
  partial[1] = -1;
  partial[2] = 4;
  usd.set_panels(some, partial);
  usd.add_frame(1, wobble(m.x, 1));
  const std::string gaps = slurp(p);
  EXPECT_EQ(panels_family_type(gaps), "nonOverlapping");
  std::set<double> covered;
  for (const UsdaSubset& s : usda_subsets(gaps)) covered.insert(s.indices.begin(), s.indices.end());
  EXPECT_EQ(covered.size(), static_cast<std::size_t>(m.tris.rows()) - 2);
  EXPECT_EQ(covered.count(1.0) + covered.count(2.0), 0u);

  // A topology that changes: the panels index faces that are gone, so they are not written.
  const TriangleSurface b = curved_sheet(5, 4);
  usd.add_frame(2, b.x, b.tris);
  const std::string cut = slurp(p);
  EXPECT_TRUE(usda_subsets(cut).empty());
  EXPECT_EQ(panels_family_type(cut), "");

  EXPECT_THROW(usd.set_panels(m.groups, std::vector<int>(3, 0)), std::invalid_argument);
  UsdaAnimationWriter plain(dir.path("plain.usda"), "plain", m.tris, 25);
  plain.set_panels({}, m.triangle_group);  // no names: no panels, as the OBJ writer writes no `g`
  plain.add_frame(0, m.x);
  EXPECT_EQ(slurp(dir.path("plain.usda")).find("GeomSubset"), std::string::npos);
}

TEST(UsdaWriter, ATopologyThatChangesIsTimeSampledWhereItChanges) {
  // A fracturing solid's frames: two frames of one topology, then three of another with more
  // points and triangles (frame 3 repeats frame 2's, so it adds no topology sample).
  TempDir dir;
  const TriangleSurface a = curved_sheet(3, 2), b = curved_sheet(5, 4);
  const std::string p = dir.path("slab.usda"), q = dir.path("same.usda");
  UsdaAnimationWriter usd(p, "slab", a.tris, 30), fixed(q, "slab", a.tris, 30);
  for (int f = 0; f < 2; ++f) {
    usd.add_frame(f, wobble(a.x, f), a.tris);
    fixed.add_frame(f, wobble(a.x, f));
  }
  // While the topology is the first one, the file is the fixed-topology one, byte for byte.
  EXPECT_FALSE(usd.topology_varies());
  EXPECT_EQ(slurp(p), slurp(q));
  EXPECT_EQ(check_usda(slurp(p)).count_samples.size(), 0u);
  for (int f = 2; f < 5; ++f) usd.add_frame(f, wobble(b.x, f), b.tris);
  EXPECT_TRUE(usd.topology_varies());
  const UsdaSummary s = check_usda(slurp(p));
  // The default value is the first frame's topology; samples at frame 0 and where it changed.
  EXPECT_EQ(s.counts.size(), static_cast<std::size_t>(a.tris.rows()));
  ASSERT_EQ(s.count_samples.size(), 2u);
  ASSERT_EQ(s.index_samples.size(), 2u);
  EXPECT_EQ(s.count_samples.at(0).size(), static_cast<std::size_t>(a.tris.rows()));
  EXPECT_EQ(s.count_samples.at(2).size(), static_cast<std::size_t>(b.tris.rows()));
  for (Eigen::Index i = 0; i < 3 * b.tris.rows(); ++i) EXPECT_EQ(s.index_samples.at(2)[static_cast<std::size_t>(i)], b.tris.data()[i]);
  for (Eigen::Index i = 0; i < 3 * a.tris.rows(); ++i) EXPECT_EQ(s.index_samples.at(0)[static_cast<std::size_t>(i)], a.tris.data()[i]);
  ASSERT_EQ(s.point_samples.size(), 5u);
  EXPECT_EQ(s.point_samples.at(1).size(), static_cast<std::size_t>(3 * a.x.rows()));
  EXPECT_EQ(s.point_samples.at(4).size(), static_cast<std::size_t>(3 * b.x.rows()));
  // Triangles naming a point the frame does not have are refused, and the file is unchanged.
  const std::string before = slurp(p);
  EXPECT_THROW(usd.add_frame(5, a.x, b.tris), std::invalid_argument);
  EXPECT_EQ(slurp(p), before);
  EXPECT_EQ(usd.num_frames(), 5u);
  if (std::system("command -v usdcat > /dev/null 2>&1") == 0) {
    EXPECT_EQ(std::system(("usdcat '" + p + "' > /dev/null").c_str()), 0);
  }
}

TEST(UsdaWriter, StructureCheckerRejectsBrokenFiles) {
  TempDir dir;
  const TriangleSurface m = curved_sheet(2, 2);
  const std::string p = dir.path("a.usda");
  UsdaAnimationWriter usd(p, "a", m.tris, 30);
  usd.add_frame(0, m.x);
  const std::string good = slurp(p);
  EXPECT_NO_THROW(check_usda(good));
  std::string missing_brace = good;
  missing_brace.erase(missing_brace.rfind('}'), 1);
  EXPECT_THROW(check_usda(missing_brace), std::runtime_error);
  std::string bad_number = good;
  bad_number.replace(bad_number.find("points = [(") + 11, 1, "x");
  EXPECT_THROW(check_usda(bad_number), std::runtime_error);
  EXPECT_THROW(check_usda("#usda 2.0\n" + good.substr(10)), std::runtime_error);
}

TEST(UsdaWriter, RejectsBadFramesAndKeepsTheFile) {
  TempDir dir;
  const TriangleSurface m = curved_sheet(2, 3);
  const std::string p = dir.path("a.usda");
  EXPECT_THROW(UsdaAnimationWriter(p, "a", m.tris, 0), std::invalid_argument);
  EXPECT_THROW(UsdaAnimationWriter(p, "a", Tris(0, 3), 30), std::invalid_argument);
  UsdaAnimationWriter usd(p, "a", m.tris, 30);
  Points small = m.x.topRows(3);
  EXPECT_THROW(usd.add_frame(0, small), std::invalid_argument);  // tris index past 3 points
  EXPECT_FALSE(fs::exists(p));
  usd.add_frame(2, m.x);
  const std::string before = slurp(p);
  EXPECT_THROW(usd.add_frame(3, small), std::invalid_argument);
  EXPECT_THROW(usd.add_frame(-1, m.x), std::invalid_argument);
  Points nan = m.x;
  nan(1, 1) = NAN;
  EXPECT_THROW(usd.add_frame(4, nan), std::invalid_argument);
  EXPECT_EQ(slurp(p), before);
  EXPECT_EQ(usd.num_frames(), 1u);
  // Frames may arrive out of order (a resumed run); the file lists them sorted.
  usd.add_frame(1, wobble(m.x, 1));
  const UsdaSummary s = check_usda(slurp(p));
  EXPECT_EQ(s.layer.at("startTimeCode"), "1");
  EXPECT_EQ(s.layer.at("endTimeCode"), "2");
  EXPECT_EQ(s.point_samples.begin()->first, 1);
}
