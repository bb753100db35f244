// The Python module `invfem` (pybind11): a Simulation built from a scene file or a dict, stepped
// with the GIL released, its state read as NumPy arrays, a sequence body driven from Python, and
// the intersection certificate on arrays. A front end like the command line: the physics and the
// scene rules are the libraries' and apps/src's (session.hpp), nothing is re-implemented here.
//
// Arrays: float64 positions (n, 3), int32 indices; outputs are new arrays (the state they come
// from moves on at the next step); inputs in C order and float64 are read in place, others are
// converted once.
//
// Threads: calls on one Simulation run one at a time (its mutex); different Simulations step in
// parallel. The module is invfem._invfem, re-exported by the package invfem (apps/python/invfem).
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "arrays.hpp"
#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/collisions/colliders/body_sequence.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/io/output_error.hpp"
#include "json_reader.hpp"
#include "run_output.hpp"
#include "session.hpp"

namespace py = pybind11;
using namespace invfem;
using namespace invfem::app;

namespace {

// --- Python values to JSON -----------------------------------------------------------------------
// A scene given as a dict, and the values of `set`, are converted here rather than through Python's
// json module, so that a value a scene cannot hold raises a ValueError naming where it is:
// `$.gravity[1]: nan is not a finite number`. Floats are taken as the exact doubles they are.

// A dict entry's path: `.name` for a plain name, `["..."]` (JSON-quoted) for any other key.
std::string member_path(const std::string& parent, const std::string& key) {
  const auto plain = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  if (!key.empty() && !std::isdigit(static_cast<unsigned char>(key[0])) && std::all_of(key.begin(), key.end(), plain))
    return parent + "." + key;
  return parent + "[" + nlohmann::json(key).dump() + "]";
}

std::string type_name(py::handle value) { return Py_TYPE(value.ptr())->tp_name; }

[[noreturn]] void not_a_scene_value(py::handle value, const std::string& path) {
  throw py::value_error(path + ": a value of type " + type_name(value) +
                        ", which a scene cannot hold (dict, list, tuple, str, int, float, bool or None)");
}

// A str as UTF-8 (a str with a lone surrogate has none).
std::string utf8(py::handle text, const std::string& path) {
  Py_ssize_t size = 0;
  const char* data = PyUnicode_AsUTF8AndSize(text.ptr(), &size);
  if (!data) {
    PyErr_Clear();
    throw py::value_error(path + ": a str that is not valid Unicode (a lone surrogate)");
  }
  return std::string(data, static_cast<std::size_t>(size));
}

// An int, or anything with __index__ (NumPy integer scalars), within the 64-bit range.
nlohmann::json integer(py::handle value, const std::string& path) {
  const auto index = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
  if (!index) throw py::error_already_set();
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow == 0) return v;
  if (overflow > 0) {
    const unsigned long long u = PyLong_AsUnsignedLongLong(index.ptr());
    if (!PyErr_Occurred()) return u;
    PyErr_Clear();
  }
  throw py::value_error(path + ": an integer outside the 64-bit range a scene's numbers have");
}

