#include "inspect_command.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <set>

#include "cli_args.hpp"
#include "invfem/collisions/colliders/skinned_body.hpp"
#include "invfem/collisions/colliders/skinning.hpp"
#include "invfem/core/io/input_file.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/core/io/skinned_file.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/solids/boundary.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "json_reader.hpp"
#include "object_builders.hpp"
#include "scene_parsing.hpp"

namespace invfem::app {

const char* const kInspectHelp =
    "usage: invfem inspect FILE [--transform JSON] [--json]\n"
    "\n"
    "What a mesh, a garment or a rigged character holds, to place it in a scene: vertices and\n"
    "triangles (and tets, for a .vtk/.mesh/.msh tet mesh: its triangles are its boundary's), the\n"
    "bounds and size in metres after the transform, the likely up axis, the bones (count, the top of\n"
    "the skeleton), the animation clips (length in seconds, keys, and how far each ends from its\n"
    "first pose: the jump after_end \"loop\" makes without loop_blend), and for an OBJ its UVs (vt),\n"
    "panels (g groups) and stitch lines. A rigged character's bounds are its bind pose's and its\n"
    "first clip's first pose's (a skinned collider shows the first at t = 0 with a pre_roll, the\n"
    "second without).\n"
    "\n"
    "  --transform JSON  the scene's transform block, as on a collider or a cloth, e.g.\n"
    "                    '{\"scale\": 0.01, \"rotate_degrees\": [-90, 0, 0], \"translate\": [0, 1, 0]}'\n"
    "  --json            the same as one JSON object on stdout\n"
    "\n"
    "Files: OBJ (read as a garment is, in file order), tet meshes (.vtk, .mesh, .msh), and anything\n"
    "else assimp reads (glTF, FBX, Collada, .x, PLY, STL, ...).\n"
    "The likely up axis: a rigged character's from its leg joints (bones named leg, knee, ankle, foot,\n"
    "toe, ...) toward its root bone (a biped's and a quadruped's legs hang below their hips and spine),\n"
    "else from its root bone toward its head or neck, else toward the mean of its other joints; a mesh\n"
    "tells no sign: its longest extent (a standing figure's height), or for a flat one its normal (a\n"
    "sheet laid out level).\n"
    "Exit code 0, or 2 with a message naming the file and the problem.\n";

namespace {

struct Box {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  Vec3 size() const { return hi - lo; }
};

Box box_of(const Points& x) {
  if (x.rows() == 0) return {};
  return {x.colwise().minCoeff().transpose(), x.colwise().maxCoeff().transpose()};
}

struct UpAxis {
  std::string axis;    // "+y", "-z"; "y" when a mesh tells no sign; "" when unknown
  std::string reason;
};

struct ClipFacts {
  std::string name;
  double seconds = 0;
  int channels = 0;
  int keys = 0;  // the most keys of one channel
  std::optional<LoopJump> jump;  // [m] after the transform (a character with bones)
  std::optional<Box> first_pose;
};

struct ObjExtras {
  long long vt = 0, faces_with_vt = 0, stitches = 0;
  std::map<std::string, int> other_lines;  // keyword -> lines the garment reader does not use
};

// What `invfem inspect` says of a file; positions after the transform.
struct Facts {
  std::string file, kind;
  long long vertices = 0, triangles = 0;
  std::optional<long long> tets;
  Box bounds;
  std::string pose;            // what the bounds are of, for a character
  std::optional<Box> clip_start;  // a character at its first clip's start
  UpAxis up;
  int bones = 0;
  std::vector<std::string> top_bones, below_top;  // bones with no bone above; those below the first
  std::vector<ClipFacts> clips;
  std::vector<std::string> panels;  // an OBJ's g/o groups; assimp's meshes
  std::optional<ObjExtras> obj;
};

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return e;
}

Mat3 linear_of(const Transform& t) { return t.scale * rotation_of(t); }

// A mesh tells an axis but no sign: its normal when it is flat (its smallest extent under 2% of
// its largest: a sheet, a garment laid out), else its longest extent when that stands out (1.25
// times the next: a standing figure is several times taller than it is deep, while a ball, a cube
// or a torus lying flat has no such axis).
UpAxis extent_axis(const Box& b) {
  Vec3 e = b.size();
  Eigen::Index big = 0, small = 0;
  const double longest = e.maxCoeff(&big);
  e.minCoeff(&small);
  if (!(longest > 0)) return {};
  const std::string axes = "xyz";
  if (e[small] < 0.02 * longest)
    return {std::string(1, axes[small]), "the normal of a flat mesh (a sheet laid out level); the sign is not told"};
  e[big] = 0;
  if (longest < 1.25 * e.maxCoeff()) return {};
  return {std::string(1, axes[big]), "its longest extent, as a standing figure's height; the sign is not told"};
}

int node_depth(const SkinnedCharacter& c, int n) {
  int d = 0;
  for (; c.nodes[static_cast<std::size_t>(n)].parent >= 0; n = c.nodes[static_cast<std::size_t>(n)].parent) ++d;
  return d;
}

// The nodes the bones deform with, shallowest first (file order among equals).
std::vector<int> bone_nodes(const SkinnedCharacter& c) {
  std::set<int> set;
  for (const Bone& b : c.bones) set.insert(b.node);
  std::vector<int> nodes(set.begin(), set.end());
  std::stable_sort(nodes.begin(), nodes.end(), [&](int a, int b) { return node_depth(c, a) < node_depth(c, b); });
  return nodes;
}

// Whether a bone's name holds one of `parts` (lower case), as rigs name legs and heads.
bool named(std::string name, std::initializer_list<const char*> parts) {
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return std::any_of(parts.begin(), parts.end(), [&](const char* p) { return name.find(p) != std::string::npos; });
}

bool leg_bone(const std::string& name) {
  return named(name, {"leg", "knee", "ankle", "foot", "toe", "heel", "thigh", "shin", "calf"});
}
bool head_bone(const std::string& name) { return named(name, {"head", "neck"}); }

// The likely up axis of a rig at rest: from its leg joints toward its root bone (a biped's and a
// quadruped's legs hang below their hips and spine, in any rest pose), else from the root bone
// toward its head and neck, else toward the mean of its other joints (most of a biped's joints,
// spine, arms and hands, lie above its hips). The axis is the direction's largest component.
UpAxis skeleton_up(const SkinnedCharacter& c, const Mat3& linear) {
  const std::vector<int> nodes = bone_nodes(c);
  if (nodes.size() < 2) return {};
  const SkeletonPose rest = pose_skeleton(c, nullptr, 0);
  auto name = [&](int n) -> const std::string& { return c.nodes[static_cast<std::size_t>(n)].name; };
  auto joint = [&](int n) { return Vec3(linear * rest.global[static_cast<std::size_t>(n)].block<3, 1>(0, 3)); };
  // The mean of the joints below the root whose names `keep` accepts, and their count.
  auto mean_of = [&](bool (*keep)(const std::string&), int& count) {
    Vec3 sum = Vec3::Zero();
    count = 0;
    for (std::size_t k = 1; k < nodes.size(); ++k)
      if (keep(name(nodes[k]))) {
        sum += joint(nodes[k]);
        ++count;
      }
    return count > 0 ? Vec3(sum / count) : sum;
  };
  const int root = nodes.front();
  const std::string root_text = "its root bone \"" + name(root) + "\"";
  int count = 0;
  Vec3 d;
  std::string reason;
  if (const Vec3 legs = mean_of(leg_bone, count); count > 0) {
    d = joint(root) - legs;
    reason = "from its " + std::to_string(count) + " leg joints (bones named leg, knee, ankle, foot, toe, ...) toward " +
             root_text;
  } else if (const Vec3 head = mean_of(head_bone, count); count > 0) {
    d = head - joint(root);
    reason = "from " + root_text + " toward its " + std::to_string(count) + " head and neck joints";
  } else {
    d = mean_of([](const std::string&) { return true; }, count) - joint(root);
    reason = "from " + root_text + " toward the mean of its other " + std::to_string(count) + " joints";
  }
  Eigen::Index i = 0;
  if (!(d.cwiseAbs().maxCoeff(&i) > 0)) return {};
  return {std::string(d[i] > 0 ? "+" : "-") + "xyz"[i], reason + ", at rest"};
}

// The bone above node n, or -1 (nodes between bones, such as a scene's root, are skipped).
int bone_above(const SkinnedCharacter& c, const std::set<int>& bones, int n) {
  for (int p = c.nodes[static_cast<std::size_t>(n)].parent; p >= 0; p = c.nodes[static_cast<std::size_t>(p)].parent)
    if (bones.count(p)) return p;
  return -1;
}

// The skeleton's top: its top bones, and the bones just below the first of them.
void skeleton_top(const SkinnedCharacter& c, Facts& f) {
  const std::vector<int> nodes = bone_nodes(c);
  const std::set<int> bones(nodes.begin(), nodes.end());
  for (int n : nodes) {
    const int above = bone_above(c, bones, n);
    if (above < 0) f.top_bones.push_back(c.nodes[static_cast<std::size_t>(n)].name);
    else if (above == nodes.front()) f.below_top.push_back(c.nodes[static_cast<std::size_t>(n)].name);
  }
}

Points placed(Points x, const Transform& t, const std::string& file) {
  apply_transform(t, x, file);
  return x;
}

ClipFacts clip_facts(const SkinnedCharacter& c, int k, const Transform& t, bool posed) {
  const AnimationClip& clip = c.clips[static_cast<std::size_t>(k)];
  ClipFacts f;
  f.name = clip.name;
  f.seconds = clip.duration;
  f.channels = static_cast<int>(clip.tracks.size());
  for (const NodeTrack& track : clip.tracks)
    f.keys = std::max({f.keys, static_cast<int>(track.position_times.size()), static_cast<int>(track.rotation_times.size()),
                       static_cast<int>(track.scale_times.size())});
  if (!posed) return f;
  f.jump = loop_jump(c, k, linear_of(t));
  Points x;
  skin_vertices(c, pose_skeleton(c, &clip, 0), x);
  f.first_pose = box_of(placed(std::move(x), t, c.source));
  return f;
}

Facts character_facts(const SkinnedCharacter& c, const Transform& t) {
  Facts f;
  f.kind = "rigged character";
  f.vertices = c.bind.rows();
  f.triangles = c.tris.rows();
  f.bounds = box_of(placed(bind_pose(c), t, c.source));
  f.pose = "bind pose";
  f.up = skeleton_up(c, linear_of(t));
  if (f.up.axis.empty()) f.up = extent_axis(f.bounds);  // a rig too small to tell
  f.bones = static_cast<int>(bone_nodes(c).size());
  skeleton_top(c, f);
  for (int k = 0; k < static_cast<int>(c.clips.size()); ++k) f.clips.push_back(clip_facts(c, k, t, true));
  if (!f.clips.empty()) f.clip_start = f.clips.front().first_pose;
  f.panels = c.groups;
  return f;
}

// What a file without a rig tells alike: its kind, vertices (X, #V x 3) and triangles, its bounds
// after the transform, and the up axis its extent suggests.
Facts mesh_facts(const char* kind, const Points& X, long long triangles, const Transform& t, const std::string& path) {
  Facts f;
  f.kind = kind;
  f.vertices = X.rows();
  f.triangles = triangles;
  f.bounds = box_of(placed(X, t, path));
  f.up = extent_axis(f.bounds);
  return f;
}

// A file without bones, as a mesh collider, a solid or a cloth reads it (welded); its clips (node
// animation) are listed, though a skinned collider needs bones.
Facts surface_facts(const std::string& path, const Transform& t, const SkinnedCharacter* read) {
  SurfaceLoadReport report;
  const TriangleSurface s = load_triangle_surface(path, &report);
  Facts f = mesh_facts("mesh", s.x, s.tris.rows(), t, path);
  f.panels = report.groups;
  if (read)
    for (int k = 0; k < static_cast<int>(read->clips.size()); ++k) f.clips.push_back(clip_facts(*read, k, t, false));
  return f;
}

Facts obj_facts(const std::string& path, const Transform& t) {
  const ObjFile obj = read_obj_file(path);
  Facts f = mesh_facts("OBJ", obj.v, obj.faces.rows(), t, path);
  f.panels = obj.groups;
  ObjExtras e;
  e.vt = obj.vt.rows();
  for (Eigen::Index i = 0; i < obj.face_vt.rows(); ++i) e.faces_with_vt += obj.face_vt(i, 0) >= 0;
  for (const ObjFile::Extra& x : obj.extra) {
    if (x.keyword == "stitch") ++e.stitches;
    else ++e.other_lines[x.keyword];
  }
  f.obj = e;
  return f;
}

Facts tet_mesh_facts(const std::string& path, const Transform& t) {
  const TetMesh mesh = read_tet_mesh(path);
  Facts f = mesh_facts("tet mesh", mesh.X, face_sharing(mesh.tets).boundary, t, path);
  f.tets = mesh.tets.rows();
  return f;
}

Facts file_facts(const std::string& path, const Transform& t) {
  try {
    check_input_file(path);
    const std::string e = lower_extension(path);
    Facts f;
    if (e == ".vtk" || e == ".mesh" || e == ".msh") f = tet_mesh_facts(path, t);
    else if (e == ".obj") f = obj_facts(path, t);
    else if (e == ".ply" || e == ".stl" || e == ".off") f = surface_facts(path, t, nullptr);  // no rig in these
    else {
      const SkinnedCharacter c = read_skinned_character(path, {.require_rig = false});
      f = c.bones.empty() ? surface_facts(path, t, &c) : character_facts(c, t);
    }
    f.file = path;
    return f;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // the readers' messages name the file
    throw InputError(e.what());
  }
}

// ---- output ----

std::string num(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.4g", x);
  return s;
}

std::string vec(const Vec3& v) { return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]"; }

std::string box_text(const Box& b) {
  const Vec3 s = b.size();
  return vec(b.lo) + " to " + vec(b.hi) + " m, size " + num(s.x()) + " x " + num(s.y()) + " x " + num(s.z()) + " m";
}

std::string quoted_list(const std::vector<std::string>& names, std::size_t shown = 8) {
  std::string s;
  for (std::size_t k = 0; k < names.size() && k < shown; ++k) s += (k ? ", \"" : "\"") + names[k] + "\"";
  if (names.size() > shown) s += " and " + std::to_string(names.size() - shown) + " more";
  return s;
}

bool rotated(const Transform& t) { return t.rotate_degrees != std::array<double, 3>{0, 0, 0}; }

// The rotation that turns a likely up axis to +y (rotation_of: about x, then y, then z).
std::string turn_to_y(const std::string& axis) {
  static const std::map<std::string, std::string> turn = {
      {"+z", "[-90, 0, 0]"}, {"-z", "[90, 0, 0]"}, {"+x", "[0, 0, 90]"}, {"-x", "[0, 0, -90]"}, {"-y", "[180, 0, 0]"}};
  const auto found = turn.find(axis);
  return found == turn.end() ? "" : found->second;
}

void print_geometry(const Facts& f, const Transform& t) {
  std::printf("  vertices   %lld\n  triangles  %lld%s\n", f.vertices, f.triangles, f.tets ? " (its boundary)" : "");
  if (f.tets) std::printf("  tets       %lld\n", *f.tets);
  std::printf("  bounds     %s%s\n", box_text(f.bounds).c_str(), f.pose.empty() ? "" : (" (" + f.pose + ")").c_str());
  if (f.clip_start)
    std::printf("             %s (clip 0's first pose)\n", box_text(*f.clip_start).c_str());
  if (f.bounds.size().maxCoeff() > 10)
    std::printf("  note: %s m across; a file in centimetres takes \"transform\": {\"scale\": 0.01}\n",
                num(f.bounds.size().maxCoeff()).c_str());
  if (f.up.axis.empty()) std::printf("  likely up  not told (no flat side, no extent stands out)\n");
  if (!f.up.axis.empty()) {
    std::printf("  likely up  %s: %s\n", f.up.axis.c_str(), f.up.reason.c_str());
    if (const std::string turn = turn_to_y(f.up.axis); !turn.empty() && !rotated(t))
      std::printf("  scenes are y-up (gravity -y): \"rotate_degrees\": %s turns %s to +y\n", turn.c_str(),
                  f.up.axis.c_str());
  }
}

void print_rig(const Facts& f) {
  if (f.bones > 0 || f.kind == "rigged character")
    std::printf("  bones      %d%s%s\n", f.bones, f.top_bones.empty() ? "" : ("; top " + quoted_list(f.top_bones)).c_str(),
                f.below_top.empty() ? "" : (", below it " + quoted_list(f.below_top)).c_str());
  if (f.clips.empty()) {
    if (f.kind == "rigged character") std::printf("  clips      none\n");
    return;
  }
  std::printf("  clips      %zu%s\n", f.clips.size(), f.bones > 0 ? "" : " (node animation: a skinned collider needs bones)");
  for (std::size_t k = 0; k < f.clips.size(); ++k) {
    const ClipFacts& c = f.clips[k];
    std::printf("    %zu \"%s\": %s s, %d key%s (%d channel%s)", k, c.name.c_str(), num(c.seconds).c_str(), c.keys,
                c.keys == 1 ? "" : "s", c.channels, c.channels == 1 ? "" : "s");
    if (c.jump && c.jump->distance > 0)
      std::printf(", ends %s cm from its first pose (vertex %lld)", num(100 * c.jump->distance).c_str(),
                  static_cast<long long>(c.jump->vertex));
    else if (c.jump)
      std::printf(", ends on its first pose");
    std::printf("\n");
  }
}

void print_surface_parts(const Facts& f) {
  if (f.tets) return;
  std::printf("  panels     %zu%s\n", f.panels.size(), f.panels.empty() ? "" : (": " + quoted_list(f.panels)).c_str());
  if (!f.obj) {
    std::printf("  UVs        not read (a pattern rest shape is read from an OBJ's vt)\n");
    return;
  }
  const ObjExtras& e = *f.obj;
  if (e.vt == 0) std::printf("  UVs (vt)   none\n");
  else std::printf("  UVs (vt)   %lld, on %lld of %lld faces\n", e.vt, e.faces_with_vt, f.triangles);
  std::printf("  stitches   %lld\n", e.stitches);
  for (const auto& [keyword, count] : e.other_lines) std::printf("  %s lines: %d (not read)\n", keyword.c_str(), count);
}

void print_text(const Facts& f, const Transform& t, bool transformed) {
  std::printf("%s: %s%s\n", f.file.c_str(), f.kind.c_str(), transformed ? " (positions after --transform)" : "");
  print_geometry(f, t);
  print_rig(f);
  print_surface_parts(f);
}

nlohmann::json box_json(const Box& b) {
  const Vec3 s = b.size();
  return {{"min", {b.lo.x(), b.lo.y(), b.lo.z()}}, {"max", {b.hi.x(), b.hi.y(), b.hi.z()}}, {"size", {s.x(), s.y(), s.z()}}};
}

nlohmann::json clip_json(const ClipFacts& c) {
  nlohmann::json j{{"name", c.name}, {"seconds", c.seconds}, {"keys", c.keys}, {"channels", c.channels}};
  if (c.jump) j["loop_jump"] = {{"metres", c.jump->distance}, {"vertex", c.jump->vertex}};
  if (c.first_pose) j["first_pose_bounds"] = box_json(*c.first_pose);
  return j;
}

nlohmann::json facts_json(const Facts& f, const Transform& t) {
  nlohmann::json j{{"file", f.file}, {"kind", f.kind}, {"vertices", f.vertices}, {"triangles", f.triangles},
                   {"transform", scene_detail::transform_json(t)}, {"bounds", box_json(f.bounds)}};
  if (f.tets) j["tets"] = *f.tets;
  if (!f.pose.empty()) j["bounds"]["pose"] = f.pose;
  if (f.clip_start) j["clip_start_bounds"] = box_json(*f.clip_start);
  j["up"] = f.up.axis.empty() ? nlohmann::json() : nlohmann::json{{"axis", f.up.axis}, {"reason", f.up.reason}};
  j["bones"] = {{"count", f.bones}, {"top", f.top_bones}, {"below_top", f.below_top}};
  j["clips"] = nlohmann::json::array();
  for (const ClipFacts& c : f.clips) j["clips"].push_back(clip_json(c));
  j["panels"] = f.panels;
  if (f.obj) {
    j["uvs"] = {{"vt", f.obj->vt}, {"faces_with_vt", f.obj->faces_with_vt}};
    j["stitches"] = f.obj->stitches;
    j["other_lines"] = f.obj->other_lines;
  } else {
    j["uvs"] = nullptr;
  }
  return j;
}

Transform transform_option(const ParsedArgs& args) {
  if (!args.has("--transform")) return {};
  const nlohmann::json j = parse_json(args.value("--transform"), "inspect --transform");
  return scene_detail::parse_transform(Fields(j, "inspect", "--transform"));
}

}  // namespace

int inspect_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "inspect", {"--transform"}, {"--help", "-h", "--json"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kInspectHelp;
    return 0;
  }
  if (args.positional.size() != 1) throw InputError("inspect: expected one file (see invfem inspect --help)");
  const Transform t = transform_option(args);
  const Facts facts = file_facts(args.positional[0], t);
  if (args.flag("--json")) std::cout << facts_json(facts, t).dump(2) << "\n";
  else print_text(facts, t, args.has("--transform"));
  return 0;
}

}  // namespace invfem::app
