// The strict garment OBJ reader (core/obj_file.hpp): vt layouts of C-IPC and ARCSim, polygons,
// relative indices, groups, uninterpreted lines, line ends, every documented error with its file
// and line, and the shared garments.
#include "invfem/core/io/obj_file.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace invfem;

namespace {

using test::TempDir;

const std::string kShared = INVFEM_SHARED_DATA;

// The message of the ObjError thrown by reading `path`, or "" (and a test failure) if none.
std::string obj_error_of(const std::string& path) {
  try {
    read_obj_file(path);
  } catch (const ObjError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected ObjError, got another exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected ObjError for " << path << ", nothing thrown";
  return "";
}

// Writes `text` as bad.obj and expects an ObjError "<path>:<line>: ..." containing `problem`.
void expect_error_at(const TempDir& tmp, const std::string& text, int line,
                     const std::string& problem) {
  const std::string path = tmp.file("bad.obj", text);
  const std::string msg = obj_error_of(path);
  const std::string prefix = path + ":" + std::to_string(line) + ": ";
  EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "message: " << msg << "\nexpected prefix: " << prefix;
  EXPECT_NE(msg.find(problem), std::string::npos) << "message: " << msg << "\nexpected: " << problem;
}

const char* kTwoTriangles = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

}  // namespace

TEST(ObjFile, PerVertexVtCipcStyle) {
  TempDir tmp;
  const std::string path = tmp.file(
      "cipc.obj",
      "v 0 0 0\nv 1 0 0\nv 0 1 0.5\nv 1 1 0\nvt 0 0\nvt 2 0\nvt 0 2\nvt 2 2\n"
      "f 1/1 2/2 3/3\nf 2/2 4/4 3/3\n");
  const ObjFile obj = read_obj_file(path);
  EXPECT_EQ(obj.path, path);
  ASSERT_EQ(obj.v.rows(), 4);
  EXPECT_EQ(obj.v.row(2), Eigen::RowVector3d(0, 1, 0.5));
  ASSERT_EQ(obj.vt.rows(), 4);
  EXPECT_EQ(obj.vt.row(3), Eigen::RowVector2d(2, 2));
  ASSERT_EQ(obj.faces.rows(), 2);
  EXPECT_EQ(obj.faces.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(obj.faces.row(1), Eigen::RowVector3i(1, 3, 2));
  EXPECT_EQ(obj.face_vt, obj.faces);
  EXPECT_EQ(obj.face_group, (std::vector<int>{0, 0}));
  EXPECT_EQ(obj.groups, (std::vector<std::string>{""}));
  EXPECT_TRUE(obj.extra.empty());
  EXPECT_EQ(obj.polygons_split, 0);
}

TEST(ObjFile, PerCornerVtArcsimStyle) {
  TempDir tmp;
  // More vt than v: each corner has its own vt; a 3rd vt coordinate is dropped; vt "u" alone
  // gets v = 0; faces without vt get -1.
  const ObjFile obj = read_obj_file(tmp.file(
      "arcsim.obj",
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
      "vt 9 9\nvt 8 8\nvt 7 7\nvt 0 0 1\nvt 1 0\nvt 0 1\nvt 1 1 0.25\nvt 3\n"
      "f 1/4 2/5 3/6\nf 2/7 4/8 3/1\nf 1 2 4\n"));
  ASSERT_EQ(obj.vt.rows(), 8);
  EXPECT_EQ(obj.vt.row(3), Eigen::RowVector2d(0, 0));
  EXPECT_EQ(obj.vt.row(6), Eigen::RowVector2d(1, 1));
  EXPECT_EQ(obj.vt.row(7), Eigen::RowVector2d(3, 0));
  ASSERT_EQ(obj.faces.rows(), 3);
  EXPECT_EQ(obj.face_vt.row(0), Eigen::RowVector3i(3, 4, 5));
  EXPECT_EQ(obj.face_vt.row(1), Eigen::RowVector3i(6, 7, 0));
  EXPECT_EQ(obj.face_vt.row(2), Eigen::RowVector3i(-1, -1, -1));
  EXPECT_EQ(obj.faces.row(2), Eigen::RowVector3i(0, 1, 3));
}

TEST(ObjFile, PolygonsAreFannedFromTheFirstCorner) {
  TempDir tmp;
  const ObjFile obj = read_obj_file(tmp.file(
      "quads.obj", std::string(kTwoTriangles) +
                       "v 2 0 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 2 0\n"
                       "f 1/1 2/2 3/3 4/4\nf 2 5 3\nf 1 2 5 3 4\n"));
  ASSERT_EQ(obj.faces.rows(), 2 + 1 + 3);
  EXPECT_EQ(obj.polygons_split, 2);
  EXPECT_EQ(obj.faces.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(obj.faces.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(obj.face_vt.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(obj.faces.row(2), Eigen::RowVector3i(1, 4, 2));
  EXPECT_EQ(obj.faces.row(3), Eigen::RowVector3i(0, 1, 4));
  EXPECT_EQ(obj.faces.row(4), Eigen::RowVector3i(0, 4, 2));
  EXPECT_EQ(obj.faces.row(5), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(obj.face_vt.row(5), Eigen::RowVector3i(-1, -1, -1));
}

TEST(ObjFile, NegativeIndicesAreRelativeToTheCountSoFar) {
  TempDir tmp;
  const ObjFile obj = read_obj_file(tmp.file(
      "neg.obj",
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
      "f -3/-3/-1 -2/-2/-1 -1/-1/-1\n"
      "v 1 1 0\nvt 1 1\n"
      "f -3/-3 -1/-1 -2/-2\nf +2 4 -2\n"));
  ASSERT_EQ(obj.faces.rows(), 3);
  EXPECT_EQ(obj.faces.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(obj.face_vt.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(obj.faces.row(1), Eigen::RowVector3i(1, 3, 2));
  EXPECT_EQ(obj.face_vt.row(1), Eigen::RowVector3i(1, 3, 2));
  EXPECT_EQ(obj.faces.row(2), Eigen::RowVector3i(1, 3, 2));
}

TEST(ObjFile, NormalIndicesAreCheckedButDropped) {
  TempDir tmp;
  const ObjFile obj = read_obj_file(tmp.file(
      "normals.obj", std::string(kTwoTriangles) +
                         "vn 0 0 1\nvn 0 0 -1\nvt 0 0\nf 1//1 2//2 3//1\nf 1/1/2 3/1/2 4/1/2\n"));
  ASSERT_EQ(obj.faces.rows(), 2);
  EXPECT_EQ(obj.face_vt.row(0), Eigen::RowVector3i(-1, -1, -1));
  EXPECT_EQ(obj.face_vt.row(1), Eigen::RowVector3i(0, 0, 0));
}

TEST(ObjFile, GroupsInOrderOfAppearance) {
  TempDir tmp;
  const ObjFile obj = read_obj_file(tmp.file(
      "groups.obj", std::string(kTwoTriangles) +
                        "f 1 2 3\n"                  // before any group: ""
                        "g  left panel \t\nf 1 3 4\n"  // name is the trimmed rest of the line
                        "o body\ng\nf 2 3 4\n"       // an empty g is "default"; o names too
                        "g left panel\nf 1 2 4\n"    // a name seen before reuses its group
                        "s off\nusemtl cloth\nmtllib cloth.mtl\ng back # comment\nf 4 3 2\n"));
  EXPECT_EQ(obj.groups,
            (std::vector<std::string>{"", "left panel", "body", "default", "back"}));
  EXPECT_EQ(obj.face_group, (std::vector<int>{0, 1, 3, 1, 4}));
  EXPECT_TRUE(obj.extra.empty());

  // No "" group when every face follows a g line; fanned faces all get the group.
  const ObjFile named = read_obj_file(
      tmp.file("named.obj", std::string(kTwoTriangles) + "g panel0\nf 1 2 3 4\n"));
  EXPECT_EQ(named.groups, (std::vector<std::string>{"panel0"}));
  EXPECT_EQ(named.face_group, (std::vector<int>{0, 0}));
}

TEST(ObjFile, UninterpretedLinesAreKeptWithTheirLineNumbers) {
  TempDir tmp;
  const ObjFile obj = read_obj_file(tmp.file(
      "stitch.obj", std::string(kTwoTriangles) +                       // lines 1-4
                        "f 1 2 3\nf 1 3 4\n\n"                         // 5-7
                        "seam 2\nstitch 0 1 2 0.5\n"                   // 8-9
                        "# stitch 9 9 9 9\n"                           // 10: a comment
                        "stitch\t3  1 2 5.000000e-001 # trailing\n"    // 11
                        "vv 0 0 0\nt 0\nl 1 2\n"));                    // 12-14
  ASSERT_EQ(obj.extra.size(), 6u);
  EXPECT_EQ(obj.extra[0].keyword, "seam");
  EXPECT_EQ(obj.extra[0].line, 8);
  EXPECT_EQ(obj.extra[0].words, (std::vector<std::string>{"2"}));
  EXPECT_EQ(obj.extra[1].keyword, "stitch");
  EXPECT_EQ(obj.extra[1].line, 9);
  EXPECT_EQ(obj.extra[1].words, (std::vector<std::string>{"0", "1", "2", "0.5"}));
  EXPECT_EQ(obj.extra[2].line, 11);
  EXPECT_EQ(obj.extra[2].words, (std::vector<std::string>{"3", "1", "2", "5.000000e-001"}));
  EXPECT_EQ(obj.extra[3].keyword, "vv");
  EXPECT_EQ(obj.extra[4].keyword, "t");
  EXPECT_EQ(obj.extra[4].line, 13);
  EXPECT_EQ(obj.extra[5].keyword, "l");
  EXPECT_EQ(obj.extra[5].words, (std::vector<std::string>{"1", "2"}));
}

TEST(ObjFile, CrlfTabsCommentsAndNoFinalNewline) {
  TempDir tmp;
  const std::string path = tmp.file(
      "crlf.obj",
      "# header\r\n\r\nv\t0 0 0\r\nv 1e0 +0 -0.0  \r\nv 0 .5e1 5.\r\n   \r\n"
      "vt 0 0\r\nvt 1 0\r\nvt 0 1\r\ng panel#1\r\nf 1/1 2/2 3/3 # tail\r\nstitch 0 1 2 0.5\r\n"
      "f 3 2 1");
  const ObjFile obj = read_obj_file(path);
  ASSERT_EQ(obj.v.rows(), 3);
  EXPECT_EQ(obj.v.row(1), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(obj.v.row(2), Eigen::RowVector3d(0, 5, 5));
  ASSERT_EQ(obj.faces.rows(), 2);
  EXPECT_EQ(obj.groups, (std::vector<std::string>{"panel#1"}));
  ASSERT_EQ(obj.extra.size(), 1u);
  EXPECT_EQ(obj.extra[0].line, 12);
  EXPECT_EQ(obj.extra[0].words.back(), "0.5");
}

TEST(ObjFile, ParseTextMatchesReadFile) {
  TempDir tmp;
  const std::string text = std::string(kTwoTriangles) + "g a\nf 1 2 3 4\nstitch 0 1 2 0\n";
  const ObjFile a = read_obj_file(tmp.file("a.obj", text));
  const ObjFile b = parse_obj_text(text, "in-memory");
  EXPECT_EQ(b.path, "in-memory");
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.v, b.v);
  EXPECT_EQ(a.groups, b.groups);
  EXPECT_EQ(a.extra.size(), b.extra.size());
  try {
    parse_obj_text("v 0 0 0\nf 1 2 3\n", "mem.obj");
    ADD_FAILURE() << "no error";
  } catch (const ObjError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("mem.obj:2: ", 0), 0u) << e.what();
  }
}

// ---- errors -------------------------------------------------------------------------------

TEST(ObjFileErrors, MissingEmptyAndFacelessFiles) {
  TempDir tmp;
  const std::string missing = tmp.path("nope.obj").string();
  EXPECT_EQ(obj_error_of(missing), missing + ": file not found");
  EXPECT_EQ(obj_error_of(tmp.path("").string()).find("not a regular file") != std::string::npos,
            true);
  const std::string empty = tmp.file("empty.obj", "");
  EXPECT_EQ(obj_error_of(empty), empty + ": file is empty");
  const std::string blank = tmp.file("blank.obj", " \r\n\t\n\n");
  EXPECT_EQ(obj_error_of(blank), blank + ": file is empty");
  const std::string faceless = tmp.file("faceless.obj", "# only points\nv 0 0 0\nv 1 0 0\n");
  const std::string msg = obj_error_of(faceless);
  EXPECT_EQ(msg.rfind(faceless + ": no faces", 0), 0u) << msg;
}

TEST(ObjFileErrors, FaceIndexOutOfRangeNamesCornerAndCount) {
  TempDir tmp;
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1 2 3\nf 1 2 5\n", 6,
                  "face corner 3 refers to vertex 5, the file has 4 vertices so far");
  // "So far": a vertex defined after the face does not count.
  expect_error_at(tmp, "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", 3,
                  "face corner 3 refers to vertex 3, the file has 2 vertices so far");
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1 -5 3\n", 5,
                  "face corner 2 refers to vertex -5 (relative), the file has 4 vertices so far");
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 0 1 2\n", 5,
                  "face corner 1: vertex index 0 is invalid");
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1 2 99999999999999999999999\n", 5,
                  "face corner 3 refers to vertex '99999999999999999999999', the file has 4");
  expect_error_at(tmp, std::string(kTwoTriangles) + "vt 0 0\nf 1/1 2/2 3/1\n", 6,
                  "face corner 2 refers to texture coordinate 2, the file has 1 texture "
                  "coordinates so far");
  expect_error_at(tmp, std::string(kTwoTriangles) + "vn 0 0 1\nf 1//1 2//1 3//2\n", 6,
                  "face corner 3 refers to normal 2, the file has 1 normals so far");
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1/1 2 3\n", 5,
                  "face corner 1 refers to texture coordinate 1, the file has 0");
}

TEST(ObjFileErrors, MalformedCorners) {
  TempDir tmp;
  for (const char* corner : {"2/", "2/1/", "2//", "/1", "2/1/1/1", "2x", "0x2", "2.0", "+-2"}) {
    SCOPED_TRACE(corner);
    const std::string text = std::string(kTwoTriangles) + "vt 0 0\nvn 0 0 1\nf 1 " + corner + " 3\n";
    const std::string msg = obj_error_of(tmp.file("bad.obj", text));
    EXPECT_NE(msg.find("bad.obj:7: face corner 2"), std::string::npos) << msg;
  }
}

TEST(ObjFileErrors, FacesWithFewerThanThreeCornersMixedVtOrRepeatedVertices) {
  TempDir tmp;
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1 2\n", 5,
                  "face with 2 corners, a face needs at least 3");
  expect_error_at(tmp, std::string(kTwoTriangles) + "f\n", 5, "face with 0 corners");
  expect_error_at(tmp, std::string(kTwoTriangles) + "vt 0 0\nf 1/1 2/1 3\n", 6,
                  "face corner 3 has no texture coordinate but corner 1 has one");
  expect_error_at(tmp, std::string(kTwoTriangles) + "vt 0 0\nvn 0 0 1\nf 1 2//1 3/1\n", 7,
                  "face corner 3 has a texture coordinate but corner 1 has none");
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1 2 1\n", 5,
                  "degenerate face: corners 1 and 3 are the same vertex 1");
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1 2 3 -2\n", 5,
                  "degenerate face: corners 3 and 4 are the same vertex 3");
  // Long polygons take the sorted path.
  std::string many;
  for (int i = 0; i < 12; ++i) many += "v " + std::to_string(i) + " 0 0\n";
  expect_error_at(tmp, many + "f 1 2 3 4 5 6 7 8 9 10 11 12 5\n", 13,
                  "degenerate face: corners 5 and 13 are the same vertex 5");
  EXPECT_EQ(read_obj_file(tmp.file("ok.obj", many + "f 1 2 3 4 5 6 7 8 9 10 11 12\n")).faces.rows(),
            10);
}

