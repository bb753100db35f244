#include "checkpoint.hpp"

#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>

#include "invfem/core/atomic_file.hpp"
#include "invfem/shells/bending_force.hpp"
#include "json_fields.hpp"
#include "run_output.hpp"

namespace invfem::app {

namespace {

constexpr char kMagic[8] = {'I', 'N', 'V', 'F', 'E', 'M', 'C', 'K'};
constexpr std::uint32_t kVersion = 1;

class Writer {
 public:
  template <class T> void pod(const T& v) { bytes_.append(reinterpret_cast<const char*>(&v), sizeof v); }
  void doubles(const double* p, std::size_t n) {
    pod(static_cast<std::uint64_t>(n));
    bytes_.append(reinterpret_cast<const char*>(p), n * sizeof(double));
  }
  void string(const std::string& s) {
    pod(static_cast<std::uint64_t>(s.size()));
    bytes_ += s;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class Reader {
 public:
  Reader(std::string bytes, std::string file) : bytes_(std::move(bytes)), file_(std::move(file)) {}
  template <class T> T pod() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  void doubles(double* p, std::size_t expected, const std::string& what) {
    const auto n = pod<std::uint64_t>();
    if (n != expected)
      fail(what + " holds " + std::to_string(n) + " values, the scene needs " + std::to_string(expected));
    need(n * sizeof(double));
    std::memcpy(p, bytes_.data() + pos_, n * sizeof(double));
    pos_ += n * sizeof(double);
  }
  std::string string() {
    const auto n = pod<std::uint64_t>();
    need(n);
    std::string s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(file_ + ": checkpoint " + what); }

 private:
  void need(std::size_t n) const {
    if (pos_ + n > bytes_.size()) fail("is truncated");
  }
  std::string bytes_;
  std::string file_;
  std::size_t pos_ = 0;
};

BendingForce* bending_of(const SimObject& o) {
  for (const auto& f : o.forces)
    if (auto* b = dynamic_cast<BendingForce*>(f.get())) return b;
  return nullptr;
}

}  // namespace

std::uint64_t scene_hash(const Scene& scene) {
  // FNV-1a over the scene as run: stable across runs of the same build.
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : to_json(scene).dump()) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::filesystem::path checkpoint_path(const std::filesystem::path& out_dir, int frame) {
  return out_dir / "checkpoints" / (RunOutput::frame_name(frame) + ".ckpt");
}

void save_checkpoint(const std::filesystem::path& out_dir, const World& world, int frame, const std::string& csv) {
  Writer w;
  w.pod(kMagic);
  w.pod(kVersion);
  w.pod(scene_hash(world.scene()));
  w.pod(static_cast<std::int64_t>(frame));
  w.pod(world.time());
  w.string(csv);
  w.pod(static_cast<std::uint64_t>(world.objects().size()));
  for (const auto& o : world.objects()) {
    w.string(o.name);
    w.doubles(o.body.x.data(), o.body.x.size());
    w.doubles(o.body.v.data(), o.body.v.size());
    const auto& fp = o.solid ? o.solid->plastic_state().Fp_inv : std::vector<Mat3>{};
    w.pod(static_cast<std::uint64_t>(fp.size()));
    for (const auto& m : fp) w.doubles(m.data(), 9);
    const BendingForce* bending = bending_of(o);
    const std::vector<double> angles = bending ? bending->rest_angles() : std::vector<double>{};
    w.pod(static_cast<std::uint64_t>(angles.size()));
    w.doubles(angles.data(), angles.size());
  }
  w.pod(kMagic);  // trailer: a file cut short is caught even if its cut falls between fields
  std::filesystem::create_directories(out_dir / "checkpoints");
  atomic_write(checkpoint_path(out_dir, frame), w.bytes());
}

CheckpointInfo load_checkpoint(const std::filesystem::path& file, World& world) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open the checkpoint");
  Reader r(std::string(std::istreambuf_iterator<char>(in), {}), file.string());
  char magic[8];
  for (char& c : magic) c = r.pod<char>();
  if (std::memcmp(magic, kMagic, 8) != 0) r.fail("is not an invfem checkpoint");
  if (r.pod<std::uint32_t>() != kVersion) r.fail("has another format version");
  if (r.pod<std::uint64_t>() != scene_hash(world.scene()))
    r.fail("was written by a different scene (or other --set/--quick options)");
  CheckpointInfo info;
  info.frame = static_cast<int>(r.pod<std::int64_t>());
  info.time = r.pod<double>();
  info.csv = r.string();
  auto& objects = world.objects_for_restore();
  if (r.pod<std::uint64_t>() != objects.size()) r.fail("holds another number of objects");
  // Read everything into copies first: a damaged file must leave the world untouched.
  struct Saved {
    Points x, v;
    std::vector<Mat3> fp;
    std::vector<double> angles;
  };
  std::vector<Saved> saved(objects.size());
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const SimObject& o = objects[k];
    if (r.string() != o.name) r.fail("has objects in another order");
    Saved& s = saved[k];
    s.x.resize(o.body.x.rows(), 3);
    s.v.resize(o.body.v.rows(), 3);
    r.doubles(s.x.data(), s.x.size(), "positions of \"" + o.name + "\"");
    r.doubles(s.v.data(), s.v.size(), "velocities of \"" + o.name + "\"");
    const auto nfp = r.pod<std::uint64_t>();
    const std::size_t expect_fp = o.solid ? o.solid->plastic_state().Fp_inv.size() : 0;
    if (nfp != expect_fp) r.fail("plastic state of \"" + o.name + "\" has the wrong size");
    s.fp.resize(nfp);
    for (auto& m : s.fp) r.doubles(m.data(), 9, "plastic state");
    const auto na = r.pod<std::uint64_t>();
    const BendingForce* bending = bending_of(o);
    if (na != (bending ? bending->rest_angles().size() : 0)) r.fail("rest angles of \"" + o.name + "\" have the wrong size");
    s.angles.resize(na);
    r.doubles(s.angles.data(), na, "rest angles");
  }
  char trailer[8];
  for (char& c : trailer) c = r.pod<char>();
  if (std::memcmp(trailer, kMagic, 8) != 0) r.fail("is damaged (bad trailer)");
  for (std::size_t k = 0; k < objects.size(); ++k) {
    SimObject& o = objects[k];
    o.body.x = std::move(saved[k].x);
    o.body.v = std::move(saved[k].v);
    if (o.solid) o.solid->restore_plastic_state(PlasticState{std::move(saved[k].fp)});
    if (BendingForce* b = bending_of(o)) b->rest_angles() = std::move(saved[k].angles);
  }
  world.resynchronize(info.time);
  return info;
}

std::optional<CheckpointInfo> resume_latest(const std::filesystem::path& out_dir, World& world, int max_frame) {
  std::map<int, std::filesystem::path, std::greater<>> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(out_dir / "checkpoints", ec)) {
    if (e.path().extension() != ".ckpt") continue;
    const std::string stem = e.path().stem().string();
    if (stem.empty() || stem.find_first_not_of("0123456789") != std::string::npos) continue;
    found[std::stoi(stem)] = e.path();
  }
  for (const auto& [frame, path] : found) {
    if (frame > max_frame) continue;
    try {
      return load_checkpoint(path, world);
    } catch (const InputError& e) {
      std::cerr << "warning: skipping " << e.what() << "\n";
    }
  }
  return std::nullopt;
}

}  // namespace invfem::app
