// SPDX-License-Identifier: GPL-3.0-or-later
// The datasets and report of a sun series (OutputDirectory::write_series, docs/series.md).
#include "writers/series_outputs.hpp"
#include "writers/face_identity_json.hpp"
#include "writers/json_text.hpp"

#include "writers/vtk_datasets.hpp"
#include "writers/vtm_writer.hpp"

#include <shadow/sun_hours.hpp>
#include <shadow/version.hpp>

#include <nlohmann/json.hpp>

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

namespace shadow::detail {
namespace {

using Json = nlohmann::ordered_json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

vtkSmartPointer<vtkDoubleArray> double_array(const char* name, vtkIdType n) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(n);
  a->Fill(kNaN);
  return a;
}

/// A copy of `base` that shares its points, cells and arrays; new arrays go to the copy only.
vtkSmartPointer<vtkPolyData> share(vtkPolyData* base) {
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->ShallowCopy(base);
  return poly;
}


}  // namespace

vtkSmartPointer<vtkPolyData> make_series_base(const Scene& scene) {
  vtkSmartPointer<vtkPolyData> poly = make_faces_polydata(scene, ShadowResult{});
  const auto n = static_cast<vtkIdType>(scene.faces.size());
  // faces.vtp's own `name` is the face's name as read (empty when unnamed); `label` is its
  // column in sunlit.csv (the name, or face_<id>).
  auto name = vtkSmartPointer<vtkStringArray>::New();
  name->SetName("label");
  name->SetNumberOfValues(n);
  for (vtkIdType c = 0; c < n; ++c) name->SetValue(c, face_label(scene, static_cast<std::size_t>(c)));
  poly->GetCellData()->AddArray(name);
  return poly;
}

bool is_series_instant_name(const std::string& name) {
  for (const std::string prefix : {"sun_", "fragments_"}) {
    const std::size_t n = prefix.size();
    // `%05zu`: five digits, more from instant 100000 on.
    if (name.size() >= n + 9 && name.rfind(prefix, 0) == 0 && name.compare(name.size() - 4, 4, ".vtp") == 0 &&
        name.find_first_not_of("0123456789", n) == name.size() - 4)
      return true;
  }
  return false;
}

vtkSmartPointer<vtkPolyData> make_series_instant(vtkPolyData* base, const SeriesResult& series, std::size_t instant) {
  return make_series_instant(base, series, SeriesColumn::of(series, instant));
}

vtkSmartPointer<vtkPolyData> make_series_instant(vtkPolyData* base, const SeriesResult& shape, const SeriesColumn& column) {
  vtkSmartPointer<vtkPolyData> poly = share(base);
  const vtkIdType n = poly->GetNumberOfCells();
  auto fraction = double_array("lit_fraction", n);
  auto lit = double_array("lit_area", n);
  auto facing = vtkSmartPointer<vtkTypeInt32Array>::New();
  facing->SetName("faces_light");
  facing->SetNumberOfTuples(n);
  facing->Fill(0);
  const bool fast = shape.arithmetic == Arithmetic::Fast;
  vtkSmartPointer<vtkDoubleArray> bound = fast ? double_array("lit_area_error_bound", n) : nullptr;
  for (std::size_t r = 0; r < shape.faces.size(); ++r) {
    const auto cell = static_cast<vtkIdType>(shape.faces[r]);
    if (cell >= n) continue;
    const std::size_t at = r * column.stride;
    fraction->SetValue(cell, column.lit_fraction[at]);
    lit->SetValue(cell, column.lit_area[at]);
    facing->SetValue(cell, column.faces_light[at]);
    if (bound) bound->SetValue(cell, column.lit_area_error_bound[at]);
  }
  vtkCellData* cd = poly->GetCellData();
  cd->AddArray(fraction);
  cd->AddArray(lit);
  cd->AddArray(facing);
  if (bound) cd->AddArray(bound);
  cd->SetActiveScalars("lit_fraction");
  return poly;
}

vtkSmartPointer<vtkPolyData> make_series_faces(vtkPolyData* base, const SeriesResult& series,
                                               const std::vector<double>& sun_hours,
                                               const std::vector<double>& sun_hours_bound) {
  vtkSmartPointer<vtkPolyData> poly = share(base);
  const vtkIdType n = poly->GetNumberOfCells();
  auto hours = double_array("sun_hours", n);
  const bool fast = series.arithmetic == Arithmetic::Fast;
  vtkSmartPointer<vtkDoubleArray> bound = fast ? double_array("sun_hours_error_bound", n) : nullptr;
  for (std::size_t r = 0; r < series.faces.size(); ++r) {
    const auto cell = static_cast<vtkIdType>(series.faces[r]);
    if (cell >= n) continue;
    hours->SetValue(cell, sun_hours[r]);
    if (bound) bound->SetValue(cell, sun_hours_bound[r]);
  }
  poly->GetCellData()->AddArray(hours);
  if (bound) poly->GetCellData()->AddArray(bound);
  poly->GetCellData()->SetActiveScalars("sun_hours");
  return poly;
}

