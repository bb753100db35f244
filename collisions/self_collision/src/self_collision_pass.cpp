#include "invfem/collisions/self_collision/self_collision_pass.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "invfem/collisions/self_collision/candidates/tangles.hpp"
#include "invfem/collisions/self_collision/response/ccd_impulses.hpp"
#include "invfem/collisions/self_collision/response/impact_zones.hpp"
#include "invfem/collisions/self_collision/response/repulsion.hpp"
#include "invfem/collisions/self_collision/response/seams.hpp"

namespace invfem::collisions {

void validate(const SelfCollisionSettings& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("self_collision: " + what); };
  if (!(s.thickness > 0) || !std::isfinite(s.thickness)) fail("thickness must be a positive length [m]");
  if (!(s.ccd_distance >= 0) || !(s.ccd_distance < s.thickness))
    fail("ccd_distance must be >= 0 and below the thickness");
  if (!(s.friction >= 0) || !std::isfinite(s.friction)) fail("friction must be >= 0");
  if (s.impulse_passes < 0) fail("impulse_passes must be >= 0");
  if (s.max_zone_iterations < 1) fail("max_zone_iterations must be >= 1");
  if (!(s.tangle_patience > 0) || !std::isfinite(s.tangle_patience)) fail("tangle_patience must be a positive time [s]");
}

SelfCollisionPass::SelfCollisionPass(SelfCollisionSettings settings,
                                     std::vector<std::shared_ptr<const ImplicitSurface>> analytic_colliders)
    : settings_(std::move(settings)), analytic_colliders_(std::move(analytic_colliders)) {
  validate(settings_);
}

namespace {
// Every figure with its record key, in stats.jsonl order: the one list add_to and of share.
template <class Figures, class Visit> void visit_figures(Figures& f, Visit&& visit) {
  visit("candidates", f.candidates);
  visit("proximity_impulses", f.proximity_impulses);
  visit("ccd_hits", f.ccd_hits);
  visit("impact_zones", f.impact_zones);
  visit("largest_zone", f.largest_zone);
  visit("unresolved_steps", f.unresolved_steps);
  visit("tangled_pairs", f.tangled_pairs);
  visit("body_crossings", f.body_crossings);
  visit("collider_projections", f.collider_projections);
  visit("seam_impulses", f.seam_impulses);
  visit("limited_vertices", f.limited_vertices);
  visit("seconds", f.seconds);
}
}  // namespace

void SelfCollisionFigures::add_to(PassRecord& record) const {
  visit_figures(*this, [&](const std::string& key, const auto& value) {
    if (key == "largest_zone") record.keep_largest(key, static_cast<double>(value));  // a frame's largest zone
    else record.add(key, static_cast<double>(value));
  });
}

SelfCollisionFigures SelfCollisionFigures::of(const FrameReport& report) {
  SelfCollisionFigures f;
  if (const PassRecord* r = report.find_pass(kSelfCollisionRecord))
    visit_figures(f, [&](const std::string& key, auto& value) { value = static_cast<std::decay_t<decltype(value)>>(r->value(key)); });
  return f;
}

bool SelfCollisionPass::excluded(const std::string& name) const {
  return std::find(settings_.excluded.begin(), settings_.excluded.end(), name) != settings_.excluded.end();
}

double SelfCollisionPass::step_motion_limit(const std::vector<SimObject>& objects) const {
  std::vector<double> lengths;
  for (const SimObject& o : objects) {
    if (excluded(o.name)) continue;
    const TriangleSurface& s = o.material_surface();
    for (Eigen::Index t = 0; t < s.tris.rows(); ++t)
      for (int e = 0; e < 3; ++e)
        lengths.push_back((s.x.row(s.tris(t, e)) - s.x.row(s.tris(t, (e + 1) % 3))).norm());
  }
  if (lengths.empty()) return std::numeric_limits<double>::infinity();
  const auto median = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), median, lengths.end());
  return *median > 0 ? kStepMotionEdges * *median : std::numeric_limits<double>::infinity();
}