TEST(ObjFileErrors, StrictNumbers) {
  TempDir tmp;
  struct Case {
    const char* line;
    const char* problem;
  };
  for (const Case& c : {
           Case{"v 0 nan 0", "vertex 3: y: 'nan' is not a finite number"},
           Case{"v 0 0 inf", "vertex 3: z: 'inf' is not a finite number"},
           Case{"v -Infinity 0 0", "vertex 3: x: '-Infinity' is not a finite number"},
           Case{"v 0x1p3 0 0", "vertex 3: x: expected a number, got '0x1p3'"},
           Case{"v 1.5e 0 0", "vertex 3: x: expected a number, got '1.5e'"},
           Case{"v 1,5 0 0", "vertex 3: x: expected a number, got '1,5'"},
           Case{"v 1 2 3abc", "vertex 3: z: expected a number, got '3abc'"},
           Case{"v +-1 0 0", "vertex 3: x: expected a number, got '+-1'"},
           Case{"v ++1 0 0", "vertex 3: x: expected a number, got '++1'"},
           Case{"v 1e400 0 0", "vertex 3: x: '1e400' is outside the range of a double"},
           Case{"v 0 -1e-400 0", "vertex 3: y: '-1e-400' is outside the range of a double"},
           Case{"v 0 0", "vertex 3: expected x y z, x y z w or x y z r g b, got 2 numbers"},
           Case{"v 0 0 0 1 1", "vertex 3: expected x y z, x y z w or x y z r g b, got 5"},
           Case{"v 0 0 0 1 1 1 1", "got more than 6 numbers"},
           Case{"vt", "texture coordinate 1: expected u [v [w]], got 0 numbers"},
           Case{"vt 0 0 0 0", "texture coordinate 1: expected u [v [w]], got more than 3"},
           Case{"vt 0 NaN", "texture coordinate 1: v: 'NaN' is not a finite number"},
           Case{"vn 0 1", "normal 1: expected x y z, got 2 numbers"},
           Case{"vn 0 1 x", "normal 1: z: expected a number, got 'x'"},
           Case{"v 1 2 \\", "line continuation with a trailing '\\' is not supported"},
       }) {
    SCOPED_TRACE(c.line);
    expect_error_at(tmp, std::string("v 0 0 0\nv 1 0 0\n") + c.line + "\nv 0 1 0\nf 1 2 3\n", 3,
                    c.problem);
  }
  // Accepted: w, an r g b colour, exponents, explicit plus, subnormals.
  const ObjFile ok = read_obj_file(tmp.file(
      "ok.obj", "v 1 2 3 1\nv 1 2 3 0.5 0.5 0.5\nv +1.5E+2 -2e-3 4e-320\nf 1 2 3\n"));
  EXPECT_EQ(ok.v(2, 0), 150.0);
  EXPECT_EQ(ok.v(2, 1), -0.002);
  EXPECT_GT(ok.v(2, 2), 0.0);
}

