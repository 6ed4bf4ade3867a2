// SPDX-License-Identifier: GPL-3.0-or-later
// The C++ half of the Python module `libshadow` (pybind11): scenes, the engine, results as numpy
// arrays, output files and the sun. The pure-Python half (python/libshadow/__init__.py) builds
// scenes from Python data, adds to_pandas() and sun hours. Only the public API (shadow/*.hpp)
// is used: the module is a client of the library like the CLI.
#include <shadow/shadow.hpp>
#include <shadow/series_files.hpp>
#include <shadow/sun.hpp>
#include <shadow/radiosity.hpp>
#include <shadow/series.hpp>
#include <shadow/sun_hours.hpp>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace py = pybind11;
using namespace shadow;

namespace {

using ScenePtr = std::shared_ptr<Scene>;

// ---- the GIL, Ctrl-C and the interpreter's exit ----------------------------------------------
//
// Long calls run with the GIL released. Two things must never happen then: a thread taking the
// GIL back while the interpreter finalizes (CPython ends such a thread with pthread_exit, whose
// forced unwinding through the library's catch (...) aborts the process: "FATAL: exception not
// rethrown"), and a call that ignores Ctrl-C until it is done. So every released call is
// counted; at exit (an atexit hook, which runs before finalization) the running calls are told
// to stop through their progress callbacks, which then throw without taking the GIL, and the
// hook waits for them; a call that ends after that never takes the GIL again but parks its
// thread until the process is gone.

std::mutex g_calls_mutex;
std::condition_variable g_calls_done;
std::size_t g_calls = 0;               ///< calls running with the GIL released
std::atomic<bool> g_exiting{false};    ///< set by the atexit hook: stop, never take the GIL again

bool interpreter_exiting() {
  if (g_exiting.load()) return true;
#if PY_VERSION_HEX >= 0x030D0000
  return Py_IsFinalizing() != 0;
#else
  return _Py_IsFinalizing() != 0;
#endif
}

/// The error a computation stops with when the interpreter exits (never seen by Python code).
class InterpreterExiting : public std::runtime_error {
 public:
  InterpreterExiting() : std::runtime_error("the Python interpreter is exiting") {}
};

[[noreturn]] void park_forever() {
  for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
}

/// Runs f() with the GIL released (called with it held), counted for the exit hook.
template <class F>
auto without_gil(F&& f) -> decltype(f()) {
  using R = decltype(f());
  if (interpreter_exiting()) throw std::runtime_error("the Python interpreter is exiting: no new computation");
  {
    std::lock_guard<std::mutex> lock(g_calls_mutex);
    ++g_calls;
  }
  PyThreadState* state = PyEval_SaveThread();
  std::exception_ptr error;
  std::conditional_t<std::is_void_v<R>, bool, std::optional<R>> result{};
  try {
    if constexpr (std::is_void_v<R>) f();
    else result.emplace(f());
  } catch (...) {
    error = std::current_exception();
  }
  {
    std::lock_guard<std::mutex> lock(g_calls_mutex);
    --g_calls;
  }
  g_calls_done.notify_all();
  // Taking the GIL now would end this thread by force: leave it parked (the process is ending).
  if (interpreter_exiting()) park_forever();
  PyEval_RestoreThread(state);
  if (error) std::rethrow_exception(error);
  if constexpr (!std::is_void_v<R>) return std::move(*result);
}

/// The atexit hook: stop the running calls and wait for them (at most a while: one that does not
/// stop in time is left to park when it ends).
void stop_calls_at_exit() {
  g_exiting.store(true);
  py::gil_scoped_release release;
  std::unique_lock<std::mutex> lock(g_calls_mutex);
  g_calls_done.wait_for(lock, std::chrono::seconds(30), [] { return g_calls == 0; });
}

/// A scene argument that may not be None (a None shared_ptr would be dereferenced).
const Scene& need_scene(const ScenePtr& scene, const char* what = "scene") {
  if (!scene) throw py::type_error(std::string(what) + ": expected a libshadow.Scene, got None");
  return *scene;
}

/// An index argument: any Python integer (numpy's too); a negative or too large one is an
/// IndexError in words, anything else a TypeError.
std::size_t index_arg(const py::handle& value, std::size_t size, const char* what, const char* owner, const char* noun) {
  if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr()))
    throw py::type_error(std::string(what) + ": expected an integer, got " +
                         py::str(py::type::of(value).attr("__name__")).cast<std::string>());
  const py::int_ i = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  if (!i) {  // an array, say
    PyErr_Clear();
    throw py::type_error(std::string(what) + ": expected one integer, got " +
                         py::str(py::type::of(value).attr("__name__")).cast<std::string>());
  }
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow == 0 && v >= 0 && static_cast<unsigned long long>(v) < size) return static_cast<std::size_t>(v);
  throw py::index_error(std::string(what) + " " + py::str(py::handle(i)).cast<std::string>() + " is out of range (" +
                        owner + " has " + std::to_string(size) + " " + noun + (size == 1 ? "" : "s") +
                        (size == 0 ? "" : ": 0 to " + std::to_string(size - 1)) + ")");
}

/// A finite number of hours per instant, >= 0 (a negative or NaN weight made negative or NaN
/// sun hours).
double hours_arg(double hours) {
  if (!std::isfinite(hours) || hours < 0)
    throw py::value_error("hours_per_instant must be a finite number of hours >= 0, got " +
                          py::repr(py::float_(hours)).cast<std::string>());
  return hours;
}

/// A site checked as a scene's sun block checks it (latitude in [-90, 90], ...).
void check_site(const SolarSite& site, const char* place) {
  SunPeriod p;
  p.site = site;
  p.times = {0};
  check_sun_period(p, "", place);
}

py::array_t<double> vec3_array(const glm::dvec3& v) {
  py::array_t<double> a(3);
  auto m = a.mutable_unchecked<1>();
  for (int i = 0; i < 3; ++i) m(i) = v[i];
  return a;
}

glm::dvec3 to_vec3(const py::handle& h, const char* what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a || a.ndim() != 1 || a.shape(0) != 3)
    throw py::value_error(std::string(what) + ": expected 3 numbers [x, y, z]");
  return {a.at(0), a.at(1), a.at(2)};
}

/// Polygon vertices as an (n, 3) float64 array.
py::array_t<double> polygon_array(const std::vector<glm::dvec3>& vertices) {
  py::array_t<double> a({static_cast<py::ssize_t>(vertices.size()), py::ssize_t{3}});
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < vertices.size(); ++i)
    for (int c = 0; c < 3; ++c) m(static_cast<py::ssize_t>(i), c) = vertices[i][c];
  return a;
}

template <class T, class Item, class Get>
py::array_t<T> column(const std::vector<Item>& items, Get get) {
  py::array_t<T> a(static_cast<py::ssize_t>(items.size()));
  T* out = a.mutable_data();
  for (std::size_t i = 0; i < items.size(); ++i) out[i] = static_cast<T>(get(items[i]));
  return a;
}

Arithmetic parse_arithmetic(const std::string& name) {
  if (name == "exact") return Arithmetic::Exact;
  if (name == "fast") return Arithmetic::Fast;
  throw py::value_error("arithmetic must be \"exact\" or \"fast\", got \"" + name + "\"");
}

std::string arithmetic_name(Arithmetic a) { return a == Arithmetic::Fast ? "fast" : "exact"; }

/// The engine's progress hook, run about every 100 ms by the thread that waits for the workers:
/// it raises a pending signal (Ctrl-C, a Jupyter kernel interrupt) as the Python exception,
/// which stops the computation, then calls the user's callback, if any, whose exceptions stop
/// it too. The GIL is taken only for that, and never once the interpreter exits: then the hook
/// stops the computation without it.
std::function<void(const Progress&)> wrap_progress(const py::object& callback) {
  std::shared_ptr<py::object> holder;
  if (!callback.is_none()) {
    if (!PyCallable_Check(callback.ptr()))
      throw py::type_error("progress: expected a callable(done, total) or None, got " +
                           py::str(py::type::of(callback).attr("__name__")).cast<std::string>());
    // The last copy of the callback may be dropped on any thread: take the GIL to release it
    // (and leak it when the interpreter is going away).
    holder.reset(new py::object(callback), [](py::object* o) {
      if (interpreter_exiting()) return;
      py::gil_scoped_acquire gil;
      delete o;
    });
  }
  // The engine may report a value again (at its end, after a tick that saw it): the callback
  // hears each (done, total) once, done never going back.
  auto last = std::make_shared<std::optional<Progress>>();
  return [holder, last](const Progress& p) {
    if (interpreter_exiting()) throw InterpreterExiting();
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (*last && (*last)->total == p.total && p.done <= (*last)->done) return;
    *last = p;
    if (holder) (*holder)(p.done, p.total);
  };
}

ShadowOptions make_options(unsigned threads, bool polygons, const std::optional<std::vector<std::size_t>>& lights,
                           const std::string& arithmetic, bool planes, double plane_window,
                           const py::object& progress, std::size_t tile_casters = ShadowOptions{}.tile_casters,
                           std::size_t fast_tile_casters = ShadowOptions{}.fast_tile_casters) {
  if (!std::isfinite(plane_window) || plane_window < 0 || plane_window > std::ldexp(1.0, 500))
    throw py::value_error("plane_window must be a finite number from 0 to 2**500, got " +
                          py::repr(py::float_(plane_window)).cast<std::string>());
  ShadowOptions o;
  o.tile_casters = tile_casters;
  o.fast_tile_casters = fast_tile_casters;
  o.threads = threads;
  o.polygons = polygons;
  if (lights) o.lights = *lights;
  o.arithmetic = parse_arithmetic(arithmetic);
  o.planes = planes;
  o.plane_window = plane_window;
  o.progress = wrap_progress(progress);
  return o;
}