void SelfCollisionPass::gather(const std::vector<SimObject>& objects, const StepPassInput& step) {
  const double dt = step.dt;
  // Per object, the body node of each of its collision vertices (-1: an embedded vertex) and its
  // embedding. A cut solid takes part with its embedded material surface (SimObject::embedded,
  // MBF04 2.3): its vertices are points of element copies, then the nodes they lie in
  // (collision_mesh.hpp SurfaceEmbedding); any other object with its surface, vertex s being node
  // surface_nodes[s].
  auto layout = [&](const SimObject& o, std::vector<int>& nodes, SurfaceEmbedding& e) {
    e = SurfaceEmbedding{};
    if (o.embedded.empty()) {
      nodes = o.surface_nodes;
      return;
    }
    const auto ne = static_cast<int>(o.embedded.vertices.size());
    std::vector<int> local(static_cast<std::size_t>(o.body.x.rows()), -1);
    std::vector<int> used;
    for (const EmbeddedVertex& ev : o.embedded.vertices)
      for (int k = 0; k < 4; ++k)
        if (ev.weights[static_cast<std::size_t>(k)] != 0) used.push_back(o.tets(ev.element, k));
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    nodes.assign(static_cast<std::size_t>(ne), -1);
    for (int node : used) {  // local vertex ne + rank
      local[static_cast<std::size_t>(node)] = static_cast<int>(nodes.size());
      nodes.push_back(node);
    }
    e.num_embedded = ne;
    for (const EmbeddedVertex& ev : o.embedded.vertices) {
      for (int k = 0; k < 4; ++k)
        if (const double w = ev.weights[static_cast<std::size_t>(k)]; w != 0) {
          e.nodes.push_back(local[static_cast<std::size_t>(o.tets(ev.element, k))]);
          e.weights.push_back(w);
          e.on.push_back(ev.on == 0 || ((ev.on >> k) & 1) ? 1 : 0);
        }
      e.offsets.push_back(static_cast<int>(e.nodes.size()));
    }
  };
  // Per object, its collision vertices' start positions, average velocities and inverse masses.
  auto object_state = [&](std::size_t k, const std::vector<int>& nodes, const SurfaceEmbedding& e, Points& x0,
                          Points& v, Eigen::VectorXd& inv_mass) {
    const SimObject& o = objects[k];
    const auto n = static_cast<Eigen::Index>(nodes.size());
    x0.resize(n, 3);
    v.resize(n, 3);
    inv_mass.resize(n);
    std::vector<char> pinned(static_cast<std::size_t>(o.body.x.rows()), 0);
    for (const PinGroup& g : o.pins)
      for (int i : g.nodes) pinned[static_cast<std::size_t>(i)] = 1;
    for (const AttachmentGroup& g : o.attachments)  // they follow their solid
      for (const Attachment& a : g.vertices) pinned[static_cast<std::size_t>(a.node)] = 1;
    for (Eigen::Index s = e.num_embedded; s < n; ++s) {
      const int i = nodes[static_cast<std::size_t>(s)];
      x0.row(s) = step.x_start[k].row(i);
      v.row(s) = (o.body.x.row(i) - step.x_start[k].row(i)) / dt;
      inv_mass(s) = pinned[static_cast<std::size_t>(i)] || !(o.body.mass(i) > 0) ? 0.0 : 1.0 / o.body.mass(i);
    }
    if (e.num_embedded > 0) embedded_state(e, x0, v, inv_mass);
  };
  // A taking-part object whose topology changed (fracture: new nodes, tets and boundary) makes
  // the mesh be built again from the objects as they now are.
  for (std::size_t r = 0; built_ && r < source_.size(); ++r)
    if (source_[r] >= 0 && objects[static_cast<std::size_t>(source_[r])].topology_version != versions_[r]) built_ = false;
  if (!built_) {
    mesh_ = CollisionMesh{};
    source_.clear();
    versions_.clear();
    vertex_nodes_.clear();
    embeddings_.clear();
    boundary_tets_.clear();
    recovering_tets_.clear();
    for (std::size_t k = 0; k < objects.size(); ++k) {
      if (excluded(objects[k].name) || objects[k].surface.tris.rows() == 0) continue;
      const SimObject& o = objects[k];
      std::vector<int> nodes;
      SurfaceEmbedding e;
      layout(o, nodes, e);
      Points x0, v;
      Eigen::VectorXd w;
      object_state(k, nodes, e, x0, v, w);
      const bool embedded = e.num_embedded > 0;
      std::vector<Weld> welds;  // the seams its forces hold (a garment's stitches)
      for (const auto& f : o.forces) welds.insert(welds.end(), f->seams().begin(), f->seams().end());
      append_surface(mesh_, o.name, embedded ? o.embedded.surface.tris : o.surface.tris, x0, v, w, false, welds,
                     embedded ? &e : nullptr);
      const bool volume = o.tets.rows() > 0;  // a solid's boundary; else a sheet
      mesh_.surfaces.back().untangle = volume;
      mesh_.surfaces.back().cut = volume && o.topology_version != 0;
      mesh_.surfaces.back().level = volume ? 1 : 0;  // one-way coupling
      if (!embedded && o.tets.rows() > 0) {
        std::vector<int> vertex_of(static_cast<std::size_t>(o.body.x.rows()), -1);
        for (std::size_t s = 0; s < nodes.size(); ++s)
          vertex_of[static_cast<std::size_t>(nodes[s])] = mesh_.surfaces.back().first_vertex + static_cast<int>(s);
        for (Eigen::Index t = 0; t < o.tets.rows(); ++t) {
          std::array<int, 4> g{};
          for (int c = 0; c < 4; ++c) g[static_cast<std::size_t>(c)] = vertex_of[static_cast<std::size_t>(o.tets(t, c))];
          if (std::all_of(g.begin(), g.end(), [](int i) { return i >= 0; })) boundary_tets_.push_back(g);
        }
      }
      source_.push_back(static_cast<int>(k));
      versions_.push_back(o.topology_version);
      vertex_nodes_.push_back(std::move(nodes));
      embeddings_.push_back(std::move(e));
    }
    if (settings_.kinematic_bodies)
      for (std::size_t b = 0; b < step.kinematic.size(); ++b) {
        const TriangleSurface* s = step.kinematic[b]->surface();
        if (!s || s->tris.rows() == 0 || !step.kinematic[b]->surface_is_shape() || excluded(step.kinematic[b]->name()))
          continue;
        const Points v = (s->x - step.kinematic_start[b]) / dt;
        append_surface(mesh_, step.kinematic[b]->name(), s->tris, step.kinematic_start[b], v, Eigen::VectorXd(), true);
        source_.push_back(-1 - static_cast<int>(b));
        versions_.push_back(0);
        vertex_nodes_.emplace_back();
        embeddings_.emplace_back();
      }
    built_ = true;
    end_.resize(0, 3);  // a new mesh: its start is searched
    tangle_ages_.entries.clear();  // its edge and triangle ids are new
    return;
  }
  for (std::size_t r = 0; r < mesh_.surfaces.size(); ++r) {
    const CollisionMesh::Range& range = mesh_.surfaces[r];
    const int src = source_[r];
    if (src >= 0) {
      Points x0, v;
      Eigen::VectorXd w;
      object_state(static_cast<std::size_t>(src), vertex_nodes_[r], embeddings_[r], x0, v, w);
      mesh_.x0.middleRows(range.first_vertex, range.num_vertices) = x0;
      mesh_.v.middleRows(range.first_vertex, range.num_vertices) = v;
      mesh_.inv_mass.segment(range.first_vertex, range.num_vertices) = w;
    } else {
      const auto b = static_cast<std::size_t>(-1 - src);
      const TriangleSurface* s = step.kinematic[b]->surface();
      mesh_.x0.middleRows(range.first_vertex, range.num_vertices) = step.kinematic_start[b];
      mesh_.v.middleRows(range.first_vertex, range.num_vertices) = (s->x - step.kinematic_start[b]) / dt;
    }
  }
}

