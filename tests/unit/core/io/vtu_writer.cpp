// The binary VTU writer, decoded here by a reader of our own: the XML part with a strict XML
// parser, the appended section (raw encoding, UInt64 headers, zlib blocks as VTK lays them out)
// by hand with zlib's uncompress. Every value must come back bit for bit, every offset must
// point at its array, and the arrays must tile the section with no gap.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "invfem/core/io/vtu_writer.hpp"
#include "invfem/shells/shapes.hpp"
#include "temp_dir.hpp"
#include "test_meshes.hpp"
#include "xml_check.hpp"

using namespace invfem;
using invfem::test::TempDir;
using invfem::test::XmlNode;
using invfem::test::XmlParser;
using invfem::test::slurp;

namespace {

std::uint64_t u64_at(const std::string& bytes, std::size_t at) {
  if (at + 8 > bytes.size()) throw std::runtime_error("header past the end of the appended section");
  std::uint64_t v;
  std::memcpy(&v, bytes.data() + at, 8);  // LittleEndian, as the file says (the machine is too)
  return v;
}

// One decoded array: its bytes, and how its stored form is laid out.
struct Decoded {
  std::string bytes;
  std::size_t end = 0;  // where its stored form ends in the section
  std::vector<std::uint64_t> header;  // compressed: [blocks, block size, last size, sizes...]
};

// The array stored at `offset`: a UInt64 byte count and the bytes, or VTK's zlib block layout.
Decoded decode_array(const std::string& section, std::size_t offset, bool compressed) {
  Decoded d;
  if (!compressed) {
    const std::uint64_t size = u64_at(section, offset);
    if (size > section.size() || offset + 8 + size > section.size())
      throw std::runtime_error("array past the end of the section");
    d.bytes = section.substr(offset + 8, size);
    d.end = offset + 8 + size;
    return d;
  }
  const std::uint64_t blocks = u64_at(section, offset), block = u64_at(section, offset + 8),
                      last = u64_at(section, offset + 16);
  d.header = {blocks, block, last};
  if (block == 0 || last >= block || blocks > section.size() / 8 || offset + 8 * (3 + blocks) > section.size())
    throw std::runtime_error("not a compression header");
  std::size_t at = offset + 8 * (3 + blocks);
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t stored = u64_at(section, offset + 8 * (3 + b));
    d.header.push_back(stored);
    if (stored > section.size() || at + stored > section.size())
      throw std::runtime_error("block past the end of the section");
    const std::uint64_t expected = (b + 1 == blocks && last != 0) ? last : block;
    std::string out(expected, '\0');
    uLongf size = static_cast<uLongf>(expected);
    if (uncompress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(section.data() + at),
                   static_cast<uLong>(stored)) != Z_OK)
      throw std::runtime_error("a block does not inflate");
    if (size != expected) throw std::runtime_error("a block inflates to " + std::to_string(size) + " bytes");
    d.bytes += out;
    at += stored;
  }
  d.end = at;
  return d;
}

// A .vtu as a reader sees it: the XML tree, and each DataArray's decoded bytes by its Name
// (prefixed by its parent element: "Points/Points", "Cells/offsets", "CellData/det_F").
struct VtuFile {
  XmlNode root;
  std::map<std::string, const XmlNode*> element;
  std::map<std::string, Decoded> arrays;
  std::size_t section_size = 0;

  template <class T> std::vector<T> values(const std::string& name) const {
    const std::string& b = arrays.at(name).bytes;
    if (b.size() % sizeof(T)) throw std::runtime_error(name + ": not a whole number of values");
    std::vector<T> v(b.size() / sizeof(T));
    std::memcpy(v.data(), b.data(), b.size());
    return v;
  }
};