TEST(ObjFileErrors, HugeLinesNulBytesAndLongTokensAreBounded) {
  TempDir tmp;
  // A 2 MiB line is refused before it is split.
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1 2 3 " + std::string(2 << 20, '4') + "\n",
                  5, "over the 1 MiB limit");
  // A long bad token is cut in the message.
  const std::string msg =
      obj_error_of(tmp.file("bad.obj", "v " + std::string(100000, '1') + "x 0 0\n"));
  EXPECT_LT(msg.size(), 300u);
  EXPECT_NE(msg.find("...'"), std::string::npos) << msg;
  expect_error_at(tmp, std::string(kTwoTriangles) + "f 1 2 3\n" + std::string("v 0 \0 0\n", 8), 6,
                  "NUL byte");
  // A face line of 100,000 distinct corners fans to 99,998 triangles.
  std::string big;
  for (int i = 0; i < 100000; ++i) big += "v 0 0 0\n";
  big += "f";
  for (int i = 1; i <= 100000; ++i) {
    big += ' ';
    big += std::to_string(i);
  }
  const ObjFile fan = read_obj_file(tmp.file("fan.obj", big + "\n"));
  EXPECT_EQ(fan.faces.rows(), 99998);
  EXPECT_EQ(fan.polygons_split, 1);
}