int SelfCollisionPass::mark_recovering(bool fresh) {
  mesh_.recovering.clear();
  recovering_tets_.resize(boundary_tets_.size(), 0);
  for (std::size_t e = 0; e < boundary_tets_.size(); ++e) {
    const auto& t = boundary_tets_[e];
    auto x = [&](std::size_t c) -> Vec3 { return mesh_.x0.row(t[c]).transpose(); };
    const Vec3 a = x(0);
    const bool inverted = !((x(1) - a).cross(x(2) - a).dot(x(3) - a) > 0);  // 6V <= 0: inverted or flat
    char& flag = recovering_tets_[e];
    flag = inverted && (flag || fresh) ? 1 : 0;
    if (!flag) continue;
    for (std::size_t c = 0; c < 4; ++c)
      for (std::size_t d = c + 1; d < 4; ++d) mesh_.recovering.push_back(std::minmax(t[c], t[d]));
  }
  std::sort(mesh_.recovering.begin(), mesh_.recovering.end());
  mesh_.recovering.erase(std::unique(mesh_.recovering.begin(), mesh_.recovering.end()), mesh_.recovering.end());
  return static_cast<int>(mesh_.recovering.size());
}

int limit_failed_step(const CollisionMesh& mesh, double dt, double thickness, const Points& v_in, Points& v,
                      std::vector<int>& projected_at) {
  // The farthest any vertex moved in the step before the layer (kinematic ones included), plus the
  // thickness: what a working response could need to move a vertex by.
  double reach = 0;
  for (Eigen::Index i = 0; i < v_in.rows(); ++i) reach = std::max(reach, dt * v_in.row(i).norm());
  const double bound = reach + thickness;
  int limited = 0;
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    if (!mesh.movable(static_cast<int>(i)) || mesh.is_embedded(static_cast<int>(i))) continue;
    if (!(dt * (v.row(i) - v_in.row(i)).norm() > bound)) continue;
    v.row(i) = v_in.row(i);
    if (static_cast<std::size_t>(i) < projected_at.size()) projected_at[static_cast<std::size_t>(i)] = -1;
    ++limited;
  }
  if (limited > 0) sync_embedded(mesh, v);
  return limited;
}