nlohmann::json finite(double v, const std::string& path) {
  if (!std::isfinite(v))
    throw py::value_error(path + ": " + (std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf") +
                          " is not a finite number (a scene's numbers are finite; JSON has no NaN or infinity)");
  return v;
}

// NumPy's bool and floating scalars (its integers have __index__), looked for only when NumPy is
// loaded: otherwise there are none.
std::optional<nlohmann::json> numpy_scalar(py::handle value, const std::string& path) {
  const auto numpy = py::reinterpret_steal<py::object>(PyImport_GetModule(py::str("numpy").ptr()));
  if (!numpy) {
    PyErr_Clear();
    return std::nullopt;
  }
  if (py::isinstance(value, numpy.attr("bool_"))) return value.cast<bool>();
  if (py::isinstance(value, numpy.attr("floating"))) return finite(value.cast<double>(), path);
  return std::nullopt;
}

class JsonFromPython {
 public:
  nlohmann::json operator()(py::handle value, const std::string& path) {
    if (value.is_none()) return nullptr;
    if (PyBool_Check(value.ptr())) return value.ptr() == Py_True;
    if (PyFloat_Check(value.ptr())) return finite(PyFloat_AS_DOUBLE(value.ptr()), path);
    if (PyLong_Check(value.ptr())) return integer(value, path);
    if (PyUnicode_Check(value.ptr())) return utf8(value, path);
    if (PyDict_Check(value.ptr())) return container(value, path, [&] { return object(value, path); });
    if (PyList_Check(value.ptr()) || PyTuple_Check(value.ptr()))
      return container(value, path, [&] { return array(value, path); });
    if (auto scalar = numpy_scalar(value, path)) return *scalar;
    if (PyIndex_Check(value.ptr())) return integer(value, path);
    not_a_scene_value(value, path);
  }

 private:
  // Converts a dict, list or tuple, refusing one that holds itself (it has no JSON form) and
  // nesting deeper than any scene.
  template <typename Convert>
  nlohmann::json container(py::handle value, const std::string& path, Convert convert) {
    if (std::find(open_.begin(), open_.end(), value.ptr()) != open_.end())
      throw py::value_error(path + ": the value contains itself (a circular reference)");
    if (open_.size() >= kMaxDepth)
      throw py::value_error(path + ": nested deeper than " + std::to_string(kMaxDepth) + " levels");
    open_.push_back(value.ptr());
    nlohmann::json j = convert();
    open_.pop_back();
    return j;
  }
  nlohmann::json object(py::handle dict, const std::string& path) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [key, item] : py::reinterpret_borrow<py::dict>(dict)) {
      if (!PyUnicode_Check(key.ptr()))
        throw py::value_error(path + ": the key " + std::string(py::repr(key)) + " is of type " + type_name(key) +
                              "; a scene's keys are str");
      const std::string name = utf8(key, path);
      j[name] = (*this)(item, member_path(path, name));
    }
    return j;
  }
  nlohmann::json array(py::handle sequence, const std::string& path) {
    nlohmann::json j = nlohmann::json::array();
    const auto items = py::reinterpret_borrow<py::sequence>(sequence);
    for (std::size_t i = 0; i < items.size(); ++i) j.push_back((*this)(py::object(items[i]), path + "[" + std::to_string(i) + "]"));
    return j;
  }

  static constexpr std::size_t kMaxDepth = 200;
  std::vector<PyObject*> open_;  // the containers being converted, outermost first
};

// The `set` overrides as invfem run's --set arguments, PATH=JSON; each value named set["PATH"].
std::vector<std::string> override_arguments(const py::dict& set) {
  std::vector<std::string> overrides;
  for (const auto& [key, value] : set) {
    if (!PyUnicode_Check(key.ptr()))
      throw py::value_error("set: the key " + std::string(py::repr(key)) + " is of type " + type_name(key) +
                            "; keys are field paths (str), e.g. \"solver.max_dt\"");
    const std::string field = utf8(key, "set");
    overrides.push_back(field + "=" + JsonFromPython{}(value, "set[" + nlohmann::json(field).dump() + "]").dump());
  }
  return overrides;
}

// The frame report as a dict: the stats.jsonl record of the frame (counts, Newton, each after-step
// pass's figures, seconds per phase) plus the energies [J].
py::dict report_dict(int frame, const World& world, const FrameReport& r) {
  py::dict d = py::module_::import("json").attr("loads")(stats_record(frame, world, r, FrameTimings{}));
  d["kinetic"] = r.kinetic;
  d["elastic"] = r.elastic;
  d["gravity"] = r.gravity;
  d["newton_converged"] = r.newton_capped == 0;
  return d;
}

// What a Python user holds: the session, its thread limit, and the frames pushed to driven bodies.
class Simulation {
 public:
  Simulation(const py::object& scene, const py::dict& set, bool quick, const py::object& out, const std::string& formats,
             bool overwrite, int threads, const py::object& base_dir, const std::string& memory_limit, bool strict) {
    if (threads < 0) throw py::value_error("threads must be >= 0 (0: all cores)");
    if (threads > 0)
      limit_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
    const std::vector<std::string> overrides = override_arguments(set);
    SessionOptions options;
    options.formats = parse_formats(formats);
    options.overwrite = overwrite;
    options.memory_limit = memory_limit;
    options.strict = strict;
    if (!out.is_none()) options.out = std::filesystem::path(py::str(out).cast<std::string>());
    Scene parsed;
    if (py::isinstance<py::dict>(scene)) {
      // A dict: relative paths resolve against base_dir (default: the working directory) and
      // errors name "<dict>" there.
      const std::filesystem::path dir =
          base_dir.is_none() ? std::filesystem::current_path() : std::filesystem::path(py::str(base_dir).cast<std::string>());
      parsed = scene_from_json(JsonFromPython{}(scene, "$"), dir / "<dict>", overrides, quick);
    } else {
      parsed = load_scene(std::filesystem::path(py::str(scene).cast<std::string>()), overrides, quick);
    }
    py::gil_scoped_release release;
    session_ = std::make_unique<Session>(std::move(parsed), std::move(options));
  }

