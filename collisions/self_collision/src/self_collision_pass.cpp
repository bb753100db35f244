#include "invfem/collisions/self_collision/self_collision_pass.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "invfem/collisions/self_collision/response/collider_keep_out.hpp"
#include "invfem/collisions/self_collision/response/pass_through.hpp"

namespace invfem::collisions {

void validate(const SelfCollisionSettings& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("self_collision: " + what); };
  if (!(s.thickness > 0) || !std::isfinite(s.thickness)) fail("thickness must be a positive length [m]");
  if (!(s.ccd_distance >= 0) || !(s.ccd_distance < s.thickness))
    fail("ccd_distance must be >= 0 and below the thickness");
  if (!(s.friction >= 0) || !std::isfinite(s.friction)) fail("friction must be >= 0");
  if (s.impulse_passes < 0) fail("impulse_passes must be >= 0");
  if (s.max_zone_iterations < 1) fail("max_zone_iterations must be >= 1");
  if (s.zone_projection.rounds < 0) fail("zone_projection_rounds must be >= 0");
  if (s.zone_projection.solve.max_sweeps < 0) fail("the zone projection's sweeps must be >= 0");
  if (!(s.tangle_patience > 0) || !std::isfinite(s.tangle_patience)) fail("tangle_patience must be a positive time [s]");
}

SelfCollisionPass::SelfCollisionPass(SelfCollisionSettings settings,
                                     std::vector<std::shared_ptr<const ImplicitSurface>> analytic_colliders)
    : settings_(std::move(settings)), analytic_colliders_(std::move(analytic_colliders)) {
  validate(settings_);
}

