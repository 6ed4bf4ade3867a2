// SPDX-License-Identifier: GPL-3.0-or-later
// Python bindings of weather files and irradiation (docs/irradiance.md, docs/python.md):
// libshadow.read_epw(path), read_tmy3(path), read_weather(path) and libshadow.irradiance(scene, weather, ...), results as numpy arrays.
#include <shadow/irradiance.hpp>
#include <shadow/shadows.hpp>
#include <shadow/epw.hpp>
#include <shadow/weather.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

template <class T>
py::array_t<T> array_of(const std::vector<T>& values) {
  py::array_t<T> a(static_cast<py::ssize_t>(values.size()));
  T* out = a.mutable_data();
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = values[i];
  return a;
}

py::array_t<std::int64_t> array_of_sizes(const std::vector<std::size_t>& values) {
  py::array_t<std::int64_t> a(static_cast<py::ssize_t>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i) a.mutable_data()[i] = static_cast<std::int64_t>(values[i]);
  return a;
}

py::array_t<double> months(const std::vector<double>& values, std::size_t rows) {
  py::array_t<double> a({static_cast<py::ssize_t>(rows), py::ssize_t{12}});
  for (std::size_t i = 0; i < rows * 12; ++i) a.mutable_data()[i] = values[i];
  return a;
}

/// The hourly components (rows x hours, W/m2) of a result.
py::dict hourly(const shadow::IrradianceResult& r) {
  const std::size_t rows = r.faces.size(), hours = r.hours.size();
  py::array_t<double> direct({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(hours)});
  py::array_t<double> diffuse({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(hours)});
  py::array_t<double> reflected({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(hours)});
  for (std::size_t row = 0; row < rows; ++row)
    for (std::size_t h = 0; h < hours; ++h) {
      const shadow::FaceIrradiance e = shadow::face_irradiance(r, row, h);
      direct.mutable_data()[row * hours + h] = e.direct;
      diffuse.mutable_data()[row * hours + h] = e.sky_diffuse;
      reflected.mutable_data()[row * hours + h] = e.ground_reflected;
    }
  py::dict d;
  d["direct"] = direct;
  d["sky_diffuse"] = diffuse;
  d["ground_reflected"] = reflected;
  return d;
}

}  // namespace