void write_pvd(const std::vector<std::pair<double, std::string>>& steps, const std::filesystem::path& path,
               const std::filesystem::path& shown_as) {
  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (out) {
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "  <Collection>\n";
    char time[32];
    for (const auto& [t, file] : steps) {
      std::snprintf(time, sizeof time, "%.17g", t);
      out << "    <DataSet timestep=\"" << time << "\" group=\"\" part=\"0\" file=\"" << xml_escape(file)
          << "\"/>\n";
    }
    out << "  </Collection>\n</VTKFile>\n";
    out.close();
  }
  if (!out) {
    const int saved = errno;
    throw OutputError(shown_as.string() + ": " + (saved != 0 ? std::strerror(saved) : "could not write the file"));
  }
}

namespace {

/// report.json's `sun_hours_map` (additive): the map's size and, for the threshold map, the
/// exact area that gets at least each level's hours, and its share of the mapped area.
Json sun_hours_map_json(const SunHoursMap& map) {
  const double area = sun_hours_map_area(map);
  Json j = {{"file", "sun_hours.vtp"},  {"faces", map.faces.size()},     {"cells", map.cells.size()},
            {"regions", map.regions}, {"total_hours", map.total_hours}, {"area", area}, {"full", map.full}};
  if (!map.full) j["file"] = nullptr;  // the threshold map alone: no sun_hours.vtp
  if (!map.levels.empty()) {
    const std::vector<double> at_least = sun_hours_level_areas(map);
    Json levels = Json::array();
    for (std::size_t k = 0; k < map.levels.size(); ++k)
      levels.push_back({{"hours", map.levels[k]},
                        {"area", at_least[k]},
                        {"fraction", area > 0 ? at_least[k] / area : 0.0}});
    j["levels"] = levels;
    j["levels_file"] = "sun_hours_levels.vtp";
    j["level_cells"] = map.level_cells.size();
  }
  return j;
}

}  // namespace