// ---- shared garments ----------------------------------------------------------------------

TEST(ObjFileShared, CipcDressStage) {
  const std::string path = kShared + "/cloth/dress_knife_stage_cipc.obj";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data not present: " << path;
  const auto t0 = std::chrono::steady_clock::now();
  const ObjFile obj = read_obj_file(path);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("read %s in %.4f s\n", path.c_str(), seconds);
  RecordProperty("read_seconds", std::to_string(seconds));

  EXPECT_EQ(obj.v.rows(), 15656);
  EXPECT_EQ(obj.vt.rows(), 15656);
  ASSERT_EQ(obj.faces.rows(), 29456);
  EXPECT_EQ(obj.face_vt, obj.faces);
  EXPECT_EQ(obj.polygons_split, 0);
  ASSERT_EQ(obj.groups.size(), 14u);
  for (int g = 0; g < 14; ++g) EXPECT_EQ(obj.groups[g], "panel" + std::to_string(g));
  ASSERT_EQ(obj.face_group.size(), 29456u);
  EXPECT_EQ(obj.face_group.front(), 0);
  EXPECT_EQ(obj.face_group.back(), 13);
  EXPECT_EQ(std::count(obj.face_group.begin(), obj.face_group.end(), 0), 1575);  // "# 1575 triangles"
  // Bounding box from the data README.
  EXPECT_NEAR(obj.v.col(0).minCoeff(), -0.330276, 1e-6);
  EXPECT_NEAR(obj.v.col(2).maxCoeff(), 0.581747, 1e-6);

  int stitches = 0, seams = 0;
  for (const ObjFile::Extra& e : obj.extra) {
    if (e.keyword == "stitch") {
      ++stitches;
      ASSERT_EQ(e.words.size(), 4u) << "line " << e.line;
      for (int k = 0; k < 3; ++k) {  // 0-based vertex indices
        const int i = std::stoi(e.words[k]);
        EXPECT_GE(i, 0);
        EXPECT_LT(i, 15656);
      }
    } else if (e.keyword == "seam") {
      ++seams;
    } else {
      ADD_FAILURE() << "unexpected keyword " << e.keyword << " at line " << e.line;
    }
  }
  EXPECT_EQ(stitches, 851);
  EXPECT_EQ(seams, 94);
  ASSERT_GE(obj.extra.size(), 2u);
  EXPECT_EQ(obj.extra[0].keyword, "seam");
  EXPECT_EQ(obj.extra[0].line, 60816);
  EXPECT_EQ(obj.extra[1].line, 60817);
  EXPECT_EQ(obj.extra[1].words, (std::vector<std::string>{"56", "37", "704", "0.000000e+000"}));
}