void bind_irradiance(py::module_& m) {
  py::class_<shadow::Weather>(m, "Weather",
                              "An hourly weather file (EPW): location and per-record arrays. Each record covers the "
                              "hour ending at its stamp (local standard time); irradiation in Wh/m2, NaN when missing.")
      .def_readonly("source", &shadow::Weather::source)
      .def_property_readonly("city", [](const shadow::Weather& w) { return w.location.city; })
      .def_property_readonly("country", [](const shadow::Weather& w) { return w.location.country; })
      .def_property_readonly("latitude", [](const shadow::Weather& w) { return w.location.latitude; })
      .def_property_readonly("longitude", [](const shadow::Weather& w) { return w.location.longitude; })
      .def_property_readonly("time_zone_hours", [](const shadow::Weather& w) { return w.location.time_zone_hours; })
      .def_property_readonly("elevation", [](const shadow::Weather& w) { return w.location.elevation; })
      .def_readonly("year", &shadow::Weather::year)
      .def_property_readonly("month", [](const shadow::Weather& w) { return array_of(w.month); })
      .def_property_readonly("day", [](const shadow::Weather& w) { return array_of(w.day); })
      .def_property_readonly("hour", [](const shadow::Weather& w) { return array_of(w.hour); })
      .def_property_readonly("start_utc", [](const shadow::Weather& w) { return array_of(w.start_utc); },
                             "UTC seconds at which each record's hour starts")
      .def_property_readonly("global_horizontal", [](const shadow::Weather& w) { return array_of(w.global_horizontal); })
      .def_property_readonly("direct_normal", [](const shadow::Weather& w) { return array_of(w.direct_normal); })
      .def_property_readonly("diffuse_horizontal", [](const shadow::Weather& w) { return array_of(w.diffuse_horizontal); })
      .def_property_readonly("dry_bulb", [](const shadow::Weather& w) { return array_of(w.dry_bulb); })
      .def_property_readonly("albedo", [](const shadow::Weather& w) { return array_of(w.albedo); })
      .def_property_readonly("warnings",
                             [](const shadow::Weather& w) {
                               std::vector<std::string> out;
                               for (const shadow::Warning& warning : w.warnings) out.push_back(warning.to_string());
                               return out;
                             },
                             "what the reader found odd but read as written, one line each")
      .def("__len__", &shadow::Weather::hours);

  m.def("read_epw", &shadow::read_epw, py::arg("path"),
        "Reads an EnergyPlus EPW weather file. Raises InputError naming the file, line and field.");
  m.def("read_tmy3", &shadow::read_tmy3, py::arg("path"),
        "Reads an NREL TMY3 CSV weather file (site line, column names, hourly records). Raises InputError naming\n"
        "the file, line and field.");
  m.def("read_weather", &shadow::read_weather, py::arg("path"),
        "Reads a weather file: TMY3 when the name ends in .csv, else EPW.");

  m.def(
      "irradiance",
      [](const std::shared_ptr<shadow::Scene>& scene, const shadow::Weather& weather, const std::string& sky,
         int sky_patches, std::optional<double> ground_reflectance, std::size_t first_record,
         std::optional<std::size_t> end_record, bool fast, unsigned threads, bool with_hourly,
         const std::optional<std::vector<std::string>>& ground) {
        if (!scene) throw shadow::InputError({"", "scene"}, "no scene");
        // ground=[names]: these meshes are the ground instead of the scene's (a copy of the scene).
        std::shared_ptr<const shadow::Scene> used = scene;
        if (ground) {
          auto copy = std::make_shared<shadow::Scene>(*scene);
          copy->ground.emplace();
          for (const std::string& name : *ground)
            for (std::size_t m : shadow::select_meshes(*copy, name, {"", "ground"}))
              if (std::find(copy->ground->begin(), copy->ground->end(), m) == copy->ground->end())
                copy->ground->push_back(m);
          used = copy;
        }
        if (sky != "perez" && sky != "isotropic")
          throw shadow::InputError({"", "sky"}, "'" + sky + "': use 'perez' or 'isotropic'");
        shadow::IrradianceOptions options;
        options.sky = sky == "perez" ? shadow::SkyModel::Perez : shadow::SkyModel::Isotropic;
        options.sky_patches = sky_patches;
        if (ground_reflectance) {
          // NaN is the library's "not given": from Python it would silently take the default.
          if (std::isnan(*ground_reflectance))
            throw shadow::InputError({"", "ground_reflectance"}, "nan is not in [0, 1] (None: the weather's albedo, else 0.2)");
          options.ground_reflectance = *ground_reflectance;
        }
        options.first_record = first_record;
        if (end_record) options.end_record = *end_record;
        if (scene->sun) options.north_axis = scene->sun->north_axis;
        options.series.threads = threads;
        options.series.arithmetic = fast ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
        const shadow::ShadowEngine engine(*used, threads);
        const shadow::IrradianceResult r = shadow::compute_irradiance(engine, *used, weather, options);
        py::dict d;
        d["face_id"] = array_of_sizes(r.faces);
        d["area"] = array_of(r.area);
        d["sky_view_factor"] = array_of(r.sky_view_factor);
        d["ground_view_factor"] = array_of(r.ground_view);
        d["ground"] = array_of(std::vector<int>(r.on_ground.begin(), r.on_ground.end()));
        d["direct"] = array_of(r.direct);
        d["sky_diffuse"] = array_of(r.sky_diffuse);
        d["ground_reflected"] = array_of(r.ground_reflected);
        d["total"] = array_of(r.total);
        d["sky_diffuse_unshaded"] = array_of(r.sky_diffuse_unshaded);
        d["monthly_total"] = months(r.monthly_total, r.faces.size());
        std::vector<std::size_t> records;
        for (const shadow::IrradianceHour& h : r.hours) records.push_back(h.record);
        d["record"] = array_of_sizes(records);
        d["ground_reflectance"] = r.ground_reflectance;
        d["missing_hours"] = r.missing_hours;
        if (with_hourly) d["hourly"] = hourly(r);
        return d;
      },
      py::arg("scene"), py::arg("weather"), py::arg("sky") = "perez", py::arg("sky_patches") = 145,
      py::arg("ground_reflectance") = py::none(), py::arg("first_record") = 0, py::arg("end_record") = py::none(),
      py::arg("fast") = false, py::arg("threads") = 0, py::arg("hourly") = false, py::arg("ground") = py::none(),
      "Irradiation of every receiving face over weather records [first_record, end_record) (docs/irradiance.md):\n"
      "a dict of numpy arrays per receiving face (face_id, area, sky_view_factor, ground_view_factor, ground\n"
      "(1 for ground faces), direct, sky_diffuse, ground_reflected, total in kWh/m2; monthly_total faces x 12),\n"
      "and with hourly=True the hourly W/m2 components (faces x hours). ground: mesh names (or type:<T>) that\n"
      "are the ground instead of the scene's. Holds the GIL while it computes.");
}