void write_series_report_json(std::ostream& out, const Scene& scene, const SunSeries& suns,
                              const SeriesResult& series, const SurfaceSeries& surfaces,
                              const ObjectSunHours& objects, const std::vector<double>& sun_hours, const std::vector<double>& sun_hours_bound,
                              const EnergyPlusSchedule& energyplus, std::size_t every, const RunInfo* run) {
  const bool fast = series.arithmetic == Arithmetic::Fast;
  Json report;
  report["libshadow_version"] = version();
  report["scene"] = scene.source.string();
  Json run_json;
  run_json["scene"] = run != nullptr && !run->scene.empty() ? run->scene : scene.source.string();
  run_json["started_utc"] = run != nullptr && !run->started_utc.empty() ? Json(run->started_utc) : Json(nullptr);
  run_json["libshadow_version"] = version();
  run_json["command"] = "series";
  run_json["arithmetic"] = fast ? "fast" : "exact";
  if (run != nullptr) {
    run_json["options"] = {{"threads", run->options.threads}, {"planarity_tolerance", run->planarity_tolerance},
                           {"every", every}};
    // Additive keys, written only when not the defaults (as in `shadow compute`'s report.json):
    // reports of runs with the default thresholds stay as they were.
    const SeriesOptions defaults;
    if (run->options.tile_casters != defaults.tile_casters) run_json["options"]["tile_casters"] = run->options.tile_casters;
    if (run->options.fast_tile_casters != defaults.fast_tile_casters)
      run_json["options"]["fast_tile_casters"] = run->options.fast_tile_casters;
  }
  report["run"] = run_json;

  Json s;
  s["instants"] = suns.all_instants;
  s["above_horizon"] = series.instants;
  s["arithmetic"] = fast ? "fast" : "exact";
  s["hours_per_instant"] = suns.hours_per_instant;
  s["integration"] = suns.explicit_times
                         ? "each instant counts for the median gap between consecutive times: "
                           "sun_hours = sum(lit_fraction) * hours_per_instant"
                         : scene.sun && scene.sun->energyplus_times
                             ? "each instant stands for the step it ends (mid-step for steps of an hour or more, "
                               "EnergyPlus's times): sun_hours = sum(lit_fraction) * step_minutes / 60"
                             : "each instant stands for the step it starts: sun_hours = sum(lit_fraction) * step_minutes / 60";
  if (scene.sun) {
    const SunPeriod& p = *scene.sun;
    s["site"] = {{"latitude", p.site.latitude}, {"longitude", p.site.longitude}, {"elevation", p.site.elevation}};
    s["utc_offset"] = p.utc_offset_hours;
    if (p.times.empty()) {
      s["start"] = p.start;
      s["end"] = p.end;
      s["step_minutes"] = p.step_minutes;
      if (p.energyplus_times) s["energyplus_times"] = true;
    }
    s["north_axis"] = p.north_axis;
    s["min_elevation"] = p.min_elevation;
  }
  if (!suns.times.empty()) {
    s["first"] = format_iso8601_utc(suns.times.front());
    s["last"] = format_iso8601_utc(suns.times.back());
  }
  s["pvd_every"] = every;
  Json ep;
  ep["written"] = energyplus.written;
  if (energyplus.written) {
    ep["file"] = "energyplus-shading.csv";
    ep["year"] = energyplus.year;
    ep["timesteps_per_hour"] = energyplus.timesteps_per_hour;
    ep["rows"] = energyplus.rows;
    ep["rows_in_period"] = energyplus.rows_in_period;
  }
  if (!energyplus.reason.empty()) ep["note"] = energyplus.reason;
  s["energyplus"] = ep;
  Json named = Json::array();
  for (std::size_t i = 0; i < surfaces.surfaces.size(); ++i)
    named.push_back({{"name", surfaces.surfaces[i].label},
                     {"faces", surfaces.surfaces[i].faces},
                     {"area", surfaces.area[i]},
                     {"sun_hours", surfaces.sun_hours[i]}});
  s["surfaces"] = named;
  s["skipped_faces"] = scene.skipped_faces.size();  // --skip-invalid (additive key)
  // Per building, zone or mesh (sun_hours_by_object.csv): additive, after the surfaces.
  Json per_object = Json::array();
  std::vector<const std::string*> object_of_mesh(scene.meshes.size(), nullptr);
  for (std::size_t i = 0; i < objects.objects.size(); ++i) {
    const SceneObject& o = objects.objects[i];
    Json meshes = Json::array();
    for (const std::size_t m : o.meshes) {
      meshes.push_back(scene.meshes[m].name);
      object_of_mesh[m] = &o.id;
    }
    per_object.push_back({{"id", o.id},
                          {"type", o.type},
                          {"meshes", meshes},
                          {"face_count", objects.faces[i]},
                          {"area", objects.area[i]},
                          {"sun_hours", objects.sun_hours[i]},
                          {"sunlit_area_hours", objects.sunlit_area_hours[i]}});
  }
  s["objects"] = per_object;
  report["series"] = s;
  if (run != nullptr && run->sun_hours_map != nullptr) report["sun_hours_map"] = sun_hours_map_json(*run->sun_hours_map);
  if (!scene.skipped_faces.empty()) report["skipped_faces"] = skipped_faces_json(scene);  // as in compute's

  // The members so far, then the faces one entry at a time (a city's entries as one document
  // were most of a series' peak memory at the end), then the rest: the bytes of dump(2).
  out << "{\n";
  for (const auto& [key, value] : report.items()) detail::write_member(out, key, detail::dump_json(value, 2));
  report = Json::object();
  out << "  \"faces\": [";
  for (std::size_t r = 0; r < series.faces.size(); ++r) {
    const std::size_t f = series.faces[r];
    const Face& face = scene.faces[f];
    Json entry = {{"id", f},
                  {"mesh", face.mesh < scene.meshes.size() ? scene.meshes[face.mesh].name : std::string()}};
    detail::add_face_identity(entry, scene, f);  // as in `shadow compute`'s report.json
    entry["label"] = face_label(scene, f);       // its column in sunlit.csv: the name or face_<id>
    if (face.mesh < object_of_mesh.size() && object_of_mesh[face.mesh] != nullptr)
      entry["object"] = *object_of_mesh[face.mesh];  // its row in sun_hours_by_object.csv
    entry["area"] = series.area[r];
    entry["sun_hours"] = sun_hours[r];
    if (fast) entry["sun_hours_error_bound"] = sun_hours_bound[r];
    out << (r == 0 ? "\n    " : ",\n    ") << detail::indent_more(detail::dump_json(entry, 2), 4);
  }
  out << (series.faces.empty() ? "],\n" : "\n  ],\n");
  const ShadowStats& st = series.stats;
  Json stats = {{"receivers", st.receivers},           {"back_facing", st.back_facing},
                {"candidate_pairs", st.candidate_pairs}, {"casting_pairs", st.casting_pairs},
                {"unshadowed", st.unshadowed}};
  if (fast) {
    stats["fast_exact_fallbacks"] = st.fast_exact_fallbacks;
    stats["fast_collapsed"] = st.fast_collapsed;
  }
  if (st.tiled_receivers > 0) {  // receivers split into tiles only (additive keys, as in compute's)
    stats["tiled_receivers"] = st.tiled_receivers;
    stats["tiles"] = st.tiles;
  }
  detail::write_member(out, "stats", detail::dump_json(stats, 2));
  Json warnings = Json::array();
  for (const Warning& w : scene.warnings) warnings.push_back(w.to_string());
  detail::write_member(out, "warnings", detail::dump_json(warnings, 2), true);
  out << "}\n";
}

}  // namespace shadow::detail