bool SelfCollisionPass::may_start_crossed() const {
  // The last step's end, bit for bit: nothing moved the surfaces in between (another pass, a
  // restored checkpoint), and the mesh is the one it ended on (a rebuild leaves end_ empty).
  return left_crossable_ || !started_where_ended();
}

void SelfCollisionPass::resolve(double dt, SelfCollisionFigures& r, const Points& v_in, Points& v, bool have_candidates,
                                const ZoneConstraint& constrain) {
  // Repulsion: pairs within the thickness at x0 (swept boxes grown by it hold them all).
  if (!have_candidates) broad_phase_.find(mesh_, v, dt, settings_.thickness, candidates_);
  r.candidates += static_cast<long long>(candidates_.size());
  const long long repulsions = apply_repulsion(mesh_, candidates_, dt, {settings_.thickness, settings_.friction}, v);
  r.proximity_impulses += repulsions;
  // Seams move as one with what the impulses asked of either side (response/seams.hpp); the
  // passes below re-detect on the result.
  if (repulsions > 0) r.seam_impulses += hold_seams(mesh_, v_in, v);
  // The impulses need the time of contact only roughly (it sets where the normal is taken), and a
  // query that runs out of boxes is answered as a conservative hit (an extra impulse or zone
  // merge, never a miss): loose tolerances buy speed without costing safety.
  CcdSettings ccd;
  ccd.min_distance = settings_.ccd_distance;
  ccd.time_tolerance = 1e-4;
  ccd.max_iterations = 10'000;
  // Each pass re-detects on the velocities the last one left (BFA02 section 5); when the
  // repulsion changed nothing, its candidates (boxes grown by the thickness, more than the CCD
  // needs) serve the first pass. Otherwise the first pass refinds from the repulsion's find: its
  // boxes, grown by the thickness, still hold nearly every box of the CCD's margin after the
  // repulsion's small velocity changes (broad_phase.hpp refind). A pass that finds nothing
  // colliding ends the step's work: the impact zones would find the same nothing.
  const double margin = 2 * settings_.ccd_distance;
  bool clear = false;
  for (int pass = 0; pass < settings_.impulse_passes && !clear; ++pass) {
    if (pass > 0 || repulsions > 0)  // only velocities changed since the last find: re-detect around them
      broad_phase_.refind(mesh_, v, dt, margin, candidates_);
    const CcdPassReport p = apply_ccd_impulses(mesh_, candidates_, dt, ccd, settings_.friction, v);
    r.ccd_hits += p.impulses;
    clear = p.colliding == 0;
    if (!clear) r.seam_impulses += hold_seams(mesh_, v_in, v);
  }
  // With nothing colliding, the zones run only if keeping clear of the colliders moved something.
  ImpactZoneReport zones;
  if (!clear || (constrain && constrain({}, v)))
    zones = resolve_impact_zones(mesh_, broad_phase_, margin, dt, ccd, settings_.max_zone_iterations, v, constrain);
  r.impact_zones += zones.zones;
  r.largest_zone = std::max(r.largest_zone, zones.largest);
  if (!zones.resolved) ++r.unresolved_steps;
}