  // What a property reads, f(session), taken under the call lock.
  template <typename Read>
  auto read(Read f) const {
    const CallLock lock(*this);
    return f(static_cast<const Session&>(*session_));
  }

  py::dict step_frame() {
    const CallLock lock(*this);
    FrameReport r;
    {
      py::gil_scoped_release release;
      r = session_->step_frame();
    }
    return report_dict(session_->frame(), session_->world(), r);
  }

  py::dict advance_to(double t) {
    const CallLock lock(*this);
    FrameReport r;
    {
      py::gil_scoped_release release;
      r = session_->advance_to(t);
    }
    return report_dict(session_->frame(), session_->world(), r);
  }

  py::array positions(const std::string& name) const {
    const CallLock lock(*this);
    if (const SimObject* o = find_object(name)) return points_array(o->body.x);
    if (const KinematicBody* k = body_with_surface(name)) return points_array(k->surface()->x);
    unknown(name);
  }
  py::array velocities(const std::string& name) const {
    const CallLock lock(*this);
    if (const SimObject* o = find_object(name)) return points_array(o->body.v);
    if (const KinematicBody* k = body_with_surface(name)) return points_array(k->surface_velocities());
    unknown(name);
  }
  py::dict surface(const std::string& name) const {
    const CallLock lock(*this);
    const TriangleSurface* s = nullptr;
    py::dict d;
    if (const SimObject* o = find_object(name)) {
      s = &o->material_surface();
      if (o->embedded.empty()) d["nodes"] = int_vector_array(o->surface_nodes);
    } else if (const KinematicBody* k = body_with_surface(name)) {
      s = k->surface();
    } else {
      unknown(name);
    }
    d["vertices"] = points_array(s->x);
    d["triangles"] = index_array(s->tris);
    d["uv"] = uv_array(s->uv);
    d["uv_triangles"] = index_array(s->uv_tris);
    return d;
  }
  py::array tets(const std::string& name) const {
    const CallLock lock(*this);
    return index_array(object(name).tets);
  }
  py::dict element_fields(const std::string& name) const {
    const CallLock lock(*this);
    CellFields fields;
    for (const auto& f : object(name).forces) f->add_cell_fields(fields);
    py::dict d;
    for (const auto& [key, values] : fields) d[py::str(key)] = vector_array(values);
    return d;
  }

  // Frames from Python for a sequence collider (BodySequence::set_frame_source): `source(k)`
  // returns frame k as the file would hold it, (V, 3) float64; None returns to the files.
  void drive_body(const std::string& name, const py::object& source) {
    const CallLock lock(*this);
    BodySequence& body = sequence(name);
    if (!source.is_none() && !PyCallable_Check(source.ptr()))
      throw py::type_error("drive_body: the source must be callable (k -> (V, 3) array) or None");
    // The pushed frames' source reads pushed_[name]: replaced before that entry goes.
    if (source.is_none()) {
      body.set_frame_source({}, "");
      pushed_.erase(name);
      return;
    }
    auto fn = std::make_shared<py::object>(source);
    try {  // the source is set even when placing the body with it throws (a bad first frame)
      body.set_frame_source(
          [fn](int k) {
            py::gil_scoped_acquire gil;
            return points_from(py::object((*fn)(k)), "drive_body: frame " + std::to_string(k));
          },
          "body \"" + name + "\" (driven from Python)");
    } catch (...) {
      pushed_.erase(name);
      throw;
    }
    pushed_.erase(name);
  }