VtuFile read_vtu(const std::string& path) {
  const std::string file = slurp(path);
  const std::string open = "<AppendedData encoding=\"raw\">", tail = "\n  </AppendedData>\n</VTKFile>\n";
  const std::size_t at = file.find(open);
  if (at == std::string::npos) throw std::runtime_error("no raw AppendedData");
  const std::size_t underscore = file.find('_', at + open.size());
  if (underscore == std::string::npos || file.find_first_not_of(" \n", at + open.size()) != underscore)
    throw std::runtime_error("the appended section does not start with '_'");
  if (file.size() < underscore + 1 + tail.size() ||
      file.compare(file.size() - tail.size(), tail.size(), tail) != 0)
    throw std::runtime_error("the file does not end with the appended section's end tag");
  VtuFile v;
  v.root = XmlParser(file.substr(0, underscore) + tail).document();
  const std::string section = file.substr(underscore + 1, file.size() - tail.size() - underscore - 1);
  v.section_size = section.size();
  const bool compressed = v.root.attrs.count("compressor") > 0;
  if (compressed && v.root.attr("compressor") != "vtkZLibDataCompressor")
    throw std::runtime_error("unknown compressor");
  const XmlNode& piece = v.root.one("UnstructuredGrid").one("Piece");
  std::vector<std::pair<std::size_t, std::size_t>> spans;  // (offset, end) of every array
  for (const XmlNode& group : piece.children)
    for (const XmlNode* a : group.all("DataArray")) {
      if (a->attr("format") != "appended") throw std::runtime_error(a->attr("Name") + " is not appended");
      const std::size_t offset = std::stoull(a->attr("offset"));
      const std::string key = group.name + "/" + a->attr("Name");
      v.element[key] = a;
      v.arrays[key] = decode_array(section, offset, compressed);
      spans.emplace_back(offset, v.arrays[key].end);
    }
  // The arrays follow one another from offset 0 to the end of the section, in document order.
  std::size_t expected = 0;
  for (const auto& [offset, end] : spans) {
    if (offset != expected)
      throw std::runtime_error("an array starts at " + std::to_string(offset) + ", not " + std::to_string(expected));
    expected = end;
  }
  if (expected != section.size()) throw std::runtime_error("bytes after the last array");
  return v;
}

// A solid's frame: a box of tets, moved so no coordinate is trivial, with det F, inverted flags,
// a point scalar whose name needs escaping and velocities.
struct SolidFrame {
  Points x;
  Tets tets;
  VtuFields fields;
};

SolidFrame solid_frame() {
  const test::TetMesh mesh = test::cube_cells_mesh({3, 2, 2}, 0.1);
  SolidFrame s;
  s.x = mesh.X;
  for (Eigen::Index i = 0; i < s.x.rows(); ++i) s.x(i, 1) = 0.9 * s.x(i, 1) + 1e-3 * std::sin(7.0 * i);
  s.tets = mesh.T;
  const Eigen::Index n = s.x.rows(), m = s.tets.rows();
  Eigen::VectorXd det(m), pressure(n);
  for (Eigen::Index e = 0; e < m; ++e) det[e] = (e % 7 == 3) ? -0.25 - 1e-3 * e : 0.9 + 1e-3 * e;
  for (Eigen::Index i = 0; i < n; ++i) pressure[i] = std::exp(0.1 * i) * 1e-7;
  s.fields.cell_scalars["det_F"] = det;
  s.fields.cell_scalars["inverted"] = (det.array() < 0).cast<double>();
  s.fields.point_scalars["p<&\"q>"] = pressure;
  s.fields.point_vectors["velocity"] = 2 * s.x + Points::Constant(n, 3, 1.0 / 3);
  return s;
}

void expect_bits(const std::vector<double>& got, const double* want, Eigen::Index count, const std::string& what) {
  ASSERT_EQ(got.size(), static_cast<std::size_t>(count)) << what;
  EXPECT_EQ(std::memcmp(got.data(), want, sizeof(double) * got.size()), 0) << what << " differs";
}

}  // namespace