namespace {
// The layer's state in a checkpoint: point lists (#V x 3, row-major, as doubles) and per-item
// flags (bytes), each with its count. Read element by element (not sized by the counts first): a
// damaged count ends as "truncated".
void write_points(StateWriter& out, const Points& x) { out.doubles(x.data(), static_cast<std::size_t>(x.size())); }
Points read_points(StateReader& in, const std::string& what) {
  const std::uint64_t n = in.count(what);
  if (n % 3 != 0) throw StateError(what + ": " + std::to_string(n) + " coordinates are not whole points");
  std::vector<double> values;
  for (std::uint64_t k = 0; k < n; ++k) values.push_back(in.pod<double>(what));
  return Eigen::Map<const Points>(values.data(), static_cast<Eigen::Index>(n / 3), 3);
}
void write_flags(StateWriter& out, const std::vector<char>& flags) {
  out.count(flags.size());
  for (char f : flags) out.pod(static_cast<std::uint8_t>(f));
}
std::vector<char> read_flags(StateReader& in, const std::string& what) {
  std::vector<char> flags;
  const std::uint64_t n = in.count(what);
  for (std::uint64_t k = 0; k < n; ++k) flags.push_back(static_cast<char>(in.pod<std::uint8_t>(what)));
  return flags;
}

// Every figure with its record key, in stats.jsonl order: the one list add_to and of share.
template <class Figures, class Visit> void visit_figures(Figures& f, Visit&& visit) {
  visit("candidates", f.candidates);
  visit("proximity_impulses", f.proximity_impulses);
  visit("ccd_hits", f.ccd_hits);
  visit("impact_zones", f.impact_zones);
  visit("largest_zone", f.largest_zone);
  visit("projected_zones", f.projected_zones);
  visit("rigid_zones", f.rigid_zones);
  visit("unresolved_steps", f.unresolved_steps);
  visit("tangled_pairs", f.tangled_pairs);
  visit("body_crossings", f.body_crossings);
  visit("cloth_crossings", f.cloth_crossings);
  visit("collider_projections", f.collider_projections);
  visit("seam_impulses", f.seam_impulses);
  visit("limited_vertices", f.limited_vertices);
  visit("seconds", f.seconds);
}

// The seams an object's forces hold (a garment's stitches), in its surface's vertex indices: the
// layer's mesh and the contact potential join them alike.
std::vector<Weld> object_seams(const SimObject& o) {
  std::vector<Weld> welds;
  for (const auto& f : o.forces) welds.insert(welds.end(), f->seams().begin(), f->seams().end());
  return welds;
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
      append_surface(mesh_, o.name, embedded ? o.embedded.surface.tris : o.surface.tris, x0, v, w, false, object_seams(o),
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
    mark_open_welds(mesh_, sewn_);
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
  mark_open_welds(mesh_, sewn_);
}

bool SelfCollisionPass::may_start_crossed() const {
  // The last step's end, bit for bit: nothing moved the surfaces in between (another pass, a
  // restored checkpoint), and the mesh is the one it ended on (a rebuild leaves end_ empty).
  return left_crossable_ || !started_where_ended();
}

void SelfCollisionPass::after_step(std::vector<SimObject>& objects, const StepPassInput& step, FrameReport& report) {
  const auto start = std::chrono::steady_clock::now();
  const double dt = step.dt;
  gather(objects, step);
  if (mesh_.tris.rows() == 0) return;
  adopt_resumed();
  SelfCollisionFigures r;  // this step's, added to the frame's record at its end
  const StartCrossings released = release_start_crossings(dt, r);
  const Points v_in = mesh_.v;
  Points v = mesh_.v;
  Points kick;
  if (!released.cloth.pushes.empty()) push_through(mesh_, released.cloth.pushes, dt, settings_.thickness, v, kick);
  std::vector<const ImplicitSurface*> bodies;
  for (const auto& c : analytic_colliders_) bodies.push_back(c.get());
  ColliderKeepOut keep_out(mesh_, std::move(bodies), v_in, dt, step.t + dt);
  resolve(dt, r, v_in, v, released.tangles == 0 && released.crossings == 0 && released.cloth.pairs == 0,
          keep_out.constraint(r.collider_projections));
  const bool unresolved = r.unresolved_steps > 0;
  if (unresolved) r.limited_vertices += limit_failed_step(mesh_, dt, settings_.thickness, v_in, v, keep_out.projected_at());
  // What the next step's start may hold (may_start_crossed): a crossing only where this step let
  // pairs go (recovering tets, tangles, body and cloth crossings) or its fail-safe gave up.
  left_crossable_ = released.recovering > 0 || released.tangles > 0 || released.crossings > 0 ||
                    released.cloth.pairs > 0 || unresolved;
  write_back(objects, dt, v_in, v, kick, keep_out);
  keep_passing();
  record_end(objects, step);
  r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.add_to(report.pass(kSelfCollisionRecord));
  report.unresolved_steps += r.unresolved_steps;
}

void SelfCollisionPass::save_state(StateWriter& out) const {
  if (!built_) return;  // no step yet: nothing carries over
  write_points(out, end_);
  out.pod(static_cast<std::uint8_t>(left_crossable_));
  out.count(tangle_ages_.entries.size());
  for (const TangleAges::Entry& e : tangle_ages_.entries) {
    out.pod(static_cast<std::int64_t>(e.edge));
    out.pod(static_cast<std::int64_t>(e.triangle));
    out.pod(e.seconds);
  }
  write_flags(out, recovering_tets_);
  out.count(passing_.size());
  for (const auto& object : passing_) write_flags(out, object);
  out.count(potential_rest_.size());
  for (const Points& rest : potential_rest_) write_points(out, rest);
  write_flags(out, sewn_);
}

void SelfCollisionPass::restore_state(StateReader& in, std::vector<SimObject>& objects) {
  (void)objects;  // the mesh is rebuilt from them at the next step
  built_ = false;
  resumed_.reset();
  passing_.clear();
  potential_rest_.clear();
  sewn_.clear();
  if (in.at_end()) return;
  const std::string what = "the self-collision layer's state";
  Resumed r;
  r.end = read_points(in, what);
  r.left_crossable = in.pod<std::uint8_t>(what) != 0;
  const std::uint64_t tangles = in.count(what);
  for (std::uint64_t k = 0; k < tangles; ++k) {
    TangleAges::Entry e;
    e.edge = static_cast<int>(in.pod<std::int64_t>(what));
    e.triangle = static_cast<int>(in.pod<std::int64_t>(what));
    e.seconds = in.pod<double>(what);
    r.tangle_ages.entries.push_back(e);
  }
  r.recovering_tets = read_flags(in, what);
  // The passing regions and the contact potentials' reference positions, read straight into
  // place: the first resumed step's potentials take them before the layer runs. Absent from a
  // checkpoint written before they were kept: none (the potentials made afresh, from the surfaces).
  if (!in.at_end())
    for (std::uint64_t o = in.count(what); o > 0; --o) passing_.push_back(read_flags(in, what));
  if (!in.at_end())
    for (std::uint64_t o = in.count(what); o > 0; --o) potential_rest_.push_back(read_points(in, what));
  // Which seams were sewn: absent from an older checkpoint, none (each closed one is found
  // closed again at the first resumed step).
  if (!in.at_end()) sewn_ = read_flags(in, what);
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
  if (potential_rest_.size() <= index) potential_rest_.resize(index + 1);
  if (!p || potential_versions_[index] != o.topology_version) {
    ContactBarrierSettings s;
    s.distance = settings_.thickness;
    Points& rest = potential_rest_[index];
    if (p || rest.rows() != o.surface.x.rows()) rest = o.surface.x;  // a first step, or a new topology
    p = std::make_unique<ClothContactPotential>(o.name, o.surface.tris, o.surface_nodes, rest, object_seams(o), s);
    potential_versions_[index] = o.topology_version;
  }
  static const std::vector<char> none;
  const auto& passing = index < passing_.size() ? passing_[index] : none;
  p->let_pass(passing.size() == static_cast<std::size_t>(o.surface.x.rows()) ? passing : none);
  return p.get();
}

void SelfCollisionPass::keep_passing() {
  passing_.clear();
  if (mesh_.passing.empty()) return;
  for (std::size_t s = 0; s < mesh_.surfaces.size(); ++s) {
    if (source_[s] < 0) continue;
    const CollisionMesh::Range& range = mesh_.surfaces[s];
    const auto first = mesh_.passing.begin() + range.first_vertex;
    if (std::none_of(first, first + range.num_vertices, [](char c) { return c != 0; })) continue;
    const auto k = static_cast<std::size_t>(source_[s]);
    if (passing_.size() <= k) passing_.resize(k + 1);
    passing_[k].assign(first, first + range.num_vertices);
  }
}

}  // namespace invfem::collisions