  // Gives frame k of a driven sequence body (switching it to the pushed frames at the first call).
  // A step that reaches frame time k / fps needs frames up to k + 1: the velocity at a frame time
  // is that of the interval after it, as for a mesh sequence (body_sequence.hpp).
  void set_body_frame(const std::string& name, int k, const py::object& x) {
    const CallLock lock(*this);
    BodySequence& body = sequence(name);
    if (k < 0 || k >= body.frame_count())
      throw py::index_error("set_body_frame: frame " + std::to_string(k) + " outside the sequence's 0-" +
                            std::to_string(body.frame_count() - 1));
    Points p = points_from(x, "set_body_frame: frame " + std::to_string(k));
    const bool first = !pushed_.count(name);
    auto& frames = pushed_[name];
    frames[k] = std::move(p);
    if (first) {
      // Installed at the first frame given; placing the body now needs the frames around the
      // current time, which may come next: until then it stays where it is (MeshError caught).
      const std::map<int, Points>* held = &frames;
      try {
        body.set_frame_source(
          [held, name](int f) {
            const auto it = held->find(f);
            if (it == held->end())
              throw MeshError("body \"" + name + "\": frame " + std::to_string(f) +
                              " was not given (set_body_frame) before a step needed it");
            return it->second;
          },
          "body \"" + name + "\" (frames given from Python)");
      } catch (const MeshError&) {
      }
    }
  }

  std::string save_checkpoint(const std::string& dir) {
    const CallLock lock(*this);
    py::gil_scoped_release release;
    return session_->save_checkpoint(dir).string();
  }
  void load_checkpoint(const std::string& file) {
    const CallLock lock(*this);
    py::gil_scoped_release release;
    session_->load_checkpoint(file);
  }

 private:
  // Held for the whole of a call that touches the session: calls from several threads run one at
  // a time. The GIL is released while waiting, since the holder may need it before it lets go (a
  // drive_body source, building its result). A call from inside a call on the same thread (a
  // drive_body source calling back into its Simulation) would wait for itself: it raises instead.
  class CallLock {
   public:
    explicit CallLock(const Simulation& s) : s_(s), lock_(s.mutex_, std::defer_lock) {
      if (s.holder_.load() == std::this_thread::get_id())
        throw std::runtime_error("Simulation: called from inside one of its own calls on the same thread (a drive_body "
                                 "source calling back into its Simulation); that call would wait for itself");
      if (!lock_.try_lock()) {
        py::gil_scoped_release release;
        lock_.lock();
      }
      s.holder_ = std::this_thread::get_id();
    }
    ~CallLock() { s_.holder_ = std::thread::id(); }
    CallLock(const CallLock&) = delete;
    CallLock& operator=(const CallLock&) = delete;

   private:
    const Simulation& s_;
    std::unique_lock<std::mutex> lock_;
  };

  const SimObject* find_object(const std::string& name) const {
    for (const SimObject& o : session_->world().objects())
      if (o.name == name) return &o;
    return nullptr;
  }
  KinematicBody* find_body(const std::string& name) const {
    for (const auto& k : session_->world().kinematic_bodies())
      if (k->name() == name) return k.get();
    return nullptr;
  }
  [[noreturn]] void unknown(const std::string& name) const {
    std::string known;
    for (const SimObject& o : session_->world().objects()) known += (known.empty() ? "" : ", ") + o.name;
    for (const auto& k : session_->world().kinematic_bodies()) known += (known.empty() ? "" : ", ") + k->name();
    throw py::key_error("no object or body \"" + name + "\" (the scene has: " + known + ")");
  }
  // A kinematic body by name, nullptr when there is none; ValueError for one without a surface.
  const KinematicBody* body_with_surface(const std::string& name) const {
    const KinematicBody* k = find_body(name);
    if (k && !k->surface())
      throw py::value_error("\"" + name + "\" is a kinematic body with no surface (an infinite plane): it has no "
                            "vertices, velocities or triangles");
    return k;
  }
  const SimObject& object(const std::string& name) const {
    if (const SimObject* o = find_object(name)) return *o;
    if (find_body(name)) throw py::value_error("\"" + name + "\" is a kinematic body, not a simulated object");
    unknown(name);
  }

  BodySequence& sequence(const std::string& name) {
    KinematicBody* k = find_body(name);
    if (!k) {
      if (find_object(name)) throw py::value_error("\"" + name + "\" is a simulated object, not a sequence body");
      unknown(name);
    }
    for (const auto& s : session_->colliders().sequences)
      if (s->name() == name) return *s;
    throw py::value_error("\"" + name + "\" is not a sequence collider (\"type\": \"sequence\"): only those are driven by frames");
  }

  std::unique_ptr<tbb::global_control> limit_;
  std::unique_ptr<Session> session_;
  std::map<std::string, std::map<int, Points>> pushed_;  // per body, the frames given by set_body_frame
  mutable std::mutex mutex_;                              // held by CallLock
  mutable std::atomic<std::thread::id> holder_;           // the thread holding mutex_, if any
};

