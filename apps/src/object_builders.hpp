#pragma once
// Scene specs -> simulated objects, through the solids and shells libraries. Mesh loading errors
// become InputErrors that name the object and the file.
#include "invfem/core/world/world.hpp"
#include "invfem/solids/solid_object.hpp"
#include "invfem/solids/tet_mesh.hpp"
#include "load_warnings.hpp"
#include "scene.hpp"

namespace invfem::app {

// `mesh_out`, if given, receives the rest mesh the solid is built on (a fracturing solid's root).
// The load's warnings are printed as found and added to `warnings`.
SolidObject build_solid(const SolidSpec& spec, const Scene& scene, TetMesh* mesh_out, LoadWarnings& warnings);
SimObject build_cloth(const ClothSpec& spec, const Scene& scene, LoadWarnings& warnings);

// A tet-mesh file by its extension (.vtk, .mesh, .msh); any other is a surface to BCC-mesh.
bool is_tet_mesh_file(const std::filesystem::path& p);

// The transform's rotation: about x, then y, then z, by rotate_degrees.
Mat3 rotation_of(const Transform& t);

// Coordinates a placed object may have, in metres: 1000 km is far past any shot, and a double
// there still resolves 1e-10 m. Beyond it (translate 1e300, scale 1e30) the rest shape's
// differences are lost to round-off, and the mesh would be blamed for zero-volume elements.
inline constexpr double kMaxCoordinate = 1e6;

// Scale, rotate (rotation_of), translate: applied to every row of X. Throws InputError
// "<what>: the transform (...) puts node i at (x, y, z), ..." when a result is not finite or
// beyond kMaxCoordinate, naming the transform rather than the mesh.
void apply_transform(const Transform& t, Points& X, const std::string& what);

// Throws InputError "<what>: bounding-box diagonal D m ..." when the placed surface's size is
// outside the solids' plausible sizes [kMinDiagonal, kMaxDiagonal] (tet_mesh_checks.hpp), with
// the transform's scale that would fix it (`scale` is the one applied): cloth gets the checks
// solids have.
void check_object_size(const Points& X, double scale, const std::string& what);

}  // namespace invfem::app
