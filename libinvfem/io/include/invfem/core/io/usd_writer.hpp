#pragma once
// USD ASCII (.usda) animation of one triangle surface: fixed topology, time-sampled points.
#include <map>
#include <string>
#include <vector>

#include "invfem/core/math/types.hpp"

namespace invfem {

// Collects frames and rewrites the whole .usda atomically on every add_frame, so a killed run
// leaves a valid file holding the frames written so far. Layer metadata: upAxis "Y",
// metersPerUnit 1, timeCodesPerSecond = framesPerSecond = fps, start/endTimeCode = first/last
// frame. Prims: /<name> (Xform, the defaultPrim) and /<name>/mesh (Mesh, subdivisionScheme
// "none", rightHanded = counter-clockwise seen from outside) with faceVertexCounts,
// faceVertexIndices, points (first frame) plus points.timeSamples and extent(.timeSamples),
// normals.timeSamples (per vertex, "vertex" interpolation: the area-weighted mean of its
// triangles' normals, unit length, zero where they cancel) and, for frames given velocities,
// velocities.timeSamples [m/s] (motion blur in renderers); a garment's panels are GeomSubsets
// /<name>/mesh/<panel> (set_panels).
// Time code = frame number. Points are point3f (USD's schema type), written with 9 digits.
// Cost: the text of each frame is formatted once and kept, but the file write grows with the
// number of frames (quadratic over a run).
// Topology that changes (a fracturing solid, whose cut frames have more points and triangles):
// frames added with their own triangles. While every frame has the constructor's triangles the
// file is exactly as above; once one differs, faceVertexCounts and faceVertexIndices also get
// timeSamples (USD holds an array attribute's sample until the next one): a sample at the first
// frame and at every frame whose triangles differ from the previous frame's, the default value
// being the first frame's. points may then change size from one sample to the next. Texture
// coordinates and panels index the faces, so they are written only while the topology does not
// vary: a layer whose faces change has neither.
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
  // `velocities` (#points x 3 [m/s], or nullptr) are written with the frame when given.
  void add_frame(int frame, const Points& x, const Points* velocities = nullptr);
  // The same with this frame's own triangles (time-varying topology, above); x may then have any
  // number of points. Throws as add_frame, and for an index of tris outside [0, x.rows()).
  void add_frame(int frame, const Points& x, const Tris& tris, const Points* velocities = nullptr);
  // True once some frame's triangles differ from the constructor's.
  bool topology_varies() const;
  // The surface's texture coordinates (uv: #UV x 2; uv_tris: #F x 3 indices into uv, per face
  // corner, as TriangleSurface holds them), written as the indexed face-varying primvar
  // primvars:st (texCoord2f[] with primvars:st:indices) while the topology does not vary.
  // Throws std::invalid_argument for a uv_tris of another shape than the triangles, an index
  // outside [0, #UV) or a non-finite coordinate.
  void set_texture_coordinates(const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>& uv,
                               const Tris& uv_tris);

  // The surface's panels, as the OBJ writer writes them as `g` groups (names; triangle_group[t]
  // indexes names for triangle t, as TriangleSurface holds them), written as GeomSubset children
  // of the mesh while the topology does not vary: one per panel with triangles and a non-empty
  // name, in the order of `names`, named by usd_identifier (a name taken already gets a suffix
  // _2, _3, ..), with elementType "face", familyName "panels" and the panel's triangles as
  // ascending indices. The mesh declares subsetFamily:panels:familyType "partition" when every
  // triangle is in a panel, else "nonOverlapping" (a triangle whose group is outside
  // [0, #names) or unnamed is in none). No names: no subsets. Throws std::invalid_argument for a
  // triangle_group whose length is not the number of triangles.
  void set_panels(const std::vector<std::string>& names, const std::vector<int>& triangle_group);

  const std::string& path() const { return path_; }
  const std::string& prim_name() const { return prim_; }
  std::size_t num_frames() const { return frames_.size(); }

 private:
  struct Frame {
    std::string points;  // "[(x, y, z), ...]"
    std::string extent;  // "[(min), (max)]"
    std::string normals;     // "[(nx, ny, nz), ...]", one per point
    std::string velocities;  // the same, or "" when the frame has none
    int topology = 0;    // index into topologies_
  };
  struct Topology {
    Tris tris;
    std::string counts, indices;  // "[3, 3, ...]", "[i, j, k, ...]"
  };
  int topology_of(const Tris& tris);
  void add(int frame, const Points& x, int topology, const Points* velocities);
  std::string render() const;

  std::string path_;
  std::string prim_;
  std::vector<Topology> topologies_;  // [0]: the constructor's triangles
  double fps_;
  Eigen::Index num_points_ = -1;  // fixed by the first frame
  std::map<int, Frame> frames_;
  std::string st_, st_indices_;  // primvars:st and its indices, "" when none
  std::string panels_type_, panels_;  // the panels' family type and GeomSubset prims, "" when none
};

// The velocities.timeSamples of a layer UsdaAnimationWriter wrote (frame -> #points x 3), for a
// resumed run to write its earlier frames again as they were; empty when the file is missing or
// holds none.
std::map<int, Points> read_usda_velocities(const std::string& path);

// A valid USD identifier made from `name` (see UsdaAnimationWriter's constructor).
std::string usd_identifier(const std::string& name);

// One USD stage for a whole shot: a layer whose default prim /shot (Xform) holds one prim per
// object or body, each referencing that one's animated layer (`layers`: (name, path relative to
// the stage's folder), in order), with the layers' metadata (upAxis "Y", metersPerUnit 1,
// time codes = frames at `fps`, from `first` to `last`). usdview, Houdini and Blender open it as
// the shot. Throws std::invalid_argument for fps <= 0 or non-finite or last < first.
std::string usda_stage(const std::vector<std::pair<std::string, std::string>>& layers, int first, int last, double fps);

}  // namespace invfem