py::dict check_surfaces(const py::list& surfaces, const py::object& welds, const py::object& count_self, int max_examples) {
  std::vector<TriangleSurface> held(surfaces.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const py::object item = surfaces[i];
    const py::tuple pair = py::tuple(item);  // a tuple or a list
    if (pair.size() != 2) throw py::value_error("check: each surface is a pair (vertices (n, 3), triangles (m, 3))");
    const std::string what = "check: surface " + std::to_string(i);
    held[i].x = points_from(pair[0], what + " vertices");
    held[i].tris = tris_from(pair[1], what + " triangles");
    held[i].source = what;
  }
  std::vector<const TriangleSurface*> pointers;
  for (const auto& s : held) pointers.push_back(&s);
  std::vector<certificate::SurfaceWelds> w;
  if (!welds.is_none()) {
    for (const auto& item : welds.cast<py::list>()) {
      certificate::SurfaceWelds sw;
      if (!item.is_none()) {
        const py::array_t<int, py::array::c_style | py::array::forcecast> a(py::reinterpret_borrow<py::object>(item));
        if (a.ndim() != 2 || a.shape(1) != 2)
          throw py::value_error("check: welds are (k, 2) index pairs per surface (or None)");
        for (py::ssize_t r = 0; r < a.shape(0); ++r) sw.same_point.push_back({a.at(r, 0), a.at(r, 1)});
      }
      w.push_back(std::move(sw));
    }
    if (w.size() != held.size()) throw py::value_error("check: welds has " + std::to_string(w.size()) +
                                                       " entries for " + std::to_string(held.size()) + " surfaces");
  }
  std::vector<char> self;
  if (!count_self.is_none())
    for (const auto& item : count_self.cast<py::list>()) self.push_back(item.cast<bool>() ? 1 : 0);
  certificate::IntersectionCount c;
  {
    py::gil_scoped_release release;
    try {
      c = certificate::count_intersections(pointers, w, max_examples, self);
    } catch (const std::invalid_argument& e) {
      throw py::value_error(e.what());
    }
  }
  py::dict d;
  d["total"] = c.total();
  d["self"] = c.self;
  py::dict cross;
  for (const auto& [pair, n] : c.cross) cross[py::make_tuple(pair.first, pair.second)] = n;
  d["cross"] = cross;
  d["candidates"] = c.candidates;
  py::list examples;
  for (const auto& p : c.examples) examples.append(py::make_tuple(p.surface_a, p.triangle_a, p.surface_b, p.triangle_b));
  d["examples"] = examples;
  return d;
}

}  // namespace