TEST(VtuWriter, EveryArrayDecodesToTheValuesGivenBitForBit) {
  TempDir dir;
  const SolidFrame s = solid_frame();
  const Eigen::Index n = s.x.rows(), m = s.tets.rows();
  for (const int level : {0, 1, 6, 9}) {
    SCOPED_TRACE("compression " + std::to_string(level));
    const std::string p = dir.path("frame" + std::to_string(level) + ".vtu");
    write_vtu(p, s.x, s.tets, s.fields, {level, 32768});
    const VtuFile v = read_vtu(p);
    EXPECT_EQ(v.root.attr("type"), "UnstructuredGrid");
    EXPECT_EQ(v.root.attr("version"), "1.0");
    EXPECT_EQ(v.root.attr("byte_order"), "LittleEndian");
    EXPECT_EQ(v.root.attr("header_type"), "UInt64");
    EXPECT_EQ(v.root.attrs.count("compressor"), level > 0 ? 1u : 0u);
    const XmlNode& piece = v.root.one("UnstructuredGrid").one("Piece");
    EXPECT_EQ(piece.attr("NumberOfPoints"), std::to_string(n));
    EXPECT_EQ(piece.attr("NumberOfCells"), std::to_string(m));

    EXPECT_EQ(v.element.at("Points/Points")->attr("type"), "Float64");
    EXPECT_EQ(v.element.at("Points/Points")->attr("NumberOfComponents"), "3");
    expect_bits(v.values<double>("Points/Points"), s.x.data(), 3 * n, "points");
    EXPECT_EQ(v.element.at("Cells/connectivity")->attr("type"), "Int32");
    EXPECT_EQ(v.values<std::int32_t>("Cells/connectivity"),
              std::vector<std::int32_t>(s.tets.data(), s.tets.data() + 4 * m));
    const auto offsets = v.values<std::int32_t>("Cells/offsets");
    ASSERT_EQ(offsets.size(), static_cast<std::size_t>(m));
    for (Eigen::Index e = 0; e < m; ++e) EXPECT_EQ(offsets[static_cast<std::size_t>(e)], 4 * (e + 1));
    EXPECT_EQ(v.element.at("Cells/types")->attr("type"), "UInt8");
    EXPECT_EQ(v.values<std::uint8_t>("Cells/types"), std::vector<std::uint8_t>(static_cast<std::size_t>(m), 10));

    expect_bits(v.values<double>("CellData/det_F"), s.fields.cell_scalars.at("det_F").data(), m, "det_F");
    const auto inverted = v.values<double>("CellData/inverted");
    expect_bits(inverted, s.fields.cell_scalars.at("inverted").data(), m, "inverted");
    EXPECT_GT(std::count(inverted.begin(), inverted.end(), 1.0), 0);
    expect_bits(v.values<double>("PointData/p<&\"q>"), s.fields.point_scalars.at("p<&\"q>").data(), n, "escaped name");
    EXPECT_EQ(v.element.at("PointData/velocity")->attr("NumberOfComponents"), "3");
    expect_bits(v.values<double>("PointData/velocity"), s.fields.point_vectors.at("velocity").data(), 3 * n, "velocity");
  }
  // Compression pays on these arrays.
  EXPECT_LT(std::filesystem::file_size(dir.path("frame1.vtu")), std::filesystem::file_size(dir.path("frame0.vtu")));
}