/// A result with the scene it belongs to (write_outputs and face labels need the scene).
struct Result {
  ScenePtr scene;
  ShadowResult result;
};

struct Engine {
  ScenePtr scene;
  std::unique_ptr<ShadowEngine> engine;
};

/// A series (faces x instants) with its scene and its suns.
struct Series {
  ScenePtr scene;
  SeriesResult result;
  std::vector<Light> lights;
  std::vector<UtcSeconds> times;  ///< the instants' UTC times when they are the scene's suns
};

/// The scene file's name of a light type.
std::string light_type_name(LightType type) {
  switch (type) {
    case LightType::Point: return "point";
    case LightType::Area: return "area";
    case LightType::Disk: return "disk";
    case LightType::Directional: break;
  }
  return "directional";
}

/// A row-major rows x cols table as a 2-D numpy array.
template <class T, class Source>
py::array_t<T> table(const std::vector<Source>& values, std::size_t rows, std::size_t cols) {
  py::array_t<T> a({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  T* out = a.mutable_data();
  for (std::size_t i = 0; i < rows * cols && i < values.size(); ++i) out[i] = static_cast<T>(values[i]);
  return a;
}

std::shared_ptr<Result> run_compute(const ScenePtr& scene, ShadowOptions options,
                                    const std::function<ShadowResult(const ShadowOptions&)>& compute) {
  auto out = std::make_shared<Result>();
  out->scene = scene;
  out->result = without_gil([&] { return compute(options); });
  return out;
}

UtcSeconds to_utc(const py::handle& t) {
  if (py::isinstance<py::str>(t)) {
    const std::string text = t.cast<std::string>();
    const std::optional<UtcSeconds> s = parse_iso8601(text);
    if (!s) throw py::value_error("not an ISO 8601 time with Z or an offset: \"" + text + "\"");
    return *s;
  }
  const py::module_ datetime = py::module_::import("datetime");
  if (py::isinstance(t, datetime.attr("datetime"))) {
    if (t.attr("tzinfo").is_none() || t.attr("utcoffset")().is_none())
      throw py::value_error("a naive datetime has no time zone: give tzinfo (datetime.timezone.utc, say)");
    // Whole seconds, truncated like parse_iso8601 does with fractions.
    const py::object epoch = datetime.attr("datetime")(1970, 1, 1, 0, 0, 0, 0, datetime.attr("timezone").attr("utc"));
    const py::object delta = t - epoch;
    const long long days = delta.attr("days").cast<long long>();
    const long long seconds = delta.attr("seconds").cast<long long>();
    return static_cast<UtcSeconds>(days * 86400 + seconds);
  }
  if (PyBool_Check(t.ptr()))
    throw py::type_error("time: expected UTC seconds, an ISO 8601 string or an aware datetime, got a bool");
  // float, numpy floating scalars and 0-d arrays: whole seconds, rounded down like fractions of
  // an ISO 8601 time are dropped (toward the past).
  if (PyFloat_Check(t.ptr()) || (py::hasattr(t, "dtype") && py::hasattr(t, "__float__") &&
                                 py::str(t.attr("dtype").attr("kind")).cast<std::string>() == "f" &&
                                 py::len(t.attr("shape")) == 0)) {
    const double v = py::float_(py::reinterpret_borrow<py::object>(t)).cast<double>();
    if (!std::isfinite(v) || std::abs(v) >= 9.2e18)
      throw py::value_error("time: expected finite UTC seconds within 64 bits, got " +
                            py::repr(py::float_(v)).cast<std::string>());
    return static_cast<UtcSeconds>(std::floor(v));
  }
  if (PyIndex_Check(t.ptr())) {  // int, numpy integers (an array of them is refused below)
    const py::int_ i = py::reinterpret_steal<py::int_>(PyNumber_Index(t.ptr()));
    if (!i) {
      PyErr_Clear();
      throw py::type_error("time: expected one time, got " + py::str(py::type::of(t).attr("__name__")).cast<std::string>() +
                           " (solar_positions takes many)");
    }
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
    if (overflow != 0)
      throw py::value_error("time: " + py::str(py::handle(i)).cast<std::string>() + " UTC seconds is out of range (64 bits)");
    return static_cast<UtcSeconds>(v);
  }
  throw py::type_error("time: expected UTC seconds (int or float), an ISO 8601 string or an aware datetime, got " +
                       py::str(py::type::of(t).attr("__name__")).cast<std::string>());
}

py::dict stats_dict(const ShadowStats& s) {
  py::dict d;
  d["receivers"] = s.receivers;
  d["back_facing"] = s.back_facing;
  d["candidate_pairs"] = s.candidate_pairs;
  d["casting_pairs"] = s.casting_pairs;
  d["unshadowed"] = s.unshadowed;
  d["fast_exact_fallbacks"] = s.fast_exact_fallbacks;
  d["fast_collapsed"] = s.fast_collapsed;
  d["tiled_receivers"] = s.tiled_receivers;
  d["tiles"] = s.tiles;
  return d;
}

}  // namespace

void bind_irradiance(py::module_& m);  // irradiance_module.cpp

PYBIND11_MODULE(_libshadow, m) {
  m.doc() = "libshadow's C++ core (pybind11): its classes and functions are libshadow's, imported from\n"
            "there (import libshadow; see help(libshadow) and docs/python.md).";
  // Everything here is used as libshadow.X: while the classes and functions are made, the module
  // goes by that name, so their __module__, reprs and the types in docstrings say `libshadow.`.
  const py::object own_name = m.attr("__name__");
  m.attr("__name__") = "libshadow";
  m.attr("__version__") = version();

  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  input_error.doc() = "Bad input: one line 'FILE: PLACE: PROBLEM', as the shadow CLI prints it.";
  static py::exception<OutputError> output_error(m, "OutputError", PyExc_OSError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      input_error(e.what());
    } catch (const OutputError& e) {
      output_error(e.what());
    } catch (const py::reference_cast_error&) {
      // None where a libshadow object is needed (pybind11's own text is empty).
      PyErr_SetString(PyExc_TypeError, "an argument that must be a libshadow object was None");
    }
  });
  // Stop computations still running in other threads before the interpreter finalizes.
  py::module_::import("atexit").attr("register")(py::cpp_function(&stop_calls_at_exit));

  // ---- scene ------------------------------------------------------------------------------------
  py::class_<Mesh>(m, "Mesh", "A named group of consecutive faces.")
      .def_readonly("name", &Mesh::name)
      .def_readonly("file", &Mesh::file, "OBJ path as written in the scene ('' for inline polygons)")
      .def_readonly("first_face", &Mesh::first_face)
      .def_readonly("face_count", &Mesh::face_count)
      .def_readonly("receiver", &Mesh::receiver)
      .def_readonly("material", &Mesh::material)
      .def_readonly("orient_outward", &Mesh::orient_outward)
      .def_readonly("object_type", &Mesh::object_type,
                    "the CityJSON city object's type ('Building', 'BuildingPart', ...), 'zone' for an EnergyPlus\n"
                    "zone, '' otherwise")
      .def_readonly("parent", &Mesh::parent,
                    "CityJSON: the top-level city object this one is part of (named like meshes), or ''")
      .def_readonly("parent_type", &Mesh::parent_type, "the CityJSON type of parent, or ''")
      .def_readonly("scene_mesh", &Mesh::scene_mesh,
                    "a model's mesh read through a scene file's mesh: that mesh's name, which selects them all; ''\n"
                    "otherwise")
      .def("__repr__", [](const Mesh& x) {
        return "Mesh(name=" + py::repr(py::str(x.name)).cast<std::string>() + ", faces=" +
               std::to_string(x.face_count) + ", receiver=" + (x.receiver ? "True" : "False") + ")";
      });

  py::class_<Light>(m, "Light", "A light: directional (to_light, toward the light) or point (position).")
      .def(py::init([](const std::string& name, const std::string& type, const py::object& to_light,
                       const py::object& position, double intensity, const py::object& color) {
             Light l;
             l.name = name;
             if (type == "directional") l.type = LightType::Directional;
             else if (type == "point") l.type = LightType::Point;
             else throw py::value_error("light type must be \"directional\" or \"point\", got \"" + type + "\"");
             if (!to_light.is_none()) l.to_light = to_vec3(to_light, "to_light");
             if (!position.is_none()) l.position = to_vec3(position, "position");
             l.intensity = intensity;
             if (!color.is_none()) l.color = to_vec3(color, "color");
             return l;
           }),
           py::arg("name") = "", py::arg("type") = "directional", py::arg("to_light") = py::none(),
           py::arg("position") = py::none(), py::arg("intensity") = 1.0, py::arg("color") = py::none())
      .def_readonly("name", &Light::name)
      .def_property_readonly("type", [](const Light& l) { return light_type_name(l.type); })
      .def_property_readonly("to_light", [](const Light& l) { return vec3_array(l.to_light); })
      .def_property_readonly("position", [](const Light& l) { return vec3_array(l.position); })
      .def_readonly("intensity", &Light::intensity)
      .def_property_readonly("color", [](const Light& l) { return vec3_array(l.color); })
      .def("__repr__", [](const Light& l) {
        return "Light(name=" + py::repr(py::str(l.name)).cast<std::string>() + ", type='" +
               light_type_name(l.type) + "')";
      });

  py::class_<Plane>(m, "Plane", "An infinite receiving plane n . (x - point) = 0.")
      .def_readonly("name", &Plane::name)
      .def_property_readonly("point", [](const Plane& p) { return vec3_array(p.point); })
      .def_property_readonly("normal", [](const Plane& p) { return vec3_array(p.normal); })
      .def_readonly("window", &Plane::window);

  py::class_<Material>(m, "Material")
      .def_readonly("name", &Material::name)
      .def_readonly("k_a", &Material::k_a)
      .def_readonly("k_d", &Material::k_d)
      .def_readonly("k_s", &Material::k_s)
      .def_readonly("shininess", &Material::shininess)
      .def_property_readonly("color", [](const Material& x) { return vec3_array(x.color); })
      .def_property_readonly("specular_color", [](const Material& x) { return vec3_array(x.specular_color); })
      .def_readonly("reflectance", &Material::reflectance)
      .def_property_readonly("reflectance_rgb", [](const Material& x) { return vec3_array(x.reflectance_rgb); })
      .def_readonly("emittance", &Material::emittance);

  py::class_<NamedSurface>(m, "NamedSurface", "Faces sharing a name, or one unnamed face (label face_<id>).")
      .def_readonly("label", &NamedSurface::label)
      .def_readonly("faces", &NamedSurface::faces);

  py::class_<SceneObject>(m, "SceneObject",
                          "An object of the scene, the unit of sun hours per object: a CityJSON top-level city object\n"
                          "with its parts, an EnergyPlus zone, or any other mesh (Scene.objects()).")
      .def_readonly("id", &SceneObject::id, "its name: a mesh name, or a CityJSON parent's name as a mesh would have it")
      .def_readonly("type", &SceneObject::type, "the CityJSON type, 'zone' or 'mesh'")
      .def_readonly("meshes", &SceneObject::meshes, "indices into Scene.meshes")
      .def("__repr__", [](const SceneObject& x) {
        return "SceneObject(id=" + py::repr(py::str(x.id)).cast<std::string>() + ", type=" +
               py::repr(py::str(x.type)).cast<std::string>() + ", meshes=" + std::to_string(x.meshes.size()) + ")";
      });

  // Registered before the sun functions below name it (else their docstrings show `shadow::Scene`).
  py::class_<Scene, ScenePtr> scene_class(m, "Scene", "A validated scene: meshes of planar faces, lights, planes.");

  // ---- sun --------------------------------------------------------------------------------------
  py::class_<SolarSite> solar_site(m, "SolarSite",
                                   "Where the sun is seen from (degrees, metres, millibars, Celsius); checked\n"
                                   "like a scene's sun block (latitude in [-90, 90], ...): ValueError otherwise.");
  solar_site.def(py::init([](double latitude, double longitude, double elevation, double pressure, double temperature) {
                   SolarSite site{latitude, longitude, elevation, pressure, temperature};
                   check_site(site, "SolarSite");
                   return site;
                 }),
                 py::arg("latitude"), py::arg("longitude"), py::arg("elevation") = 0.0,
                 py::arg("pressure") = 1013.25, py::arg("temperature") = 12.0);
  // Each field checked when set, the site left as it was when the value is refused.
  auto site_field = [&solar_site](const char* name, double SolarSite::*field) {
    solar_site.def_property(
        name, [field](const SolarSite& s) { return s.*field; },
        [field](SolarSite& s, double value) {
          SolarSite changed = s;
          changed.*field = value;
          check_site(changed, "SolarSite");
          s = changed;
        });
  };
  site_field("latitude", &SolarSite::latitude);
  site_field("longitude", &SolarSite::longitude);
  site_field("elevation", &SolarSite::elevation);
  site_field("pressure", &SolarSite::pressure);
  site_field("temperature", &SolarSite::temperature);

  py::class_<SunPosition>(m, "SunPosition", "The sun seen from a site (topocentric, refraction included).")
      .def_readonly("zenith", &SunPosition::zenith)
      .def_readonly("elevation", &SunPosition::elevation)
      .def_readonly("azimuth", &SunPosition::azimuth, "degrees clockwise from true north")
      .def_property_readonly("to_light", [](const SunPosition& s) { return vec3_array(s.to_light); })
      .def("__repr__", [](const SunPosition& s) {
        std::ostringstream o;
        o.precision(10);
        o << "SunPosition(elevation=" << s.elevation << ", azimuth=" << s.azimuth << ")";
        return o.str();
      });

  py::class_<SunPeriod>(m, "SunPeriod", "A scene's sun block: a site and a period (start..end, step) or times.")
      .def(py::init([](const SolarSite& site, double utc_offset_hours, const std::string& start, const std::string& end,
                       int step_minutes, const std::vector<py::object>& times, double north_axis,
                       double min_elevation, double delta_t, bool energyplus_times) {
             SunPeriod p;
             p.site = site;
             p.utc_offset_hours = utc_offset_hours;
             p.start = start;
             p.end = end;
             p.step_minutes = step_minutes;
             for (const py::object& t : times) p.times.push_back(to_utc(t));
             p.north_axis = north_axis;
             p.min_elevation = min_elevation;
             p.delta_t = delta_t;
             p.energyplus_times = energyplus_times;
             return p;
           }),
           py::arg("site"), py::arg("utc_offset_hours") = 0.0, py::arg("start") = "", py::arg("end") = "",
           py::arg("step_minutes") = 60, py::arg("times") = std::vector<py::object>{}, py::arg("north_axis") = 0.0,
           py::arg("min_elevation") = 0.0, py::arg("delta_t") = 69.0, py::arg("energyplus_times") = false)
      .def_readwrite("site", &SunPeriod::site)
      .def_readwrite("utc_offset_hours", &SunPeriod::utc_offset_hours)
      .def_readwrite("start", &SunPeriod::start)
      .def_readwrite("end", &SunPeriod::end)
      .def_readwrite("step_minutes", &SunPeriod::step_minutes)
      .def_readwrite("times", &SunPeriod::times, "explicit UTC instants (POSIX seconds)")
      .def_readwrite("north_axis", &SunPeriod::north_axis)
      .def_readwrite("min_elevation", &SunPeriod::min_elevation)
      .def_readwrite("delta_t", &SunPeriod::delta_t)
      .def_readwrite("energyplus_times", &SunPeriod::energyplus_times,
                     "instants where EnergyPlus takes each time step's sun (the step's end, or mid-hour hourly)")
      .def_readwrite("time_zone", &SunPeriod::time_zone);

  py::class_<SunInstant>(m, "SunInstant", "One instant of a sun period; light_id is None below the horizon.")
      .def_readonly("time", &SunInstant::time, "UTC, POSIX seconds")
      .def_readonly("position", &SunInstant::position)
      .def_property_readonly("light_id", [](const SunInstant& s) -> py::object {
        if (s.light_id == SunInstant::none) return py::none();
        return py::int_(s.light_id);
      });

  m.def("solar_position",
        [](const SolarSite& site, const py::object& time, double north_axis, double delta_t) {
          SunPeriod p;  // checked as a sun block checks them: the site, north_axis, delta_t
          p.site = site;
          p.north_axis = north_axis;
          p.delta_t = delta_t;
          p.times = {to_utc(time)};
          check_sun_period(p, "", "solar_position");
          return solar_position(site, p.times.front(), north_axis, delta_t);
        },
        py::arg("site"), py::arg("time"), py::arg("north_axis") = 0.0, py::arg("delta_t") = 69.0,
        "The sun seen from `site` at `time` (UTC seconds, int or float, rounded down; an ISO 8601 string\n"
        "with Z or an offset; or an aware datetime): NREL's SPA, topocentric, refraction included. north_axis only turns to_light\n"
        "into model coordinates (EnergyPlus's Building North Axis).");
  m.def("sun_to_light", [](double e, double a, double n) { return vec3_array(sun_to_light(e, a, n)); },
        py::arg("elevation"), py::arg("azimuth"), py::arg("north_axis") = 0.0,
        "Unit vector toward a sun at `elevation` and `azimuth` (degrees) in model coordinates.");
  m.def("parse_iso8601",
        [](const std::string& text, std::optional<int> local_offset_minutes) {
          const std::optional<UtcSeconds> s =
              local_offset_minutes ? parse_iso8601(text, *local_offset_minutes) : parse_iso8601(text);
          if (!s) throw py::value_error("not an ISO 8601 time that exists: \"" + text + "\"");
          return *s;
        },
        py::arg("text"), py::arg("local_offset_minutes") = py::none(),
        "UTC seconds of an ISO 8601 time; without Z or an offset it is local time local_offset_minutes\n"
        "ahead of UTC (an error when that is None). Raises ValueError when malformed.");
  m.def("format_iso8601_utc", &format_iso8601_utc, py::arg("time"), "YYYY-MM-DDThh:mm:ssZ");
  m.def("parse_utc_offset", &parse_utc_offset, py::arg("time_zone"),
        "Minutes east of UTC of 'UTC', 'UTC+hh:mm', ...; None for anything else.");
  m.def("check_sun_period", &check_sun_period, py::arg("period"), py::arg("file") = "", py::arg("place") = "sun",
        "Raises InputError when the period is out of range.");
  m.def("expand_sun_period", py::overload_cast<const SunPeriod&, unsigned>(&expand_sun_period), py::arg("period"),
        py::arg("threads") = 1,
        "Every instant of the period in time order with its sun's position (light_id None), the\n"
        "positions computed on `threads` threads (0: every hardware thread).");
  m.def("sun_light_name", &sun_light_name, py::arg("time"));
  m.def("replace_sun_lights",
        [](const ScenePtr& scene, const SunPeriod& period, unsigned threads) {
          auto out = std::make_shared<Scene>(need_scene(scene));
          replace_sun_lights(*out, period, threads);
          return out;
        },
        py::arg("scene"), py::arg("period"), py::arg("threads") = 1,
        "A copy of the scene with its sun period replaced: the earlier suns' lights removed, the\n"
        "period's added (other lights keep their order). The scene given is left as it was.");
  // A copy, not the scene changed in place: an engine may be computing on the scene given.
  m.def("add_sun_lights",
        [](const ScenePtr& scene, const SunPeriod& period, unsigned threads) {
          auto out = std::make_shared<Scene>(need_scene(scene));
          add_sun_lights(*out, period, threads);
          return out;
        },
        py::arg("scene"), py::arg("period"), py::arg("threads") = 1,
        "A copy of the scene with the period's suns above min_elevation appended to its lights (and\n"
        "its sun and sun_instants set); the scene given is left as it was.");

  scene_class
      .def_property_readonly("source", [](const Scene& s) { return s.source.string(); })
      .def_readonly("meshes", &Scene::meshes)
      .def_readonly("lights", &Scene::lights)
      .def_readonly("planes", &Scene::planes)
      .def_readonly("materials", &Scene::materials)
      .def_property_readonly("warnings", [](const Scene& s) {
        std::vector<std::string> w;
        for (const Warning& x : s.warnings) w.push_back(x.to_string());
        return w;
      }, "non-fatal findings of loading and validation, one line each")
      .def_property_readonly("skipped_faces", [](const Scene& s) {
        py::list l;
        for (const SkippedFace& x : s.skipped_faces) {
          py::dict d;
          d["name"] = x.name;
          d["mesh"] = x.mesh;
          d["source"] = x.source.to_string();
          d["reason"] = x.reason;
          l.append(d);
        }
        return l;
      }, "the faces left out by skip_invalid=True (dicts: name, mesh, source, reason); they have no face_id")
      .def_readonly("sun", &Scene::sun)
      .def_readonly("sun_instants", &Scene::sun_instants)
      .def_readonly("sun_hours_map", &Scene::sun_hours_map, "indices of the meshes that get the sun-hours map")
      .def_property_readonly("origin", [](const Scene& s) -> py::object {
        if (!s.origin) return py::none();
        return vec3_array(*s.origin);
      }, "the point subtracted from the VTK files' points (CityJSON models), or None")
      .def_property_readonly("face_count", [](const Scene& s) { return s.faces.size(); })
      .def("face_vertices", [](const Scene& s, const py::object& face_id) {
        return polygon_array(s.faces[index_arg(face_id, s.faces.size(), "face_id", "the scene", "face")].vertices);
      }, py::arg("face_id"), "The face's vertices, an (n, 3) float64 array.")
      .def_property_readonly("faces", [](const Scene& s) {
        py::list l;
        for (const Face& f : s.faces) l.append(polygon_array(f.vertices));
        return l;
      }, "Every face's vertices: a list of (n, 3) float64 arrays indexed by face_id.")
      .def_property_readonly("face_mesh", [](const Scene& s) {
        return column<std::uint64_t>(s.faces, [](const Face& f) { return f.mesh; });
      })
      .def_property_readonly("face_degenerate", [](const Scene& s) {
        return column<bool>(s.faces, [](const Face& f) { return f.degenerate; });
      })
      .def_property_readonly("face_receiver", [](const Scene& s) {
        py::array_t<bool> a(static_cast<py::ssize_t>(s.faces.size()));
        for (std::size_t i = 0; i < s.faces.size(); ++i) a.mutable_data()[i] = s.is_receiver(i);
        return a;
      })
      .def_property_readonly("face_name", [](const Scene& s) {
        std::vector<std::string> n;
        for (const Face& f : s.faces) n.push_back(f.name);
        return n;
      })
      .def_property_readonly("face_kind", [](const Scene& s) {
        std::vector<std::string> n;
        for (const Face& f : s.faces) n.push_back(f.kind);
        return n;
      })
      .def_property_readonly("face_source", [](const Scene& s) {
        std::vector<std::string> n;
        for (const Face& f : s.faces) n.push_back(f.source.to_string());
        return n;
      })
      .def("face_label", [](const Scene& s, const py::object& face_id) {
        return face_label(s, index_arg(face_id, s.faces.size(), "face_id", "the scene", "face"));
      }, py::arg("face_id"), "The face's label: its name, or face_<id>. IndexError out of range.")
      .def("named_surfaces", [](const Scene& s, bool r) { return named_surfaces(s, r); },
           py::arg("receivers_only") = true)
      .def("objects", [](const Scene& s, bool r, bool per_mesh) { return scene_objects(s, r, per_mesh); },
           py::arg("receivers_only") = true, py::arg("per_mesh") = false,
           "The scene's objects (SceneObject): CityJSON BuildingParts rolled up into their Building, an\n"
           "EnergyPlus zone, any other mesh; per_mesh: every mesh its own.")
      .def("validate", [](Scene& s, double tolerance) {
        LoadOptions o;
        o.planarity_tolerance = tolerance;
        validate_scene(s, o);
      }, py::arg("planarity_tolerance") = 1e-6, "Checks the scene again (load_scene already did).")
      .def("__repr__", [](const Scene& s) {
        return "<libshadow.Scene " + py::repr(py::str(s.source.string())).cast<std::string>() + ": " +
               std::to_string(s.meshes.size()) + " meshes, " + std::to_string(s.faces.size()) + " faces, " +
               std::to_string(s.lights.size()) + " lights, " + std::to_string(s.planes.size()) + " planes>";
      });

  m.def("make_city",
        [](std::size_t boxes, double extent, std::uint64_t seed, const std::vector<Light>& lights) {
          auto scene = std::make_shared<Scene>(make_city(boxes, extent, seed));
          scene->lights = lights;
          validate_scene(*scene);
          return scene;
        },
        py::arg("boxes"), py::arg("extent"), py::arg("seed"), py::arg("lights") = std::vector<Light>{},
        "The benchmark city (generators.hpp): `boxes` random boxes on a ground square of side `extent`,\n"
        "seeded; mesh 0 'ground', mesh 1 'buildings'. `lights` (Light objects) are its lights.");
  m.def("load_scene",
        [](const std::filesystem::path& path, double tolerance, bool orient_outward, const std::string& lod,
           bool skip_invalid, bool require_lights) {
          LoadOptions o;
          o.planarity_tolerance = tolerance;
          o.orient_outward = orient_outward;
          o.cityjson_lod = lod;
          o.skip_invalid = skip_invalid;
          o.require_lights = require_lights;
          return without_gil([&] { return std::make_shared<Scene>(load_scene(path, o)); });
        },
        py::arg("path"), py::arg("planarity_tolerance") = 1e-6, py::arg("orient_outward") = false,
        py::arg("cityjson_lod") = "", py::arg("skip_invalid") = false, py::arg("require_lights") = true,
        "Reads and validates a scene file and its meshes (OBJ, CityJSON, EnergyPlus). Raises InputError\n"
        "(a ValueError). orient_outward: turn every mesh's closed parts outward (--orient-outward);\n"
        "cityjson_lod: the CityJSON level of detail ('' : the highest of each object);\n"
        "skip_invalid: leave out faces that fail validation (--skip-invalid), listed in Scene.skipped_faces;\n"
        "require_lights=False: a scene without lights is read (for irradiance(): the suns come from the\n"
        "weather, as `shadow irradiance` reads its scene).");
  m.def("parse_scene",
        [](const std::string& text, const std::filesystem::path& name, double tolerance, bool orient_outward,
           const std::string& lod, bool skip_invalid, bool require_lights) {
          LoadOptions o;
          o.planarity_tolerance = tolerance;
          o.orient_outward = orient_outward;
          o.cityjson_lod = lod;
          o.skip_invalid = skip_invalid;
          o.require_lights = require_lights;
          return without_gil([&] { return std::make_shared<Scene>(parse_scene(text, name, o)); });
        },
        py::arg("text"), py::arg("name") = "<string>", py::arg("planarity_tolerance") = 1e-6,
        py::arg("orient_outward") = false, py::arg("cityjson_lod") = "", py::arg("skip_invalid") = false,
        py::arg("require_lights") = true,
        "Parses and validates scene JSON text; `name` names it in errors and anchors mesh files.\n"
        "require_lights=False: a scene without lights is read (see load_scene).");

  // ---- results ----------------------------------------------------------------------------------
  py::class_<PlaneShadow>(m, "PlaneShadow", "The shadow the scene casts on one plane from one light.")
      .def_readonly("plane_id", &PlaneShadow::plane_id)
      .def_readonly("light_id", &PlaneShadow::light_id)
      .def_property_readonly("polygons", [](const PlaneShadow& p) {
        py::list l;
        for (const auto& poly : p.polygons) l.append(polygon_array(poly));
        return l;
      })
      .def_property_readonly("region_id", [](const PlaneShadow& p) {
        return column<std::uint64_t>(p.region_id, [](std::size_t x) { return x; });
      })
      .def_property_readonly("polygon_area", [](const PlaneShadow& p) {
        return column<double>(p.polygon_area, [](double x) { return x; });
      })
      .def_readonly("area", &PlaneShadow::area)
      .def_readonly("window_half_size", &PlaneShadow::window_half_size)
      .def_readonly("reaches_window", &PlaneShadow::reaches_window);

  py::class_<Result, std::shared_ptr<Result>>(
      m, "ShadowResult",
      "Lit and shadowed areas per (face, light), ordered by face_id then light_id, as numpy arrays;\n"
      "fragments (lit and shadowed polygons) and plane shadows.")
      .def("__len__", [](const Result& r) { return r.result.lighting.size(); })
      .def_property_readonly("scene", [](const Result& r) { return r.scene; })
      .def_property_readonly("face_id", [](const Result& r) {
        return column<std::uint64_t>(r.result.lighting, [](const FaceLighting& x) { return x.face_id; });
      })
      .def_property_readonly("light_id", [](const Result& r) {
        return column<std::uint64_t>(r.result.lighting, [](const FaceLighting& x) { return x.light_id; });
      })
      .def_property_readonly("area", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.area; });
      })
      .def_property_readonly("lit_area", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.lit_area; });
      })
      .def_property_readonly("shadow_area", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.shadow_area; });
      })
      .def_property_readonly("lit_fraction", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.lit_fraction; });
      })
      .def_property_readonly("lit_area_error_bound", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.lit_area_error_bound; });
      })
      .def_property_readonly("dropped_area", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.dropped_area; });
      })
      // Extended lights' regions (docs/area-lights.md); 0 for point and directional lights.
      .def_property_readonly("fully_lit_area", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.fully_lit_area; });
      })
      .def_property_readonly("penumbra_area", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.penumbra_area; });
      })
      .def_property_readonly("umbra_area", [](const Result& r) {
        return column<double>(r.result.lighting, [](const FaceLighting& x) { return x.umbra_area; });
      })
      .def_property_readonly("faces_light", [](const Result& r) {
        return column<bool>(r.result.lighting, [](const FaceLighting& x) { return x.faces_light; });
      })
      // Fragments, one entry per simple polygon, ordered by face, light, fragment_id.
      .def_property_readonly("fragment_face_id", [](const Result& r) {
        return column<std::uint64_t>(r.result.fragments, [](const Fragment& x) { return x.face_id; });
      })
      .def_property_readonly("fragment_light_id", [](const Result& r) {
        return column<std::uint64_t>(r.result.fragments, [](const Fragment& x) { return x.light_id; });
      })
      .def_property_readonly("fragment_id", [](const Result& r) {
        return column<std::uint64_t>(r.result.fragments, [](const Fragment& x) { return x.fragment_id; });
      })
      .def_property_readonly("fragment_lit", [](const Result& r) {
        return column<bool>(r.result.fragments, [](const Fragment& x) { return x.lit; });
      })
      .def_property_readonly("fragment_area", [](const Result& r) {
        return column<double>(r.result.fragments, [](const Fragment& x) { return x.area; });
      })
      .def_property_readonly("fragment_polygons", [](const Result& r) {
        py::list l;
        for (const Fragment& f : r.result.fragments) l.append(polygon_array(f.polygon));
        return l;
      })
      .def_property_readonly("plane_shadows", [](const Result& r) { return r.result.plane_shadows; })
      .def_property_readonly("stats", [](const Result& r) { return stats_dict(r.result.stats); })
      .def_property_readonly("arithmetic", [](const Result& r) { return arithmetic_name(r.result.arithmetic); })
      .def("find", [](const Result& r, std::size_t face, std::size_t light) -> py::object {
        const FaceLighting* x = r.result.find(face, light);
        if (x == nullptr) return py::none();
        py::dict d;
        d["face_id"] = x->face_id;
        d["light_id"] = x->light_id;
        d["area"] = x->area;
        d["lit_area"] = x->lit_area;
        d["shadow_area"] = x->shadow_area;
        d["lit_fraction"] = x->lit_fraction;
        d["faces_light"] = x->faces_light;
        d["lit_area_error_bound"] = x->lit_area_error_bound;
        d["dropped_area"] = x->dropped_area;
        d["fully_lit_area"] = x->fully_lit_area;
        d["penumbra_area"] = x->penumbra_area;
        d["umbra_area"] = x->umbra_area;
        return d;
      }, py::arg("face_id"), py::arg("light_id"), "The entry for (face, light) as a dict, or None.")
      .def("report_json", [](const Result& r) {
        std::ostringstream out;
        write_report_json(out, *r.scene, r.result);
        return out.str();
      }, "report.json's text, as write_outputs writes it (without the run object).");

  m.def("write_outputs",
        [](const Result& r, const std::filesystem::path& outdir) {
          const std::vector<std::filesystem::path> paths =
              without_gil([&] { return write_outputs(outdir, *r.scene, r.result); });
          std::vector<std::string> out;
          for (const auto& p : paths) out.push_back(p.string());
          return out;
        },
        py::arg("result"), py::arg("outdir"),
        "Writes the CLI's files (fragments.vtp, faces.vtp, plane_shadows.vtp, lights.vtp, scene.vtm,\n"
        "report.json last) into outdir; returns their paths. Raises OutputError (an OSError).");

  // ---- computing --------------------------------------------------------------------------------
  const char* options_doc =
      "threads: workers (0: every hardware thread); polygons: also the lit/shadowed polygons;\n"
      "lights: indices of scene lights (None: all); arithmetic: 'exact' or 'fast' (with error bounds);\n"
      "progress: callable(done, total), called with the GIL held; an exception it raises stops the run;\n"
      "tile_casters, fast_tile_casters: split a receiver with more candidate casters than this into tiles\n"
      "(exact: areas unchanged; fast: within the bounds; fragments cut at tile borders; 0: never).";

  // Registered before ShadowEngine.compute_series names it (else its docstring would show the C++ type).
  py::class_<Series, std::shared_ptr<Series>> series_class(
      m, "SeriesResult",
      "Lit areas of every receiving face under every light of a series: rows are faces (face_id),\n"
      "columns instants. 2-D arrays lit_area, lit_fraction, faces_light, lit_area_error_bound;\n"
      "to_pandas(values, by) as a DataFrame indexed by UTC time.");

  py::class_<Engine>(m, "ShadowEngine",
                     "Prepares a scene once (exact face data) and computes shadows for many lights.")
      .def(py::init([](const ScenePtr& scene, unsigned threads) {
             need_scene(scene);
             auto e = std::make_unique<Engine>();
             e->scene = scene;
             // Ctrl-C is seen while the scene is prepared (the progress hook checks signals).
             const std::function<void(const Progress&)> progress = wrap_progress(py::none());
             e->engine = without_gil([&] { return std::make_unique<ShadowEngine>(*scene, threads, progress); });
             return e;
           }),
           py::arg("scene"), py::arg("threads") = 0)
      .def("compute",
           [](const Engine& e, unsigned threads, bool polygons, std::optional<std::vector<std::size_t>> lights,
              const std::string& arithmetic, const py::object& progress, std::size_t tile_casters,
              std::size_t fast_tile_casters) {
             return run_compute(e.scene,
                                make_options(threads, polygons, lights, arithmetic, true, 0.0, progress, tile_casters,
                                             fast_tile_casters),
                                [&](const ShadowOptions& o) { return e.engine->compute(o); });
           },
           py::arg("threads") = 0, py::arg("polygons") = true, py::arg("lights") = py::none(),
           py::arg("arithmetic") = "exact", py::arg("progress") = py::none(),
           py::arg("tile_casters") = ShadowOptions{}.tile_casters,
           py::arg("fast_tile_casters") = ShadowOptions{}.fast_tile_casters, options_doc)
      .def("compute_light",
           [](const Engine& e, const Light& light, std::size_t light_id, unsigned threads, bool polygons,
              const std::string& arithmetic, const py::object& progress, std::size_t tile_casters,
              std::size_t fast_tile_casters) {
             return run_compute(e.scene,
                                make_options(threads, polygons, std::nullopt, arithmetic, true, 0.0, progress,
                                             tile_casters, fast_tile_casters),
                                [&](const ShadowOptions& o) { return e.engine->compute(light, light_id, o); });
           },
           py::arg("light"), py::arg("light_id"), py::arg("threads") = 0, py::arg("polygons") = true,
           py::arg("arithmetic") = "exact", py::arg("progress") = py::none(),
           py::arg("tile_casters") = ShadowOptions{}.tile_casters,
           py::arg("fast_tile_casters") = ShadowOptions{}.fast_tile_casters,
           "Any light, not necessarily in the scene; results carry light_id.")
      .def("compute_series",
           [](const Engine& e, std::optional<std::vector<Light>> lights, unsigned threads,
              const std::string& arithmetic, const py::object& progress, std::size_t tile_casters,
              std::size_t fast_tile_casters) {
             auto out = std::make_shared<Series>();
             out->scene = e.scene;
             if (lights) {
               out->lights = *lights;
             } else {
               SunSeries suns = sun_series(*e.scene);
               out->lights = std::move(suns.lights);
               out->times = std::move(suns.times);
             }
             SeriesOptions o;
             o.threads = threads;
             o.arithmetic = parse_arithmetic(arithmetic);
             o.progress = wrap_progress(progress);
             o.tile_casters = tile_casters;
             o.fast_tile_casters = fast_tile_casters;
             out->result = without_gil([&] { return e.engine->compute_series(out->lights, o); });
             return out;
           },
           py::arg("lights") = py::none(), py::arg("threads") = 0, py::arg("arithmetic") = "exact",
           py::arg("progress") = py::none(), py::arg("tile_casters") = SeriesOptions{}.tile_casters,
           py::arg("fast_tile_casters") = SeriesOptions{}.fast_tile_casters,
           "Lit areas of every receiving face under each light (None: the scene's suns, sun_series),\n"
           "faces x instants, equal to compute_light per light bit for bit (with the same tile thresholds)\n"
           "but faster. progress: callable(done, total) in instants. tile_casters, fast_tile_casters: split\n"
           "a receiver with more candidate casters at an instant than this into tiles (exact: no bit\n"
           "changes; fast: within the bounds; 0: never).")
      .def("compute_planes",
           [](const Engine& e, std::optional<std::vector<std::size_t>> lights, double plane_window) {
             ShadowOptions o = make_options(0, true, lights, "exact", true, plane_window, py::none());
             return without_gil([&] { return e.engine->compute_planes(o); });
           },
           py::arg("lights") = py::none(), py::arg("plane_window") = 0.0)
      .def("face_area", [](const Engine& e, const py::object& face_id) {
        return e.engine->face_area(index_arg(face_id, e.scene->faces.size(), "face_id", "the scene", "face"));
      }, py::arg("face_id"))
      .def_property_readonly("scene", [](const Engine& e) { return e.scene; });

  // ---- sun series (series.hpp) -------------------------------------------------------------------
  py::class_<SunSeries>(m, "SunSeries", "The scene's suns above the horizon, as the lights of a series.")
      .def_readonly("lights", &SunSeries::lights)
      .def_readonly("times", &SunSeries::times, "UTC, POSIX seconds")
      .def_readonly("instants", &SunSeries::instants, "indices in Scene.sun_instants")
      .def_readonly("all_instants", &SunSeries::all_instants)
      .def_readonly("hours_per_instant", &SunSeries::hours_per_instant)
      .def_readonly("explicit_times", &SunSeries::explicit_times);
  m.def("sun_series", [](const Scene& s) { return sun_series(s); }, py::arg("scene"),
        "The series of the scene's sun block. Raises InputError without one.");
  m.def("hours_per_instant", &hours_per_instant, py::arg("period"),
        "The hours each instant stands for: step_minutes / 60, or for explicit times the median gap.");

  series_class
      .def_property_readonly("scene", [](const Series& x) { return x.scene; })
      .def_property_readonly("face_id", [](const Series& x) {
        return column<std::uint64_t>(x.result.faces, [](std::size_t f) { return f; });
      })
      .def_property_readonly("instants", [](const Series& x) { return x.result.instants; })
      .def_property_readonly("times", [](const Series& x) { return x.times; },
                             "UTC seconds of the columns (the scene's suns; empty for other lights)")
      .def_property_readonly("lights", [](const Series& x) { return x.lights; })
      .def_property_readonly("area", [](const Series& x) {
        return column<double>(x.result.area, [](double a) { return a; });
      })
      .def_property_readonly("lit_area", [](const Series& x) {
        return table<double>(x.result.lit_area, x.result.faces.size(), x.result.instants);
      })
      .def_property_readonly("lit_fraction", [](const Series& x) {
        return table<double>(x.result.lit_fraction, x.result.faces.size(), x.result.instants);
      })
      .def_property_readonly("faces_light", [](const Series& x) {
        return table<bool>(x.result.faces_light, x.result.faces.size(), x.result.instants);
      })
      .def_property_readonly("lit_area_error_bound", [](const Series& x) {
        return table<double>(x.result.lit_area_error_bound, x.result.faces.size(), x.result.instants);
      })
      .def_property_readonly("stats", [](const Series& x) { return stats_dict(x.result.stats); })
      .def_property_readonly("arithmetic", [](const Series& x) { return arithmetic_name(x.result.arithmetic); });

  m.def("_series_sun_hours", [](const Series& x, double h) {
    const std::vector<double> v = sun_hours(x.result, hours_arg(h));
    return column<double>(v, [](double a) { return a; });
  });
  m.def("_series_sun_hours_error_bound", [](const Series& x, double h) {
    const std::vector<double> v = sun_hours_error_bound(x.result, hours_arg(h));
    return column<double>(v, [](double a) { return a; });
  });
  m.def("_surface_series", [](const Series& x, double h) {
    const SurfaceSeries s = surface_series(*x.scene, x.result, hours_arg(h));
    py::dict d;
    std::vector<std::string> labels;
    for (const NamedSurface& n : s.surfaces) labels.push_back(n.label);
    d["labels"] = labels;
    d["surfaces"] = s.surfaces;
    d["area"] = column<double>(s.area, [](double a) { return a; });
    d["lit_fraction"] = table<double>(s.lit_fraction, s.surfaces.size(), s.instants);
    d["sun_hours"] = column<double>(s.sun_hours, [](double a) { return a; });
    return d;
  });
  m.def("_object_sun_hours", [](const Series& x, double h, bool per_mesh) {
    const ObjectSunHours o = object_sun_hours(*x.scene, x.result, h, per_mesh);
    py::dict d;
    std::vector<std::string> ids, types;
    std::vector<std::vector<std::size_t>> meshes;
    for (const SceneObject& object : o.objects) {
      ids.push_back(object.id);
      types.push_back(object.type);
      meshes.push_back(object.meshes);
    }
    d["ids"] = ids;
    d["types"] = types;
    d["meshes"] = meshes;
    d["faces"] = column<std::uint64_t>(o.faces, [](std::size_t n) { return n; });
    d["area"] = column<double>(o.area, [](double a) { return a; });
    d["sun_hours"] = column<double>(o.sun_hours, [](double a) { return a; });
    d["sunlit_area_hours"] = column<double>(o.sunlit_area_hours, [](double a) { return a; });
    return d;
  });
  m.def("_sun_hours_by_object_csv", [](const Series& x) {
    const SunSeries suns = sun_series(*x.scene);
    std::ostringstream out;
    write_sun_hours_by_object_csv(out, object_sun_hours(*x.scene, x.result, suns.hours_per_instant));
    return out.str();
  });
  m.def("sunlit_csv",
        [](const Series& x) {
          const SunSeries suns = sun_series(*x.scene);
          std::ostringstream out;
          write_sunlit_csv(out, suns, surface_series(*x.scene, x.result, suns.hours_per_instant));
          return out.str();
        },
        py::arg("series"), "sunlit.csv's text (the scene's suns): time, then each named surface's lit fraction.");
  m.def("energyplus_shading_csv",
        [](const Series& x) -> py::object {
          const SunSeries suns = sun_series(*x.scene);
          std::ostringstream out;
          const EnergyPlusSchedule schedule = write_energyplus_shading_csv(
              out, *x.scene, suns, surface_series(*x.scene, x.result, suns.hours_per_instant));
          py::dict d;
          d["written"] = schedule.written;
          d["reason"] = schedule.reason;
          d["year"] = schedule.year;
          d["timesteps_per_hour"] = schedule.timesteps_per_hour;
          d["rows"] = schedule.rows;
          d["rows_in_period"] = schedule.rows_in_period;
          return py::make_tuple(schedule.written ? py::object(py::str(out.str())) : py::object(py::none()), d);
        },
        py::arg("series"),
        "energyplus-shading.csv for Schedule:File:Shading: (text or None, schedule dict with 'reason').");
  m.def("write_series",
        [](const Series& x, const std::filesystem::path& outdir, std::size_t every,
           std::optional<bool> energyplus_shading) {
          const std::vector<std::filesystem::path> paths = without_gil([&] {
            const SunSeries suns = sun_series(*x.scene);
            OutputDirectory dir(outdir);
            OutputDirectory::SeriesFiles files;
            files.every = every;
            files.energyplus_shading = energyplus_shading;
            return dir.write_series(*x.scene, suns, x.result, files);
          });
          std::vector<std::string> out;
          for (const auto& p : paths) out.push_back(p.string());
          return out;
        },
        py::arg("series"), py::arg("outdir"), py::arg("every") = 1, py::arg("energyplus_shading") = py::none(),
        "Writes the series files of `shadow series` (sunlit.csv, series.pvd every `every`-th instant,\n"
        "faces.vtp with sun_hours, report.json last; energyplus-shading.csv for an EnergyPlus model, or\n"
        "with energyplus_shading=True, as --energyplus-shading). Needs the scene's suns.");

  // ---- the exact sun-hours map (sun_hours.hpp) ----------------------------------------------------
  py::class_<SunHoursInstant>(m, "SunHoursInstant", "One instant of a sun path: a light and the hours it stands for.")
      .def(py::init([](const Light& light, double hours) { return SunHoursInstant{light, hours}; }),
           py::arg("light"), py::arg("hours") = 1.0)
      .def_readwrite("light", &SunHoursInstant::light)
      .def_readwrite("hours", &SunHoursInstant::hours);

  py::class_<SunHoursMap, std::shared_ptr<SunHoursMap>>(
      m, "SunHoursMap",
      "The exact sun-hours map: cells (simple polygons lit under the same instants) with their sun\n"
      "hours, and per face totals. Cell arrays: cell_face_id, sun_hours, region_id, cell_area,\n"
      "cell_polygons; face arrays: face_id, area, hour_area, dropped_area, instants_lit.")
      .def_readonly("total_hours", &SunHoursMap::total_hours)
      .def_property_readonly("cell_face_id", [](const SunHoursMap& x) {
        return column<std::uint64_t>(x.cells, [](const SunHoursCell& c) { return c.face_id; });
      })
      .def_property_readonly("sun_hours", [](const SunHoursMap& x) {
        return column<double>(x.cells, [](const SunHoursCell& c) { return c.sun_hours; });
      })
      .def_property_readonly("region_id", [](const SunHoursMap& x) {
        return column<std::uint64_t>(x.cells, [](const SunHoursCell& c) { return c.region_id; });
      })
      .def_property_readonly("cell_area", [](const SunHoursMap& x) {
        return column<double>(x.cells, [](const SunHoursCell& c) { return c.area; });
      })
      .def_property_readonly("cell_polygons", [](const SunHoursMap& x) {
        py::list l;
        for (const SunHoursCell& c : x.cells) l.append(polygon_array(c.polygon));
        return l;
      })
      .def_property_readonly("face_id", [](const SunHoursMap& x) {
        return column<std::uint64_t>(x.faces, [](const SunHoursFace& f) { return f.face_id; });
      })
      .def_property_readonly("area", [](const SunHoursMap& x) {
        return column<double>(x.faces, [](const SunHoursFace& f) { return f.area; });
      })
      .def_property_readonly("hour_area", [](const SunHoursMap& x) {
        return column<double>(x.faces, [](const SunHoursFace& f) { return f.hour_area; });
      })
      .def_property_readonly("dropped_area", [](const SunHoursMap& x) {
        return column<double>(x.faces, [](const SunHoursFace& f) { return f.dropped_area; });
      })
      .def_property_readonly("instants_lit", [](const SunHoursMap& x) {
        return column<std::uint64_t>(x.faces, [](const SunHoursFace& f) { return f.instants_lit; });
      })
      .def_readonly("full", &SunHoursMap::full, "False when the threshold map was computed alone (no cells)")
      // The threshold map (levels=...): the levels, each level's exact area (summed over the
      // faces, and per face) and the level regions' cells.
      .def_property_readonly("levels", [](const SunHoursMap& x) { return column<double>(x.levels, [](double h) { return h; }); })
      .def_property_readonly("level_areas", [](const SunHoursMap& x) {
        const std::vector<double> a = sun_hours_level_areas(x);
        return column<double>(a, [](double v) { return v; });
      })
      .def_property_readonly("face_level_areas", [](const SunHoursMap& x) {
        py::array_t<double> out({x.faces.size(), x.levels.size()});
        auto view = out.mutable_unchecked<2>();
        for (std::size_t f = 0; f < x.faces.size(); ++f)
          for (std::size_t k = 0; k < x.levels.size(); ++k) view(f, k) = x.faces[f].level_areas.at(k);
        return out;
      })
      .def_property_readonly("level_cell_face_id", [](const SunHoursMap& x) {
        return column<std::uint64_t>(x.level_cells, [](const SunHoursCell& c) { return c.face_id; });
      })
      .def_property_readonly("level", [](const SunHoursMap& x) {
        return column<double>(x.level_cells, [](const SunHoursCell& c) { return c.sun_hours; });
      })
      .def_property_readonly("level_region_id", [](const SunHoursMap& x) {
        return column<std::uint64_t>(x.level_cells, [](const SunHoursCell& c) { return c.region_id; });
      })
      .def_property_readonly("level_cell_area", [](const SunHoursMap& x) {
        return column<double>(x.level_cells, [](const SunHoursCell& c) { return c.area; });
      })
      .def_property_readonly("level_cell_polygons", [](const SunHoursMap& x) {
        py::list l;
        for (const SunHoursCell& c : x.level_cells) l.append(polygon_array(c.polygon));
        return l;
      })
      .def("__len__", [](const SunHoursMap& x) { return x.cells.size(); });

  m.def("sun_hours_instants", [](const Scene& s) { return sun_hours_instants(s); }, py::arg("scene"),
        "The scene's suns above the horizon, each weighing the period's step (step_minutes / 60 hours).");
  m.def("sun_hours_instants", [](const SunSeries& s) { return sun_hours_instants(s); }, py::arg("series"),
        "A series' suns (sun_series), each weighing its hours_per_instant, in the series' order.");
  m.def("sun_hours_map_faces",
        [](const Scene& s, const std::optional<std::vector<std::string>>& meshes) {
          return meshes ? sun_hours_map_faces(s, *meshes, "meshes") : sun_hours_map_faces(s);
        },
        py::arg("scene"), py::arg("meshes") = py::none(),
        "The faces of the named meshes, or (None) of the scene's sun_hours_map meshes, ascending.");
  m.def("compute_sun_hours_map",
        [](const Engine& e, std::optional<std::vector<std::size_t>> faces,
           std::optional<std::vector<SunHoursInstant>> instants, unsigned threads, bool merge_equal,
           const py::object& progress, std::optional<std::vector<double>> levels, bool levels_only,
           std::optional<long long> held_segments) {
          const std::vector<std::size_t> f = faces ? *faces : sun_hours_map_faces(*e.scene);
          const std::vector<SunHoursInstant> i = instants ? *instants : sun_hours_instants(*e.scene);
          if (levels_only && (!levels || levels->empty()))
            throw InputError({"", "levels_only"}, "needs levels, e.g. levels=[2, 4, 6]");
          if (held_segments && !levels_only)
            throw InputError({"", "held_segments"}, "needs levels_only=True (it caps the threshold map alone)");
          if (held_segments &&
              (*held_segments < 0 || *held_segments > static_cast<long long>(kMaxLevelHeldSegments)))
            throw InputError({"", "held_segments"}, "must be 0 to " + std::to_string(kMaxLevelHeldSegments) +
                                                        ", got " + std::to_string(*held_segments));
          SunHoursOptions o;
          o.threads = threads;
          o.merge_equal = merge_equal;
          if (levels) o.levels = *levels;
          o.full = !levels_only;
          if (held_segments) o.level_held_segments = static_cast<std::size_t>(*held_segments);
          o.progress = wrap_progress(progress);
          auto out = std::make_shared<SunHoursMap>();
          *out = without_gil([&] { return compute_sun_hours_map(*e.engine, f, i, o); });
          return out;
        },
        py::arg("engine"), py::arg("faces") = py::none(), py::arg("instants") = py::none(), py::arg("threads") = 0,
        py::arg("merge_equal") = true, py::arg("progress") = py::none(), py::arg("levels") = py::none(),
        py::arg("levels_only") = false, py::arg("held_segments") = py::none(),
        "The exact sun-hours map on `faces` (None: the scene's sun_hours_map meshes) under `instants`\n"
        "(None: the scene's suns, sun_hours_instants). With `levels` (hours, e.g. [2, 4, 6]) also the\n"
        "threshold map: the exact regions getting at least each level (levels, level_areas,\n"
        "face_level_areas, level_* cell arrays); `levels_only=True` computes it alone (no full map's\n"
        "cells: its memory follows the level boundaries). `held_segments` (with levels_only) caps the\n"
        "exact boundary segments it holds (SunHoursOptions::level_held_segments, 2^20 when None): past\n"
        "it, lit regions are computed again, in less memory and more time, with the same level areas.\n"
        "The GIL is released while it works.");
  m.def("write_sun_hours_vtp",
        [](const SunHoursMap& map, const std::filesystem::path& path, const ScenePtr& scene) {
          without_gil([&] {
            if (scene) write_sun_hours_vtp(path, map, *scene);
            else write_sun_hours_vtp(path, map);
          });
        },
        py::arg("map"), py::arg("path"), py::arg("scene") = ScenePtr{},
        "Writes the map as VTK XML PolyData (normally OUTDIR/sun_hours.vtp); with the scene, points\n"
        "are shifted by its origin like the scene's other VTK files.");
  m.def("write_sun_hours_levels_vtp",
        [](const SunHoursMap& map, const std::filesystem::path& path, const ScenePtr& scene) {
          without_gil([&] { write_sun_hours_levels_vtp(path, map, scene ? *scene : Scene{}); });
        },
        py::arg("map"), py::arg("path"), py::arg("scene") = ScenePtr{},
        "Writes the threshold map (a map computed with levels) as VTK XML PolyData (normally\n"
        "OUTDIR/sun_hours_levels.vtp); with the scene, points shifted by its origin.");

  // Radiosity (docs/radiosity.md).
  m.def("form_factor",
        [](const ScenePtr& scene, std::size_t from_face, std::size_t to_face, double tolerance, int max_order,
           unsigned threads) {
          need_scene(scene);
          FormFactorOptions o;
          o.tolerance = tolerance;
          o.max_order = max_order;
          o.threads = threads;
          const FormFactor f = without_gil([&] { return shadow::form_factor(*scene, from_face, to_face, o); });
          py::dict d;
          d["value"] = f.value;
          d["error"] = f.error;
          d["order"] = f.order;
          d["evaluations"] = f.evaluations;
          return d;
        },
        py::arg("scene"), py::arg("from_face"), py::arg("to_face"), py::arg("tolerance") = 1e-4,
        py::arg("max_order") = 32, py::arg("threads") = 0,
        "The form factor from face from_face to face to_face with exact visibility (the fraction of the "
        "diffuse power leaving from_face that reaches to_face directly): a dict with value, error (the "
        "quadrature's last change), order and evaluations.");
  m.def("radiosity",
        [](const ScenePtr& scene, double max_element_area, double tolerance, double patch_area, unsigned threads,
           const std::string& method, double link_separation, double refine_tolerance, int refine_passes, bool per_light) {
          need_scene(scene);
          RadiosityOptions o;
          o.per_light = per_light;
          o.refine_tolerance = refine_tolerance;
          o.refine_passes = refine_passes;
          o.max_element_area = max_element_area;
          o.tolerance = tolerance;
          o.patch_area = patch_area;
          o.threads = threads;
          if (method == "shooting")
            o.method = RadiosityMethod::shooting;
          else if (method == "hierarchical")
            o.method = RadiosityMethod::hierarchical;
          else if (method != "auto")
            throw py::value_error("method must be 'auto', 'shooting' or 'hierarchical', not '" + method + "'");
          o.link_separation = link_separation;
          const RadiosityResult r = without_gil([&] { return solve_radiosity(*scene, o); });
          py::dict elements, faces, d;
          elements["face_id"] = column<std::int64_t>(r.elements, [](const RadiosityElement& e) { return e.face_id; });
          elements["area"] = column<double>(r.elements, [](const RadiosityElement& e) { return e.area; });
          elements["radiosity"] = column<double>(r.elements, [](const RadiosityElement& e) { return e.radiosity; });
          elements["irradiance"] = column<double>(r.elements, [](const RadiosityElement& e) { return e.irradiance; });
          elements["direct_irradiance"] =
              column<double>(r.elements, [](const RadiosityElement& e) { return e.direct_irradiance; });
          std::vector<glm::dvec3> corners;
          for (const RadiosityElement& e : r.elements) corners.insert(corners.end(), e.polygon.begin(), e.polygon.end());
          elements["triangles"] = polygon_array(corners).reshape({static_cast<py::ssize_t>(r.elements.size()),
                                                                  py::ssize_t{3}, py::ssize_t{3}});
          faces["area"] = column<double>(r.faces, [](const FaceRadiosity& f) { return f.area; });
          faces["radiosity"] = column<double>(r.faces, [](const FaceRadiosity& f) { return f.radiosity; });
          faces["irradiance"] = column<double>(r.faces, [](const FaceRadiosity& f) { return f.irradiance; });
          faces["direct_irradiance"] = column<double>(r.faces, [](const FaceRadiosity& f) { return f.direct_irradiance; });
          std::vector<glm::dvec3> element_rgb, face_rgb;
          for (const RadiosityElement& e : r.elements) element_rgb.push_back(e.radiosity_rgb);
          for (const FaceRadiosity& f : r.faces) face_rgb.push_back(f.radiosity_rgb);
          elements["radiosity_rgb"] = polygon_array(element_rgb);  // (n, 3): red, green, blue
          faces["radiosity_rgb"] = polygon_array(face_rgb);
          // (faces, columns): one of FaceRadiosity's per-light arrays, 0 past its end.
          const auto by_light_array = [&](std::vector<double> FaceRadiosity::*field, py::ssize_t columns) {
            py::array_t<double> out({static_cast<py::ssize_t>(r.faces.size()), columns});
            auto cells = out.mutable_unchecked<2>();
            for (py::ssize_t f = 0; f < static_cast<py::ssize_t>(r.faces.size()); ++f)
              for (py::ssize_t l = 0; l < columns; ++l) {
                const std::vector<double>& v = r.faces[static_cast<std::size_t>(f)].*field;
                cells(f, l) = static_cast<std::size_t>(l) < v.size() ? v[static_cast<std::size_t>(l)] : 0.0;
              }
            return out;
          };
          const py::ssize_t nl = static_cast<py::ssize_t>(scene->lights.size());
          // Each light's share of the direct irradiance, W/m2, (faces, lights).
          faces["direct_irradiance_by_light"] = by_light_array(&FaceRadiosity::direct_irradiance_by_light, nl);
          // Each light's share of the irradiance, direct and reflected, W/m2: (faces, lights), or
          // (faces, 0) when not computed (per_light off, or more than 8 lights).
          const bool shares = !r.faces.empty() && !r.faces.front().irradiance_by_light.empty();
          faces["irradiance_by_light"] = by_light_array(&FaceRadiosity::irradiance_by_light, shares ? nl : 0);
          d["colour"] = r.colour;
          d["elements"] = elements;
          d["faces"] = faces;
          d["shots"] = r.shots;
          d["method"] = r.hierarchical ? "hierarchical" : "shooting";
          d["iterations"] = r.iterations;
          d["near_links"] = r.near_links;
          d["far_links"] = r.far_links;
          d["converged"] = r.converged;
          d["unshot_fraction"] = r.unshot_fraction;
          d["error_estimate"] = r.error_estimate;
          d["emitted_power"] = r.emitted_power;
          d["direct_power"] = r.direct_power;
          d["absorbed_power"] = r.absorbed_power;
          d["escaped_power"] = r.escaped_power;
          d["unshot_power"] = r.unshot_power;
          d["balance_residual"] = r.balance_residual;
          d["refine_passes"] = r.refine_passes;
          d["initial_elements"] = r.initial_elements;
          d["discretization_error"] = refine_tolerance > 0 ? py::object(py::float_(r.discretization_error)) : py::none();
          return d;
        },
        py::arg("scene"), py::arg("max_element_area") = 0.0, py::arg("tolerance") = 1e-3, py::arg("patch_area") = 0.0,
        py::arg("threads") = 0, py::arg("method") = "auto", py::arg("link_separation") = 0.4,
        py::arg("refine_tolerance") = 0.0, py::arg("refine_passes") = 3, py::arg("per_light") = true,
        "Radiosity with exact visibility (docs/radiosity.md): method 'auto' (hierarchical above 4,000 "
        "patches), 'shooting' (progressive refinement) or 'hierarchical' (links between groups far apart; "
        "link_separation in (0, 1)). A dict with elements (face_id, area, radiosity, irradiance, "
        "direct_irradiance, triangles), faces (area-weighted means; direct_irradiance_by_light and "
        "irradiance_by_light, each light's share, direct and direct plus reflected), shots, method, iterations, near_links, "
        "far_links, converged, unshot_fraction, error_estimate and the energy balance in W. refine_tolerance > 0 "
        "(shooting): elements split where the irradiance varies across them until the element field's estimated "
        "relative error (discretization_error) is at most it, in at most refine_passes rounds.");
  m.def("compute_shadows",
        [](const ScenePtr& scene, unsigned threads, bool polygons, std::optional<std::vector<std::size_t>> lights,
           const std::string& arithmetic, bool planes, double plane_window, const py::object& progress,
           std::size_t tile_casters, std::size_t fast_tile_casters) {
          need_scene(scene);
          // compute_shadows in three steps, so that Ctrl-C is heard while the scene is prepared
          // too (the engine's progress checks signals; the user's callback counts pairs only).
          const std::function<void(const Progress&)> check = wrap_progress(py::none());
          return run_compute(scene,
                             make_options(threads, polygons, lights, arithmetic, planes, plane_window, progress,
                                          tile_casters, fast_tile_casters),
                             [&](const ShadowOptions& o) {
                               return shadow::compute_shadows(ShadowEngine(*scene, o.threads, check), o);
                             });
        },
        py::arg("scene"), py::arg("threads") = 0, py::arg("polygons") = true, py::arg("lights") = py::none(),
        py::arg("arithmetic") = "exact", py::arg("planes") = true, py::arg("plane_window") = 0.0,
        py::arg("progress") = py::none(), py::arg("tile_casters") = ShadowOptions{}.tile_casters,
        py::arg("fast_tile_casters") = ShadowOptions{}.fast_tile_casters,
        "One call: every selected light on every receiving face and (planes) on every plane.\n"
        "tile_casters, fast_tile_casters: split a receiver with more candidate casters than this into\n"
        "tiles (exact: areas unchanged; fast: within the bounds; fragments cut at tile borders; 0: never).");
  m.def("compute_plane_shadows",
        [](const ScenePtr& scene, unsigned threads, std::optional<std::vector<std::size_t>> lights, double plane_window) {
          need_scene(scene);
          ShadowOptions o = make_options(threads, true, lights, "exact", true, plane_window, py::none());
          return without_gil([&] { return compute_plane_shadows(*scene, o); });
        },
        py::arg("scene"), py::arg("threads") = 0, py::arg("lights") = py::none(), py::arg("plane_window") = 0.0,
        "The exact shadows on the scene's planes (Blinn's projection), by plane then light: a list of\n"
        "PlaneShadow. Independent of the face engine.");

  bind_irradiance(m);  // Weather, read_epw, irradiance (irradiance_module.cpp)

  m.attr("__name__") = own_name;  // the import system's own name back (see the top)
}