void SelfCollisionPass::after_step(std::vector<SimObject>& objects, const StepPassInput& step, FrameReport& report) {
  const auto start = std::chrono::steady_clock::now();
  const double dt = step.dt, t1 = step.t + dt;
  gather(objects, step);
  if (mesh_.tris.rows() == 0) return;
  if (resumed_) {
    if (resumed_->end.rows() == mesh_.x0.rows() && resumed_->recovering_tets.size() == boundary_tets_.size()) {
      end_ = std::move(resumed_->end);
      left_crossable_ = resumed_->left_crossable;
      tangle_ages_ = std::move(resumed_->tangle_ages);
      recovering_tets_ = std::move(resumed_->recovering_tets);
    }
    resumed_.reset();
  }
  SelfCollisionFigures r;  // this step's, added to the frame's record at its end

  // Tangles at the step's start release the pairs that can undo them (candidates/tangles.hpp);
  // only solids' boundaries are searched, so a scene of cloths pays nothing for it.
  // A cloth's crossings with a kinematic body at the step's start (left by a fail-safe failure
  // in an earlier step) are released for the step (candidates/tangles.hpp mark_body_crossings),
  // so the cloth can come out of the body instead of being held in it for ever.
  // Both searches run only when the start can hold a crossing (may_start_crossed).
  mesh_.exempt_vf.clear();
  mesh_.exempt_ee.clear();
  mesh_.stuck.clear();
  mesh_.loose.clear();
  mesh_.released.clear();
  // Before the candidates: it joins vertices.
  const int recovering = mark_recovering(!started_where_ended());
  broad_phase_.find(mesh_, dt, settings_.thickness, candidates_);
  int tangles = 0, crossings = 0;
  const bool search = may_start_crossed();
  const bool solids =
      search && std::any_of(mesh_.surfaces.begin(), mesh_.surfaces.end(), [](const auto& s) { return s.untangle; });
  const bool cloth_and_body =
      search &&
      std::any_of(mesh_.surfaces.begin(), mesh_.surfaces.end(), [](const auto& s) { return s.kinematic; }) &&
      std::any_of(mesh_.surfaces.begin(), mesh_.surfaces.end(), [](const auto& s) { return !s.kinematic && !s.untangle; });
  if (solids || cloth_and_body) broad_phase_.edge_triangle_pairs(mesh_, edge_triangles_);
  if (!solids) tangle_ages_.entries.clear();
  if (solids) {
    tangles = mark_tangles(mesh_, edge_triangles_, tangle_ages_, dt, settings_.tangle_patience);
    r.tangled_pairs += tangles;
  }
  if (cloth_and_body) {
    crossings = mark_body_crossings(mesh_, edge_triangles_);
    r.body_crossings += crossings;
  }

  const Points v_in = mesh_.v;
  Points v = mesh_.v;

  // The layer does not see the analytic colliders (their exact shape acts on vertices, through
  // the collision processing). Where its impulses or zones would carry a vertex into one (an
  // impact zone moving a cloth that rests on the ground downward), the vertex's zone (or the
  // vertex alone) is translated out along the collider's normal, inside the zones' loop, so the
  // result is both free of collisions and outside the colliders; the end-of-step velocity of
  // such a vertex then takes the body's normal velocity (no kick out of it). Counted in
  // stats.jsonl (`collider_projections`).
  std::vector<const ImplicitSurface*> bodies;
  for (const auto& c : analytic_colliders_) bodies.push_back(c.get());
  struct Projected {
    int vertex;
    Vec3 normal, body_velocity;
  };
  std::vector<Projected> projected;
  std::vector<int> projected_at(static_cast<std::size_t>(mesh_.num_vertices()), -1);  // latest entry per vertex
  ZoneConstraint keep_out;
  if (!bodies.empty())
    keep_out = [&](const std::vector<std::vector<int>>& zones, Points& vel) {
      std::vector<int> zone_of(static_cast<std::size_t>(mesh_.num_vertices()), -1);
      for (std::size_t z = 0; z < zones.size(); ++z)
        for (int i : zones[z]) zone_of[static_cast<std::size_t>(i)] = static_cast<int>(z);
      bool any = false;
      // A few sweeps: a zone translated out of a curved body may leave another of its vertices in.
      for (int sweep = 0; sweep < 4; ++sweep) {
        bool moved = false;
        std::vector<Vec3> zone_shift(zones.size(), Vec3::Zero());
        for (Eigen::Index i = 0; i < mesh_.num_vertices(); ++i) {
          // An embedded vertex follows its nodes, which are vertices here too.
          if (!mesh_.movable(static_cast<int>(i)) || vel.row(i) == v_in.row(i) || mesh_.is_embedded(static_cast<int>(i)))
            continue;
          for (const ImplicitSurface* b : bodies) {
            const Vec3 x1 = mesh_.position(static_cast<int>(i), vel, 1.0, dt);
            const double phi = b->phi(x1, t1);
            if (!(phi < 0)) continue;
            const Vec3 n = b->normal(x1, t1);
            moved = true;
            projected_at[static_cast<std::size_t>(i)] = static_cast<int>(projected.size());
            projected.push_back({static_cast<int>(i), n, b->velocity(x1, t1)});
            ++r.collider_projections;
            const int z = zone_of[static_cast<std::size_t>(i)];
            if (z < 0) {
              vel.row(i) -= (phi / dt) * n.transpose();
            } else {  // the deepest push of the zone along each direction, applied to all of it
              const Vec3 push = -phi * n;
              Vec3& shift = zone_shift[static_cast<std::size_t>(z)];
              for (int c = 0; c < 3; ++c) shift(c) = std::abs(push(c)) > std::abs(shift(c)) ? push(c) : shift(c);
            }
          }
        }
        for (std::size_t z = 0; z < zones.size(); ++z)
          if (!zone_shift[z].isZero()) {
            const int lowest = lowest_level(mesh_, zones[z]);
            for (int i : zones[z])
              if (!fixed_in_zone(mesh_, i, lowest) && !mesh_.is_embedded(i)) vel.row(i) += (zone_shift[z] / dt).transpose();
          }
        any = any || moved;
        if (!moved) break;
      }
      if (any) sync_embedded(mesh_, vel);
      return any;
    };
  const long long unresolved_before = r.unresolved_steps;
  resolve(dt, r, v_in, v, tangles == 0 && crossings == 0, keep_out);
  if (r.unresolved_steps > unresolved_before) r.limited_vertices += limit_failed_step(mesh_, dt, settings_.thickness, v_in, v, projected_at);
  // What the next step's start may hold (may_start_crossed): a crossing only where this step let
  // pairs go (recovering tets, tangles, body crossings) or its fail-safe gave up.
  left_crossable_ = recovering > 0 || tangles > 0 || crossings > 0 || r.unresolved_steps > unresolved_before;

  // Write back: x(n+1) = x0 + dt v on the surface nodes; v(n+1) gets the same change.
  for (std::size_t s = 0; s < mesh_.surfaces.size(); ++s) {
    if (source_[s] < 0) continue;
    SimObject& o = objects[static_cast<std::size_t>(source_[s])];
    const CollisionMesh::Range& range = mesh_.surfaces[s];
    for (int j = 0; j < range.num_vertices; ++j) {
      const int g = range.first_vertex + j;
      const int node = vertex_nodes_[s][static_cast<std::size_t>(j)];
      if (node < 0 || !mesh_.movable(g) || v.row(g) == v_in.row(g)) continue;  // embedded: its nodes are written
      o.body.x.row(node) = mesh_.x0.row(g) + dt * v.row(g);
      o.body.v.row(node) += v.row(g) - v_in.row(g);
      if (const int k = projected_at[static_cast<std::size_t>(g)]; k >= 0) {
        const Projected& p = projected[static_cast<std::size_t>(k)];
        const Vec3 vn = o.body.v.row(node).transpose();
        o.body.v.row(node) = (vn + (p.body_velocity.dot(p.normal) - vn.dot(p.normal)) * p.normal).transpose();
      }
    }
    o.refresh_surface();
  }
  // Where the surfaces now are, as the next step's start will read them (gather).
  end_.resize(mesh_.num_vertices(), 3);
  for (std::size_t s = 0; s < mesh_.surfaces.size(); ++s) {
    const CollisionMesh::Range& range = mesh_.surfaces[s];
    if (source_[s] >= 0) {
      // As gather() forms x0: the nodes' positions, and embedded vertices (listed first) as
      // their weighted sums, in the same order of operations so the bits agree.
      const SimObject& o = objects[static_cast<std::size_t>(source_[s])];
      const SurfaceEmbedding& em = embeddings_[s];
      Points x(range.num_vertices, 3);
      for (int j = em.num_embedded; j < range.num_vertices; ++j)
        x.row(j) = o.body.x.row(vertex_nodes_[s][static_cast<std::size_t>(j)]);
      if (em.num_embedded > 0) {
        Points unused_v = Points::Zero(range.num_vertices, 3);
        Eigen::VectorXd unused_w = Eigen::VectorXd::Zero(range.num_vertices);
        embedded_state(em, x, unused_v, unused_w);
      }
      end_.middleRows(range.first_vertex, range.num_vertices) = x;
    } else {
      end_.middleRows(range.first_vertex, range.num_vertices) =
          step.kinematic[static_cast<std::size_t>(-1 - source_[s])]->surface()->x;
    }
  }
  r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.add_to(report.pass(kSelfCollisionRecord));
  report.unresolved_steps += r.unresolved_steps;
}

