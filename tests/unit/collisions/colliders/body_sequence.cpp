// Bodies from mesh sequences (collisions/body_sequence.hpp): frame patterns, the linear
// interpolation of positions and its velocities (hold, loop, start offset, transform), lazy
// streaming, errors naming the file, and a cloth carried by a moving mesh body through the World.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "invfem/collisions/colliders/body_sequence.hpp"
#include "invfem/collisions/colliders/rigid_body.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "invfem/collisions/self_collision/self_collision_pass.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "invfem/shells/cloth_object.hpp"
#include "invfem/shells/shapes.hpp"
#include "temp_dir.hpp"

namespace invfem {
namespace {

using test::TempDir;

std::string obj_text(const Points& x, const Tris& t) {
  std::ostringstream s;
  s.precision(17);
  for (Eigen::Index i = 0; i < x.rows(); ++i) s << "v " << x(i, 0) << ' ' << x(i, 1) << ' ' << x(i, 2) << '\n';
  for (Eigen::Index i = 0; i < t.rows(); ++i) s << "f " << t(i, 0) + 1 << ' ' << t(i, 1) + 1 << ' ' << t(i, 2) + 1 << '\n';
  return s.str();
}

// A box of half extents h centred at c, frame files "<stem><k>.obj" for the given centres.
std::vector<std::string> write_box_frames(const TempDir& dir, const std::string& stem, const Vec3& h,
                                          const std::vector<Vec3>& centres) {
  const TriangleSurface box = box_triangles(h);
  std::vector<std::string> files;
  for (std::size_t k = 0; k < centres.size(); ++k) {
    Points x = box.x;
    x.rowwise() += centres[k].transpose();
    files.push_back(dir.file(stem + std::to_string(k) + ".obj", obj_text(x, box.tris)));
  }
  return files;
}

Points box_at(const Vec3& h, const Vec3& c) {
  Points x = box_triangles(h).x;
  x.rowwise() += c.transpose();
  return x;
}

TEST(FramePattern, ExpandsPlainAndZeroPaddedNumbers) {
  EXPECT_EQ(expand_frame_pattern("body/shell{N}.obj", 9, 11),
            (std::vector<std::string>{"body/shell9.obj", "body/shell10.obj", "body/shell11.obj"}));
  EXPECT_EQ(expand_frame_pattern("frame_{N:04}.ply", 7, 8),
            (std::vector<std::string>{"frame_0007.ply", "frame_0008.ply"}));
  EXPECT_EQ(expand_frame_pattern("f{N:02}", 123, 123), std::vector<std::string>{"f123"});  // wider than the pad
}

TEST(FramePattern, RejectsBadPatternsNamingThem) {
  for (const std::string bad : {"frame.obj", "f{N}_{N}.obj", "f{M}.obj", "f{N:4}.obj", "f{N.obj", "f}{N}.obj",
                                "f{N:00}.obj"}) {
    try {
      expand_frame_pattern(bad, 0, 3);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(expand_frame_pattern("f{N}.obj", 3, 2), std::invalid_argument);
  EXPECT_THROW(expand_frame_pattern("f{N}.obj", -1, 2), std::invalid_argument);
}

struct Fixture {
  TempDir dir;
  Vec3 h{0.2, 0.1, 0.3};
  std::vector<Vec3> centres{{0, 0, 0}, {0.1, 0.05, 0}, {0.1, 0.25, -0.2}};
  std::vector<std::string> files = write_box_frames(dir, "box", h, centres);
};

TEST(BodySequence, InterpolatesPositionsAndVelocitiesAtAndBetweenFrames) {
  Fixture f;
  BodySequenceSettings s;
  s.files = f.files;
  s.fps = 10;
  s.start_time = 0.2;
  BodySequence b("box", s);
  EXPECT_NO_THROW(b.check_frames());
  const Points X0 = box_at(f.h, f.centres[0]), X1 = box_at(f.h, f.centres[1]), X2 = box_at(f.h, f.centres[2]);
  auto expect_at = [&](double t, const Points& x, const Points& v) {
    b.move_to(t);
    EXPECT_LT((b.surface()->x - x).cwiseAbs().maxCoeff(), 1e-12) << "t = " << t;
    EXPECT_LT((b.velocities() - v).cwiseAbs().maxCoeff(), 1e-9) << "t = " << t;
  };
  const Points zero = Points::Zero(X0.rows(), 3);
  expect_at(0.0, X0, zero);                              // before the start: frame 0, still
  expect_at(0.2, X0, (X1 - X0) * 10);                    // frame 0, and the interval it starts
  expect_at(0.225, 0.75 * X0 + 0.25 * X1, (X1 - X0) * 10);
  expect_at(0.3, X1, (X2 - X1) * 10);                    // frame 1 exactly
  expect_at(0.35, 0.5 * X1 + 0.5 * X2, (X2 - X1) * 10);
  expect_at(0.4, X2, zero);                              // the last frame: held
  expect_at(7.0, X2, zero);
  // The collision surface sees the same pose and the interpolation's velocity (not a finite
  // difference over the last move): a point just above the top face.
  b.move_to(0.35);
  const Vec3 top = 0.5 * (f.centres[1] + f.centres[2]) + Vec3(0, f.h.y() + 0.01, 0);
  const MeshClosestPoint c = b.mesh_surface().closest(top);
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.phi, 0.01, 1e-12);
  EXPECT_LT((c.velocity - (f.centres[2] - f.centres[1]) * 10).norm(), 1e-9);
  EXPECT_LT((b.implicit()->velocity(top, 0.35) - (f.centres[2] - f.centres[1]) * 10).norm(), 1e-9);
}

// The World's settle phase holds a body at a pose at rest (KinematicBody::hold_at): the pose of
// that time, and zero velocities for the output and for the collision surface; moved again to the
// same time, it has the animation's velocity back.
TEST(BodySequence, HeldAtATimeItKeepsThatPoseAtRest) {
  Fixture f;
  BodySequenceSettings s;
  s.files = f.files;
  s.fps = 10;
  BodySequence b("box", s);
  const Points X0 = box_at(f.h, f.centres[0]), X1 = box_at(f.h, f.centres[1]);
  const Vec3 top = f.centres[0] + Vec3(0, f.h.y() + 0.01, 0);
  b.hold_at(0.0);
  EXPECT_EQ(b.surface()->x, X0);
  EXPECT_TRUE(b.velocities().isZero(0));
  EXPECT_TRUE(b.surface_velocities().isZero(0));
  EXPECT_EQ(b.implicit()->velocity(top, 0.0), Vec3::Zero());
  b.move_to(0.0);  // the same time, moving: frame 0 and the interval it starts
  EXPECT_EQ(b.surface()->x, X0);
  EXPECT_LT((b.velocities() - (X1 - X0) * 10).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((b.implicit()->velocity(top, 0.0) - (f.centres[1] - f.centres[0]) * 10).norm(), 1e-9);
  b.hold_at(0.05);  // halfway to frame 1, at rest
  EXPECT_LT((b.surface()->x - 0.5 * (X0 + X1)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_TRUE(b.velocities().isZero(0));
}

TEST(BodySequence, LoopsBackToTheFirstFrameThroughAWrapInterval) {
  Fixture f;
  BodySequenceSettings s;
  s.files = f.files;
  s.fps = 10;
  s.after_end = AnimationEnd::Loop;
  BodySequence b("box", s);
  const Points X0 = box_at(f.h, f.centres[0]), X1 = box_at(f.h, f.centres[1]), X2 = box_at(f.h, f.centres[2]);
  b.move_to(0.25);  // the wrap interval [2, 3): last frame back to the first
  EXPECT_LT((b.surface()->x - (0.5 * X2 + 0.5 * X0)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((b.velocities() - (X0 - X2) * 10).cwiseAbs().maxCoeff(), 1e-9);
  b.move_to(0.3);  // one period: frame 0 again, moving towards frame 1
  EXPECT_LT((b.surface()->x - X0).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((b.velocities() - (X1 - X0) * 10).cwiseAbs().maxCoeff(), 1e-9);
  b.move_to(3.0 + 0.15);  // ten periods on, halfway from frame 1 to 2
  EXPECT_LT((b.surface()->x - (0.5 * X1 + 0.5 * X2)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((b.velocities() - (X2 - X1) * 10).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(BodySequence, StartOffsetAndTransformApplyToPositionsAndVelocities) {
  Fixture f;
  BodySequenceSettings s;
  s.files = f.files;
  s.fps = 25;
  s.start_time = -1.0 / 25;  // start at frame 1 (a scene's start_frame: 1)
  const Mat3 R = Eigen::AngleAxisd(0.5 * M_PI, Vec3::UnitZ()).toRotationMatrix();
  s.linear = 2.0 * R;
  s.translation = Vec3(1, 2, 3);
  BodySequence b("box", s);
  auto world = [&](const Points& X) {
    Points x = X;
    for (Eigen::Index i = 0; i < x.rows(); ++i) x.row(i) = (s.linear * X.row(i).transpose() + s.translation).transpose();
    return x;
  };
  const Points X1 = box_at(f.h, f.centres[1]), X2 = box_at(f.h, f.centres[2]);
  EXPECT_LT((b.surface()->x - world(X1)).cwiseAbs().maxCoeff(), 1e-12);  // t = 0 shows frame 1
  b.move_to(0.02);                                                        // half a frame on
  EXPECT_LT((b.surface()->x - world(0.5 * X1 + 0.5 * X2)).cwiseAbs().maxCoeff(), 1e-12);
  Points v = (X2 - X1) * 25;
  for (Eigen::Index i = 0; i < v.rows(); ++i) v.row(i) = (s.linear * v.row(i).transpose()).transpose();
  EXPECT_LT((b.velocities() - v).cwiseAbs().maxCoeff(), 1e-9);
  // A rotation of +90 degrees about z sends the body's +x motion to +y, doubled.
  EXPECT_NEAR(b.velocities()(0, 1), 2 * 25 * (f.centres[2] - f.centres[1]).x(), 1e-9);
}

// Frames from a function (the Python module's drive_body) move the body exactly as the same
// frames from files: the same interpolation and transform, bit for bit; a wrong vertex count or a
// non-finite vertex is reported naming the source; an empty source returns to the files.
TEST(BodySequence, AFrameSourceMovesTheBodyAsTheSameFramesFromFiles) {
  Fixture f;
  BodySequenceSettings s;
  s.files = f.files;
  s.fps = 10;
  s.translation = Vec3(0, 1, 0);
  BodySequence files("box", s), driven("box", s);
  int calls = 0;
  driven.set_frame_source(
      [&](int k) {
        ++calls;
        return box_at(f.h, f.centres[static_cast<std::size_t>(k)]);
      },
      "the test's frames");
  EXPECT_EQ(calls, 2);  // placed again at t = 0: frames 0 and 1
  for (double t : {0.0, 0.05, 0.1, 0.125, 0.2, 0.3}) {
    files.move_to(t);
    driven.move_to(t);
    EXPECT_EQ(driven.surface()->x, files.surface()->x) << "t = " << t;
    EXPECT_EQ(driven.velocities(), files.velocities()) << "t = " << t;
  }
  BodySequence wrong("box", s);
  try {  // placing the body at t = 0 needs frame 1 already
    wrong.set_frame_source([&](int k) { return k == 0 ? box_at(f.h, f.centres[0]) : Points(Points::Zero(3, 3)); },
                           "wrong frames");
    FAIL() << "a frame with 3 vertices was taken";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("wrong frames, frame 1: 3 vertices"), std::string::npos) << e.what();
  }
  Points bad = box_at(f.h, f.centres[1]);
  bad(2, 1) = std::nan("");
  EXPECT_THROW(wrong.set_frame_source([&](int) { return bad; }, "NaN frames"), MeshError);
  wrong.set_frame_source({}, "");
  wrong.move_to(0.15);
  files.move_to(0.15);
  EXPECT_EQ(wrong.surface()->x, files.surface()->x);
}

TEST(BodySequence, StreamsFramesLazilyWithASmallCache) {
  TempDir dir;
  std::vector<Vec3> centres;
  for (int k = 0; k < 300; ++k) centres.emplace_back(0.01 * k, std::sin(0.1 * k), 0);
  BodySequenceSettings s;
  s.files = write_box_frames(dir, "f", Vec3(0.1, 0.1, 0.1), centres);
  s.fps = 30;
  BodySequence b("box", s);
  EXPECT_EQ(b.frames_loaded(), 2);  // t = 0 starts the interval [0, 1): frames 0 and 1
  // Substeps of a third of a frame through the whole sequence: each frame is read once.
  for (int i = 0; i <= 3 * 299; ++i) {
    b.move_to(i / 90.0);
    ASSERT_LE(b.frames_cached(), 3u);
  }
  EXPECT_LE(b.frames_loaded(), 300);
  EXPECT_GE(b.frames_loaded(), 299);
  // Going back and forth inside one interval reads nothing new.
  const long long before = b.frames_loaded();
  b.move_to(100.0 / 30 + 0.001);
  const long long jumped = b.frames_loaded();
  EXPECT_LE(jumped - before, 2);
  for (int i = 0; i < 20; ++i) b.move_to(100.0 / 30 + 0.001 * (i % 5));
  EXPECT_EQ(b.frames_loaded(), jumped);
}

TEST(BodySequence, ReadsObjFramesInFileOrderWithoutWelding) {
  // Frame 1 puts vertex 0 on vertex 1 (two body points touching) and lists an unreferenced
  // vertex: assimp's loader would weld the pair and drop the stray vertex, changing the count.
  TempDir dir;
  const TriangleSurface box = box_triangles(Vec3(0.1, 0.1, 0.1));
  Points x0(box.x.rows() + 1, 3), x1;
  x0 << box.x, Eigen::RowVector3d(1, 1, 1);
  x1 = x0;
  x1.row(0) = x1.row(1);
  BodySequenceSettings s;
  s.files = {dir.file("a.obj", obj_text(x0, box.tris)), dir.file("b.obj", obj_text(x1, box.tris))};
  s.fps = 1;
  BodySequence b("box", s);
  b.move_to(1.0);
  ASSERT_EQ(b.surface()->x.rows(), x0.rows());
  EXPECT_EQ(b.surface()->x, x1);
  EXPECT_EQ(b.surface()->tris, box.tris);
}

TEST(BodySequence, ReadsOtherFormatsThroughAssimp) {
  // ASCII PLY frames of a box moving +y: the interpolation halfway is the box halfway.
  TempDir dir;
  const TriangleSurface box = box_triangles(Vec3(0.1, 0.2, 0.3));
  auto ply = [&](double dy) {
    std::ostringstream o;
    o << "ply\nformat ascii 1.0\nelement vertex " << box.x.rows() << "\nproperty float x\nproperty float y\n"
      << "property float z\nelement face " << box.tris.rows() << "\nproperty list uchar int vertex_indices\n"
      << "end_header\n";
    for (Eigen::Index i = 0; i < box.x.rows(); ++i) o << box.x(i, 0) << ' ' << box.x(i, 1) + dy << ' ' << box.x(i, 2) << '\n';
    for (Eigen::Index t = 0; t < box.tris.rows(); ++t) o << "3 " << box.tris(t, 0) << ' ' << box.tris(t, 1) << ' ' << box.tris(t, 2) << '\n';
    return o.str();
  };
  BodySequenceSettings s;
  s.files = {dir.file("f_0000.ply", ply(0)), dir.file("f_0001.ply", ply(1))};
  s.fps = 4;
  BodySequence b("box", s);
  b.move_to(0.125);
  ASSERT_EQ(b.surface()->x.rows(), 8);
  EXPECT_NEAR(b.surface()->x.col(1).minCoeff(), 0.3, 1e-6);
  EXPECT_NEAR(b.surface()->x.col(1).maxCoeff(), 0.7, 1e-6);
  EXPECT_NEAR(b.velocities().col(1).minCoeff(), 4.0, 1e-6);
  EXPECT_NEAR(b.velocities().col(1).maxCoeff(), 4.0, 1e-6);
}

// What a bad frame's error says: the file, and that it is frame 0's topology that it breaks.
void expect_bad_frame(BodySequence& b, double t, const std::string& file, const std::string& words) {
  const Points before = b.surface()->x;
  try {
    b.move_to(t);
    ADD_FAILURE() << "no error for " << file;
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
  EXPECT_EQ(b.surface()->x, before);  // left where it was
  EXPECT_TRUE(b.velocities().allFinite());
}

TEST(BodySequence, BadFramesAreReportedNamingTheFile) {
  Fixture f;
  const TriangleSurface box = box_triangles(f.h);
  // Frame 2: one vertex more.
  Points more(box.x.rows() + 1, 3);
  more << box.x, Eigen::RowVector3d(5, 5, 5);
  BodySequenceSettings s;
  s.fps = 10;
  s.files = {f.files[0], f.files[1], f.dir.file("more.obj", obj_text(more, box.tris))};
  {
    BodySequence b("box", s);
    // check_frames finds it ahead of time, and leaves the streaming as it was.
    const long long loaded = b.frames_loaded();
    EXPECT_THROW(b.check_frames(), MeshError);
    EXPECT_EQ(b.frames_loaded(), loaded);
    expect_bad_frame(b, 0.15, s.files[2], "9 vertices, but frame 0");
  }
  // Other triangles (two corners of one swapped).
  Tris swapped = box.tris;
  std::swap(swapped(3, 0), swapped(3, 1));
  s.files[2] = f.dir.file("swapped.obj", obj_text(box.x, swapped));
  {
    BodySequence b("box", s);
    expect_bad_frame(b, 0.15, s.files[2], "triangle 3 is");
  }
  // A NaN coordinate.
  const std::string text = obj_text(box.x, box.tris);
  s.files[2] = f.dir.file("nan.obj", "v 0 nan 0\n" + text.substr(text.find('\n') + 1));
  {
    BodySequence b("box", s);
    expect_bad_frame(b, 0.15, s.files[2], "nan");
  }
  // A missing file.
  s.files[2] = (f.dir.path("absent.obj")).string();
  {
    BodySequence b("box", s);
    expect_bad_frame(b, 0.15, s.files[2], "absent.obj");
  }
  // A missing first frame fails at construction.
  s.files[0] = (f.dir.path("absent0.obj")).string();
  try {
    BodySequence b("box", s);
    ADD_FAILURE() << "no error";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("absent0.obj"), std::string::npos) << e.what();
  }
  // Bad settings.
  s.files = f.files;
  s.fps = 0;
  EXPECT_THROW(BodySequence("box", s), std::invalid_argument);
  s.fps = 10;
  s.files.clear();
  EXPECT_THROW(BodySequence("box", s), std::invalid_argument);
}

// A World as the app builds it for a cloth over a body: the implicit integrator, the body's mesh
// surface in the collision processing, and the self-collision layer with the body's triangles.
World cloth_world(SimObject cloth, const std::shared_ptr<BodySequence>& body, double max_dt) {
  WorldSettings settings;
  settings.max_dt = max_dt;
  settings.integrator = Integrator::Implicit;
  std::vector<SimObject> objects;
  objects.push_back(std::move(cloth));
  auto collisions = std::make_unique<RigidCollisions>(std::vector<RigidCollider>{{body->implicit(), body->friction()}});
  World world(settings, std::move(objects), {body}, std::move(collisions));
  world.add_pass(std::make_unique<collisions::SelfCollisionPass>(collisions::SelfCollisionSettings{}));
  return world;
}

ClothObjectParams cloth_params() {
  ClothObjectParams p;
  const double E = 1e5, nu = 0.3;
  p.model = RotatedLinear{E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))};
  p.thickness = 0.001;
  p.density = 300;
  p.damping = 0.01;
  p.bending = BendingParams{1e-5, 1e-6};
  return p;
}

TEST(BodySequence, ClothRestingOnAMovingBodyIsCarriedWithoutPassingThrough) {
  // A box 0.6 x 0.2 x 0.6 m slides sideways at 0.2 m/s and rises at 0.1 m/s (10 frames per
  // second, 2 s); a 0.3 m cloth square rests on its top, friction 0.6.
  TempDir dir;
  const Vec3 h(0.3, 0.1, 0.3);
  std::vector<Vec3> centres;
  for (int k = 0; k <= 20; ++k) centres.emplace_back(0.02 * k, 0.01 * k, 0);
  BodySequenceSettings s;
  s.files = write_box_frames(dir, "box", h, centres);
  s.fps = 10;
  s.friction = 0.6;
  s.mesh.query_radius = 0.05;
  auto body = std::make_shared<BodySequence>("box", s);
  const TriangleSurface grid = make_grid(0.3, 0.3, 8, 8, Vec3(-0.15, h.y() + 0.002, 0.15), Vec3::UnitX(), -Vec3::UnitZ());
  World world = cloth_world(make_cloth_object("cloth", grid, cloth_params()), body, 0.02);
  const Vec3 start = world.objects()[0].body.x.colwise().mean().transpose();
  int unresolved = 0;
  for (int frame = 1; frame <= 40; ++frame) {
    FrameReport r;
    world.advance_to(frame / 20.0, r);
    unresolved += collisions::SelfCollisionFigures::of(r).unresolved_steps;
    ASSERT_TRUE(world.state_is_finite()) << "frame " << frame;
    const Points& x = world.objects()[0].body.x;
    double worst = INFINITY;
    for (Eigen::Index i = 0; i < x.rows(); ++i) worst = std::min(worst, body->mesh_surface().closest(x.row(i).transpose()).phi);
    EXPECT_GT(worst, -1e-4) << "a cloth vertex is inside the body at frame " << frame;
  }
  EXPECT_EQ(unresolved, 0);
  // Carried: the cloth moved with the box (0.4 m sideways, 0.2 m up) and still lies on its top.
  const Vec3 moved = world.objects()[0].body.x.colwise().mean().transpose() - start;
  EXPECT_NEAR(moved.x(), 0.4, 0.02);
  EXPECT_NEAR(moved.y(), 0.2, 0.01);
  EXPECT_NEAR(moved.z(), 0.0, 0.01);
}

// A cloth pinned at its corners, 0.5 m up; a box below it jumps in one frame (1/10 s) to above it,
// passing through. Returns the unresolved steps the self-collision layer reported; fails the test
// for an exception or a non-finite state, or for a cloth vertex left inside the box unreported.
int run_teleport(double box_half_width) {
  TempDir dir;
  const Vec3 h(box_half_width, 0.05, box_half_width);
  BodySequenceSettings s;
  s.files = write_box_frames(dir, "jump", h, {Vec3(0, 0.3, 0), Vec3(0, 0.3, 0), Vec3(0, 0.8, 0), Vec3(0, 0.8, 0)});
  s.fps = 10;
  s.mesh.query_radius = 0.05;
  auto body = std::make_shared<BodySequence>("box", s);
  const TriangleSurface grid = make_grid(0.4, 0.4, 8, 8, Vec3(-0.2, 0.5, 0.2), Vec3::UnitX(), -Vec3::UnitZ());
  ClothObjectParams p = cloth_params();
  PinGroup corners;
  corners.nodes = {0, 8, 72, 80};
  corners.anchors.resize(4, 3);
  for (int k = 0; k < 4; ++k) corners.anchors.row(k) = grid.x.row(corners.nodes[k]);
  p.pins.push_back(corners);
  World world = cloth_world(make_cloth_object("cloth", grid, p), body, 0.025);
  int unresolved = 0, inside_frames = 0;
  for (int frame = 1; frame <= 8; ++frame) {
    FrameReport r;
    EXPECT_NO_THROW(world.advance_to(frame / 20.0, r));
    unresolved += collisions::SelfCollisionFigures::of(r).unresolved_steps;
    EXPECT_TRUE(world.state_is_finite()) << "frame " << frame;
    if (!world.state_is_finite()) return unresolved;
    const Points& x = world.objects()[0].body.x;
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      if (body->mesh_surface().closest(x.row(i).transpose()).phi < -1e-3) {
        ++inside_frames;
        break;
      }
  }
  std::printf("teleport (box half width %.2f m): %d unresolved steps, %d frames with a cloth vertex inside the box, "
              "cloth top y %.3f\n", box_half_width, unresolved, inside_frames, world.objects()[0].body.x.col(1).maxCoeff());
  EXPECT_TRUE(inside_frames == 0 || unresolved > 0) << "the cloth went into the box without a fail-safe report";
  return unresolved;
}

TEST(BodySequence, ATeleportingFrameNeitherFailsTheRunNorMakesNaNs) {
  // A box narrower than the pinned corners: the collision layers carry the cloth up with it.
  run_teleport(0.1);
  // A box wider than the cloth sweeps through its pinned corners: nothing can move out of its
  // way, the fail-safe must say so, and the run goes on.
  EXPECT_GT(run_teleport(0.25), 0);
}

}  // namespace
}  // namespace invfem