TEST(VtuWriter, ATriangleSurfaceIsWrittenAsTriangleCells) {
  TempDir dir;
  const TriangleSurface sheet = make_grid(1.3, 0.7, 5, 3, Vec3(-0.4, 0.2, 0.1));
  VtuFields f;
  f.point_vectors["velocity"] = sheet.x * 0.5;
  const std::string p = dir.path("cloth.vtu");
  write_vtu(p, sheet.x, sheet.tris, f);
  const VtuFile v = read_vtu(p);
  EXPECT_EQ(v.root.attr("compressor"), "vtkZLibDataCompressor");  // the default compresses
  const Eigen::Index m = sheet.tris.rows();
  EXPECT_EQ(v.values<std::int32_t>("Cells/connectivity"),
            std::vector<std::int32_t>(sheet.tris.data(), sheet.tris.data() + 3 * m));
  const auto offsets = v.values<std::int32_t>("Cells/offsets");
  ASSERT_EQ(offsets.size(), static_cast<std::size_t>(m));
  for (Eigen::Index e = 0; e < m; ++e) EXPECT_EQ(offsets[static_cast<std::size_t>(e)], 3 * (e + 1));
  EXPECT_EQ(v.values<std::uint8_t>("Cells/types"), std::vector<std::uint8_t>(static_cast<std::size_t>(m), 5));
  expect_bits(v.values<double>("Points/Points"), sheet.x.data(), 3 * sheet.x.rows(), "points");
  expect_bits(v.values<double>("PointData/velocity"), f.point_vectors.at("velocity").data(), 3 * sheet.x.rows(), "velocity");
}

// An empty array still has its header: a byte count of 0, or zero blocks (VTK's layout keeps the
// block size and a last size of 0), and the next array starts right after it.
TEST(VtuWriter, EmptyArraysHaveAHeaderAndNoData) {
  TempDir dir;
  const test::TetMesh mesh = test::cube_cells_mesh({1, 1, 1}, 1.0);
  VtuFields f;
  f.cell_scalars["det_F"] = Eigen::VectorXd(0);
  f.point_vectors["velocity"] = mesh.X;
  for (const int level : {0, 1}) {
    SCOPED_TRACE("compression " + std::to_string(level));
    const std::string p = dir.path("empty.vtu");
    write_vtu(p, mesh.X, Tets(0, 4), f, {level, 4096});
    const VtuFile v = read_vtu(p);  // also checks the arrays tile the section
    EXPECT_EQ(v.root.one("UnstructuredGrid").one("Piece").attr("NumberOfCells"), "0");
    for (const char* name : {"Cells/connectivity", "Cells/offsets", "Cells/types", "CellData/det_F"}) {
      const Decoded& d = v.arrays.at(name);
      EXPECT_TRUE(d.bytes.empty()) << name;
      const std::size_t offset = std::stoull(v.element.at(name)->attr("offset"));
      if (level == 0) {
        EXPECT_EQ(d.end - offset, 8u) << name;
      } else {
        EXPECT_EQ(d.header, (std::vector<std::uint64_t>{0, 4096, 0})) << name;
        EXPECT_EQ(d.end - offset, 24u) << name;
      }
    }
    expect_bits(v.values<double>("PointData/velocity"), mesh.X.data(), 3 * mesh.X.rows(), "velocity");
  }
}

// An array larger than a block is split into blocks of the block size, the last one partial (its
// size in the header) or full (0 in the header), each compressed on its own.
TEST(VtuWriter, ArraysLargerThanABlockAreSplitIntoBlocks) {
  TempDir dir;
  const TriangleSurface sheet = make_grid(2.0, 1.0, 80, 60);  // 4941 points: 118584 bytes of Float64
  Points x = sheet.x;
  for (Eigen::Index i = 0; i < x.rows(); ++i) x(i, 2) = 0.1 * std::sin(3 * x(i, 0)) * std::cos(5 * x(i, 1));
  const std::size_t bytes = 24 * static_cast<std::size_t>(x.rows());
  // 32 KiB: 3 full blocks and a partial one; 8 * 4941 = 39528 divides the points' bytes: 3 full.
  for (const std::size_t block : {std::size_t{32768}, std::size_t{39528}}) {
    SCOPED_TRACE("block size " + std::to_string(block));
    const std::string p = dir.path("big.vtu");
    write_vtu(p, x, sheet.tris, {}, {6, block});
    const VtuFile v = read_vtu(p);
    const Decoded& d = v.arrays.at("Points/Points");
    const std::uint64_t blocks = (bytes + block - 1) / block;
    ASSERT_GE(d.header.size(), 3u);
    EXPECT_GT(blocks, 1u);
    EXPECT_EQ(d.header[0], blocks);
    EXPECT_EQ(d.header[1], block);
    EXPECT_EQ(d.header[2], bytes % block);
    ASSERT_EQ(d.header.size(), 3 + blocks);
    std::uint64_t stored = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) stored += d.header[3 + b];
    EXPECT_EQ(d.end - std::stoull(v.element.at("Points/Points")->attr("offset")), 8 * (3 + blocks) + stored);
    expect_bits(v.values<double>("Points/Points"), x.data(), 3 * x.rows(), "points");
    EXPECT_EQ(v.values<std::int32_t>("Cells/connectivity"),
              std::vector<std::int32_t>(sheet.tris.data(), sheet.tris.data() + 3 * sheet.tris.rows()));
  }
}