PYBIND11_MODULE(_invfem, m) {
  m.doc() = "invfem's extension module (import invfem): invertible finite elements for cloth, shells and solids";
  m.attr("__version__") = INVFEM_VERSION;
  // Bad input is a ValueError naming the file and the JSON path, as the command line's exit 2.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const MeshError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const OutputError& e) {  // a file that cannot be written: the command line's exit 2
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });

  py::class_<Simulation>(m, "Simulation",
                         "A scene built and stepped in this process (invfem run's world, checks and writers).")
      .def(py::init<const py::object&, const py::dict&, bool, const py::object&, const std::string&, bool, int,
                    const py::object&, const std::string&, bool>(),
           py::arg("scene"), py::kw_only(), py::arg("set") = py::dict(), py::arg("quick") = false,
           py::arg("out") = py::none(), py::arg("formats") = "obj", py::arg("overwrite") = false,
           py::arg("threads") = 0, py::arg("base_dir") = py::none(), py::arg("memory_limit") = "",
           py::arg("strict") = false,
           "scene: a scene file's path, or a dict with the same schema (relative paths against base_dir, default "
           "the working directory). set: {\"path.to.field\": value} overrides (invfem run --set); quick: the "
           "scene's quick overrides. out: a run folder written as invfem run --out writes it (scene.json, frame 0 "
           "now, each step_frame's frame after), in `formats` (\"obj,usd,...\"). threads: worker threads (0: "
           "all cores). memory_limit: a scene whose estimated memory exceeds it is refused (invfem run "
           "--memory-limit: \"16G\", \"none\"; \"\": 80% of the machine's). strict: a warning at load (a cloth "
           "starting through a body, ...) refuses the scene (invfem run --strict). A bad field raises ValueError "
           "naming its JSON path; an output that cannot be written, OSError.")
      .def_property_readonly("time", [](const Simulation& s) { return s.read([](const Session& x) { return x.world().time(); }); },
                             "the simulated time [s]")
      .def_property_readonly("frame", [](const Simulation& s) { return s.read([](const Session& x) { return x.frame(); }); },
                             "the last whole frame reached (frame k is at t = k / fps)")
      .def_property_readonly("fps", [](const Simulation& s) { return s.read([](const Session& x) { return x.scene().fps; }); },
                             "the scene's frames per second")
      .def_property_readonly("frames", [](const Simulation& s) { return s.read([](const Session& x) { return x.scene().frames; }); },
                             "the scene's frames after frame 0")
      .def_property_readonly("objects",
                             [](const Simulation& s) {
                               return s.read([](const Session& x) {
                                 std::vector<std::string> names;
                                 for (const SimObject& o : x.world().objects()) names.push_back(o.name);
                                 return names;
                               });
                             },
                             "the simulated objects' names (solids and cloths)")
      .def_property_readonly("bodies",
                             [](const Simulation& s) {
                               return s.read([](const Session& x) {
                                 std::vector<std::string> names;
                                 for (const auto& k : x.world().kinematic_bodies()) names.push_back(k->name());
                                 return names;
                               });
                             },
                             "the kinematic bodies' names (colliders)")
      .def("step_frame", &Simulation::step_frame,
           "Advances one frame (written to `out` when given); returns the frame's report: substeps, cg_iterations, "
           "newton_iterations, newton_capped, newton_converged, each after-step pass's figures (self_collision: "
           "proximity_impulses, ccd_hits, impact_zones, ...), seconds per phase and the energies [J].")
      .def("advance_to", &Simulation::advance_to, py::arg("t"),
           "Advances to time t [s] (>= time), writing nothing; returns the report of the steps taken.")
      .def("positions", &Simulation::positions, py::arg("name"),
           "An object's node positions, or a body's surface vertices: (n, 3) float64 [m]. ValueError for a body "
           "with no surface (an infinite plane).")
      .def("velocities", &Simulation::velocities, py::arg("name"), "As positions: (n, 3) float64 [m/s].")
      .def("surface", &Simulation::surface, py::arg("name"),
           "The written surface: vertices (V, 3) float64, triangles (F, 3) int32, uv (U, 2) float64 and "
           "uv_triangles (F, 3) int32 (the pattern's UVs; empty when none), and for an object nodes (V,) int32, "
           "the node of each vertex.")
      .def("tets", &Simulation::tets, py::arg("name"), "A solid's tets, (T, 4) int32 node indices; (0, 4) for a cloth.")
      .def("element_fields", &Simulation::element_fields, py::arg("name"),
           "Per-element quantities as the VTU frames hold them, e.g. det_F and inverted (0/1) per tet: {name: (T,) float64}.")
      .def("drive_body", &Simulation::drive_body, py::arg("name"), py::arg("source"),
           "Frames of a sequence collider from Python: source(k) returns frame k as its file would hold it, (V, 3) "
           "float64 before the collider's transform; interpolated, checked and collided as file frames are. None "
           "returns to the files. The topology stays that of the scene's frame 0 file.")
      .def("set_body_frame", &Simulation::set_body_frame, py::arg("name"), py::arg("k"), py::arg("x"),
           "Gives frame k of a sequence collider, (V, 3) float64 as its file would hold it. A step to frame time "
           "k / fps needs frames up to k + 1 (the velocity at a frame time is the next interval's).")
      .def("save_checkpoint", &Simulation::save_checkpoint, py::arg("dir"),
           "Writes DIR/checkpoints/NNNN.ckpt (invfem run's format) at a whole frame; returns its path.")
      .def("load_checkpoint", &Simulation::load_checkpoint, py::arg("path"),
           "Restores a checkpoint of this scene; stepping on is bit-identical to the run that wrote it.");

  m.def("check", &check_surfaces, py::arg("surfaces"), py::arg("welds") = py::none(), py::arg("count_self") = py::none(),
        py::arg("max_examples") = 10,
        "The intersection certificate (invfem check) on arrays. surfaces: [(vertices (n, 3), triangles (m, 3)), ...]; "
        "welds: per surface None or (k, 2) vertex pairs that are one seam point; count_self: per surface whether its "
        "own pairs count. Returns {total, self: [per surface], cross: {(a, b): pairs}, candidates, examples: "
        "[(surface_a, triangle_a, surface_b, triangle_b)]}.");
}