TEST(ObjFileShared, CipcDressDrapeSharesTheStageFaces) {
  const std::string stage = kShared + "/cloth/dress_knife_stage_cipc.obj";
  const std::string drape = kShared + "/garment/dress_drape_cipc.obj";
  if (!fs::exists(stage) || !fs::exists(drape)) GTEST_SKIP() << "shared data not present";
  const ObjFile s = read_obj_file(stage);
  const ObjFile d = read_obj_file(drape);
  EXPECT_EQ(d.v.rows(), 28467);
  EXPECT_EQ(d.vt.rows(), 0);
  ASSERT_EQ(d.faces.rows(), 54928);
  EXPECT_EQ(d.face_vt.minCoeff(), -1);
  EXPECT_EQ(d.face_vt.maxCoeff(), -1);
  EXPECT_EQ(d.faces.topRows(29456), s.faces);
}

TEST(ObjFileShared, ArcsimGarments) {
  const std::string robe = kShared + "/cloth/robe_arcsim.obj";
  const std::string tshirt = kShared + "/cloth/tshirt_arcsim.obj";
  if (!fs::exists(robe) || !fs::exists(tshirt)) GTEST_SKIP() << "shared data not present";
  const ObjFile r = read_obj_file(robe);
  EXPECT_EQ(r.v.rows(), 523);
  EXPECT_EQ(r.vt.rows(), 2820);
  ASSERT_EQ(r.faces.rows(), 940);
  EXPECT_GE(r.face_vt.minCoeff(), 0);
  EXPECT_LT(r.face_vt.maxCoeff(), 2820);
  EXPECT_EQ(r.groups, (std::vector<std::string>{""}));
  int vv = 0, t = 0;
  for (const ObjFile::Extra& e : r.extra) {
    if (e.keyword == "vv") ++vv;
    else if (e.keyword == "t") ++t;
    else ADD_FAILURE() << "unexpected keyword " << e.keyword << " at line " << e.line;
  }
  EXPECT_EQ(vv, 523);
  EXPECT_EQ(t, 940);
  ASSERT_FALSE(r.extra.empty());
  EXPECT_EQ(r.extra[0].keyword, "vv");
  EXPECT_EQ(r.extra[0].line, 2);
  EXPECT_EQ(r.extra[0].words, (std::vector<std::string>{"0", "0", "0"}));

  const ObjFile s = read_obj_file(tshirt);
  EXPECT_EQ(s.v.rows(), 330);
  EXPECT_EQ(s.vt.rows(), 426);
  EXPECT_EQ(s.faces.rows(), 604);
}