// The decoder above can fail: a file cut short, a flipped byte in a block, an offset that does
// not point at its array.
TEST(VtuWriter, TheDecoderRejectsDamagedFiles) {
  TempDir dir;
  const SolidFrame s = solid_frame();
  const std::string p = dir.path("frame.vtu");
  write_vtu(p, s.x, s.tets, s.fields);
  const std::string good = slurp(p);
  ASSERT_NO_THROW(read_vtu(p));
  const std::size_t data = good.find("   _") + 4;
  const std::string cut = good.substr(0, good.size() - 200) + "\n  </AppendedData>\n</VTKFile>\n";
  std::string flipped = good;
  flipped[data + 40] = static_cast<char>(flipped[data + 40] ^ 0x5a);  // inside the points' first block
  std::string moved = good;
  moved.replace(moved.find("offset=\"0\""), 10, "offset=\"8\"");
  for (const std::string& bad : {cut, flipped, moved})
    EXPECT_THROW(read_vtu(dir.file("bad.vtu", bad)), std::runtime_error);
}

TEST(VtuWriter, RejectsBadFieldsMeshesAndEncodings) {
  TempDir dir;
  const test::TetMesh mesh = test::cube_cells_mesh({1, 1, 1}, 1.0);
  const std::string p = dir.path("f.vtu");
  VtuFields f;
  f.cell_scalars["det_F"] = Eigen::VectorXd::Ones(mesh.T.rows() + 1);
  try {
    write_vtu(p, mesh.X, mesh.T, f);
    FAIL() << "wrong length accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("det_F"), std::string::npos) << e.what();
  }
  f.cell_scalars["det_F"] = Eigen::VectorXd::Ones(mesh.T.rows());
  f.cell_scalars["det_F"][2] = INFINITY;
  EXPECT_THROW(write_vtu(p, mesh.X, mesh.T, f), std::invalid_argument);
  VtuFields g;
  g.point_vectors["v"] = Points::Zero(mesh.X.rows() - 1, 3);
  EXPECT_THROW(write_vtu(p, mesh.X, mesh.T, g), std::invalid_argument);
  Tets t = mesh.T;
  t(0, 0) = -1;
  EXPECT_THROW(write_vtu(p, mesh.X, t), std::invalid_argument);
  Points x = mesh.X;
  x(0, 0) = std::nan("");
  EXPECT_THROW(write_vtu(p, x, mesh.T), std::invalid_argument);
  for (const VtuEncoding bad :
       {VtuEncoding{-1, 32768}, VtuEncoding{10, 32768}, VtuEncoding{1, 0}, VtuEncoding{1, 12}}) {
    try {
      write_vtu(p, mesh.X, mesh.T, {}, bad);
      FAIL() << "encoding " << bad.compression << ", " << bad.block_size << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(std::filesystem::exists(p));
}