void SelfCollisionPass::save_state(StateWriter& out) const {
  if (!built_) return;  // no step yet: nothing carries over
  out.doubles(end_.data(), static_cast<std::size_t>(end_.size()));
  out.pod(static_cast<std::uint8_t>(left_crossable_));
  out.count(tangle_ages_.entries.size());
  for (const TangleAges::Entry& e : tangle_ages_.entries) {
    out.pod(static_cast<std::int64_t>(e.edge));
    out.pod(static_cast<std::int64_t>(e.triangle));
    out.pod(e.seconds);
  }
  out.count(recovering_tets_.size());
  for (char f : recovering_tets_) out.pod(static_cast<std::uint8_t>(f));
}

void SelfCollisionPass::restore_state(StateReader& in, std::vector<SimObject>& objects) {
  (void)objects;  // the mesh is rebuilt from them at the next step
  built_ = false;
  resumed_.reset();
  if (in.at_end()) return;
  const std::string what = "the self-collision layer's state";
  Resumed r;
  const std::uint64_t n = in.count(what);
  if (n % 3 != 0) throw StateError(what + ": " + std::to_string(n) + " coordinates are not whole points");
  // Element by element (not sized by the counts first): a damaged count ends as "truncated".
  std::vector<double> end;
  for (std::uint64_t k = 0; k < n; ++k) end.push_back(in.pod<double>(what));
  r.end = Eigen::Map<const Points>(end.data(), static_cast<Eigen::Index>(n / 3), 3);  // row-major, as written
  r.left_crossable = in.pod<std::uint8_t>(what) != 0;
  const std::uint64_t tangles = in.count(what);
  for (std::uint64_t k = 0; k < tangles; ++k) {
    TangleAges::Entry e;
    e.edge = static_cast<int>(in.pod<std::int64_t>(what));
    e.triangle = static_cast<int>(in.pod<std::int64_t>(what));
    e.seconds = in.pod<double>(what);
    r.tangle_ages.entries.push_back(e);
  }
  const std::uint64_t tets = in.count(what);
  for (std::uint64_t k = 0; k < tets; ++k) r.recovering_tets.push_back(static_cast<char>(in.pod<std::uint8_t>(what)));
  resumed_ = std::move(r);
}

ContactPotential* SelfCollisionPass::contact_potential(const SimObject& o, std::size_t index) {
  if (!settings_.barrier || excluded(o.name) || o.tets.rows() > 0 || !o.embedded.empty() || o.surface.tris.rows() == 0)
    return nullptr;
  if (potentials_.size() <= index) {
    potentials_.resize(index + 1);
    potential_versions_.resize(index + 1, 0);
  }
  auto& p = potentials_[index];
  if (!p || potential_versions_[index] != o.topology_version) {
    std::vector<Weld> welds;  // the seams its forces hold, as gather() joins them
    for (const auto& f : o.forces) welds.insert(welds.end(), f->seams().begin(), f->seams().end());
    ContactBarrierSettings s;
    s.distance = settings_.thickness;
    p = std::make_unique<ClothContactPotential>(o.name, o.surface.tris, o.surface_nodes, o.surface.x, welds, s);
    potential_versions_[index] = o.topology_version;
  }
  return p.get();
}

}  // namespace invfem::collisions
