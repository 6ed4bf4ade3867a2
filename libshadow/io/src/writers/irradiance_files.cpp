// SPDX-License-Identifier: GPL-3.0-or-later
// The files of `shadow irradiance` (shadow/irradiance_output.hpp, docs/irradiance.md).
#include <shadow/irradiance_output.hpp>

#include "writers/face_identity_json.hpp"
#include "writers/series_outputs.hpp"
#include "writers/staged_files.hpp"
#include "writers/vtk_datasets.hpp"
#include "writers/vtp_writer.hpp"

#include <shadow/output.hpp>
#include <shadow/series_files.hpp>
#include <shadow/version.hpp>

#include <nlohmann/json.hpp>

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkPolyData.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>

namespace shadow {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
const char* const kMonths[12] = {"jan", "feb", "mar", "apr", "may", "jun", "jul", "aug", "sep", "oct", "nov", "dec"};

/// A number as JSON: null when not finite.
Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

/// The period's components; `scene` (what the scene's faces reflect) only when computed (not NaN).
Json components(double direct, double diffuse, double reflected, double total,
                double scene = std::numeric_limits<double>::quiet_NaN()) {
  Json j{{"direct", number(direct)}, {"sky_diffuse", number(diffuse)}, {"ground_reflected", number(reflected)}};
  if (!std::isnan(scene)) j["scene_reflected"] = number(scene);
  j["total"] = number(total);
  return j;
}

Json months(const std::vector<double>& values, std::size_t row) {
  Json a = Json::array();
  for (std::size_t m = 0; m < 12; ++m) a.push_back(number(values[row * 12 + m]));
  return a;
}

Json group_json(const IrradianceGroup& g) {
  Json j;
  j["name"] = g.name;
  if (!g.type.empty()) j["type"] = g.type;
  j["faces"] = g.rows.size();
  j["area"] = number(g.area);
  j["sky_view_factor"] = number(g.sky_view_factor);
  j["ground_view_factor"] = number(g.ground_view_factor);
  j["annual_irradiation_kwh_m2"] = components(g.direct, g.sky_diffuse, g.ground_reflected, g.total, g.scene_reflected);
  j["monthly_total_kwh_m2"] = g.monthly_total;
  return j;
}

std::string sky_name(SkyModel sky) { return sky == SkyModel::Perez ? "perez" : "isotropic"; }

Json run_json(const Scene& scene, const Weather& weather, const IrradianceResult& r, const IrradianceRunInfo& run) {
  Json j;
  j["scene"] = run.scene;
  j["weather"] = run.weather;
  j["location"] = {{"city", weather.location.city},     {"country", weather.location.country},
                   {"latitude", weather.location.latitude}, {"longitude", weather.location.longitude},
                   {"time_zone_hours", weather.location.time_zone_hours}, {"elevation", weather.location.elevation}};
  Json period;
  period["from"] = run.from;
  period["to"] = run.to;
  period["hours"] = r.hours.size();
  if (!r.hours.empty()) {
    period["first_hour_start_utc"] = format_iso8601_utc(weather.start_utc[r.hours.front().record]);
    period["last_hour_end_utc"] = format_iso8601_utc(weather.start_utc[r.hours.back().record] + 3600);
  }
  period["sun_instants"] = r.sun_lights.size();
  period["missing_hours"] = r.missing_hours;
  j["period"] = period;
  j["sky"] = sky_name(r.sky_model);
  j["sky_patches"] = r.patches.size();
  j["ground_patches"] = r.ground_patches.size();
  Json ground_meshes = Json::array();  // the meshes that are the ground (ground_faces())
  const std::vector<unsigned char> ground = ground_faces(scene);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    bool all = mesh.face_count > 0;
    for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count; ++f) all = all && ground[f] != 0;
    if (all) ground_meshes.push_back(mesh.name);
  }
  j["ground_meshes"] = ground_meshes;
  j["ground_reflectance"] = r.ground_reflectance;
  j["arithmetic"] = r.sky.arithmetic == Arithmetic::Fast ? "fast" : "exact";
  j["threads"] = run.threads;
  j["conventions"] =
      "each weather record covers the hour ending at its stamp (local standard time); the sun is the SPA's at "
      "mid-hour; irradiation in kWh/m2 over the period; the ground is what a face sees below the horizon that is no face "
      "or a ground face (ground_meshes, faces of kind GroundSurface), through the ground patches";
  j["seconds"] = {{"sky_patches", r.seconds_sky}, {"ground_patches", r.seconds_ground}, {"sun", r.seconds_sun}, {"sums", r.seconds_sums},
                  {"total", run.seconds_total}};
  j["started_utc"] = run.started_utc;
  return j;
}

Json report_json(const Scene& scene, const Weather& weather, const IrradianceResult& r, const IrradianceRunInfo& run) {
  Json j;
  j["libshadow_version"] = version();
  j["kind"] = "irradiance";
  j["run"] = run_json(scene, weather, r, run);
  if (!r.scene_reflected.empty())
    j["reflections"] = {{"elements", r.reflections.elements},
                        {"shots", r.reflections.shots},
                        {"method", r.reflections.hierarchical ? "hierarchical" : "shooting"},
                        {"iterations", r.reflections.iterations},
                        {"near_links", r.reflections.near_links},
                        {"far_links", r.reflections.far_links},
                        {"unshot_fraction", number(r.reflections.unshot_fraction)},
                        {"error_estimate", number(r.reflections.error_estimate)},
                        {"default_reflectance", r.reflections.default_reflectance},
                        {"seconds", number(r.reflections.seconds)},
                        {"note", "one radiosity solution on the period's irradiation of every receiving face; "
                                 "part of annual total, not of the monthly totals"}};
  j["energy_check"] = {{"max_direct_excess_w_m2", r.max_direct_excess},
                       {"max_sky_diffuse_excess_w_m2", r.max_diffuse_excess},
                       {"min_component_w_m2", r.min_component},
                       {"sky_diffuse_excess_from_negative_horizon_band_w_m2", r.max_horizon_band_excess},
                       {"ok", r.energy_check_ok()}};
  Json faces = Json::array();
  for (std::size_t row = 0; row < r.faces.size(); ++row) {
    Json f;
    f["face"] = r.faces[row];
    f["label"] = face_label(scene, r.faces[row]);
    f["mesh"] = scene.meshes[scene.faces[r.faces[row]].mesh].name;
    f["area"] = number(r.area[row]);
    f["normal"] = {r.normal[row].x, r.normal[row].y, r.normal[row].z};
    f["sky_view_factor"] = number(r.sky_view_factor[row]);
    f["ground_view_factor"] = number(r.ground_view[row]);
    f["ground"] = r.on_ground[row] != 0;
    f["annual_irradiation_kwh_m2"] =
        components(r.direct[row], r.sky_diffuse[row], r.ground_reflected[row], r.total[row],
                   r.scene_reflected.empty() ? std::numeric_limits<double>::quiet_NaN() : r.scene_reflected[row]);
    if (r.sun.arithmetic == Arithmetic::Fast || r.sky.arithmetic == Arithmetic::Fast) {
      f["direct_error_bound_kwh_m2"] = number(r.direct_error_bound[row]);
      f["sky_view_factor_error_bound"] = number(r.sky_view_factor_error_bound[row]);
      f["ground_view_factor_error_bound"] = number(r.ground_view_factor_error_bound[row]);
    }
    f["monthly_irradiation_kwh_m2"] = {{"direct", months(r.monthly_direct, row)},
                                       {"sky_diffuse", months(r.monthly_sky_diffuse, row)},
                                       {"ground_reflected", months(r.monthly_ground_reflected, row)},
                                       {"total", months(r.monthly_total, row)}};
    faces.push_back(f);
  }
  j["faces"] = faces;
  Json warnings = Json::array();
  for (const Warning& w : weather.warnings) warnings.push_back(w.to_string());
  for (const Warning& w : scene.warnings) warnings.push_back(w.to_string());
  j["warnings"] = warnings;
  j["skipped_faces"] = detail::skipped_faces_json(scene);  // --skip-invalid: the faces left out
  for (const auto& [key, grouping] : {std::pair<const char*, IrradianceGrouping>{"surfaces", IrradianceGrouping::Surface},
                                      {"objects", IrradianceGrouping::Object},
                                      {"meshes", IrradianceGrouping::Mesh}}) {
    Json list = Json::array();
    for (const IrradianceGroup& g : irradiance_groups(scene, r, grouping)) list.push_back(group_json(g));
    j[key] = list;
  }
  return j;
}

void write_irradiation_csv(std::ostream& out, const std::vector<IrradianceGroup>& surfaces) {
  out.precision(std::numeric_limits<double>::max_digits10);
  out << "surface,area_m2,sky_view_factor,direct_kwh_m2,sky_diffuse_kwh_m2,ground_reflected_kwh_m2,total_kwh_m2";
  for (const char* m : kMonths) out << ',' << m << "_kwh_m2";
  out << "\r\n";
  for (const IrradianceGroup& g : surfaces) {
    out << csv_field(g.name) << ',' << g.area << ',' << g.sky_view_factor << ',' << g.direct << ',' << g.sky_diffuse << ','
        << g.ground_reflected << ',' << g.total;
    for (double m : g.monthly_total) out << ',' << m;
    out << "\r\n";
  }
}

/// W/m2 per named surface and hour: area-weighted over the surface's faces.
void write_hourly_csv(std::ostream& out, const Weather& weather, const IrradianceResult& r,
                      const std::vector<IrradianceGroup>& surfaces) {
  out.precision(std::numeric_limits<double>::max_digits10);
  out << "hour_start_utc,surface,direct_w_m2,sky_diffuse_w_m2,ground_reflected_w_m2,total_w_m2\r\n";
  for (std::size_t h = 0; h < r.hours.size(); ++h) {
    const std::string time = format_iso8601_utc(weather.start_utc[r.hours[h].record]);
    for (const IrradianceGroup& g : surfaces) {
      double direct = 0.0, diffuse = 0.0, reflected = 0.0;
      for (std::size_t row : g.rows) {
        const FaceIrradiance e = face_irradiance(r, row, h);
        direct += e.direct * r.area[row];
        diffuse += e.sky_diffuse * r.area[row];
        reflected += e.ground_reflected * r.area[row];
      }
      const double a = g.area > 0.0 ? g.area : 1.0;
      out << time << ',' << csv_field(g.name) << ',' << direct / a << ',' << diffuse / a << ',' << reflected / a << ','
          << (direct + diffuse + reflected) / a << "\r\n";
    }
  }
}

void write_energyplus_csv(std::ostream& out, const std::vector<IrradianceGroup>& surfaces) {
  out.precision(std::numeric_limits<double>::max_digits10);
  out << "Surface Name,Diffuse Shading Ratio\r\n";
  for (const IrradianceGroup& g : surfaces) {
    const double ratio = g.sky_diffuse_unshaded > 0.0 ? g.sky_diffuse / g.sky_diffuse_unshaded : 1.0;
    out << csv_field(energyplus_name(g.name)) << ',' << ratio << "\r\n";
  }
}

vtkSmartPointer<vtkPolyData> faces_polydata(const Scene& scene, const IrradianceResult& r) {
  // faces.vtp of a series: the faces with their `label` (the CSV columns' names).
  vtkSmartPointer<vtkPolyData> poly = detail::make_series_base(scene);
  const auto n = static_cast<vtkIdType>(scene.faces.size());
  const std::pair<const char*, const std::vector<double>*> arrays[] = {
      {"irradiation_direct_kwh_m2", &r.direct},
      {"irradiation_sky_diffuse_kwh_m2", &r.sky_diffuse},
      {"irradiation_ground_reflected_kwh_m2", &r.ground_reflected},
      {"irradiation_total_kwh_m2", &r.total},
      {"sky_view_factor", &r.sky_view_factor},
      {"ground_view_factor", &r.ground_view}};
  std::vector<std::pair<const char*, const std::vector<double>*>> all(std::begin(arrays), std::end(arrays));
  if (!r.scene_reflected.empty()) all.emplace_back("irradiation_scene_reflected_kwh_m2", &r.scene_reflected);
  for (const auto& [name, values] : all) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfTuples(n);
    a->Fill(std::numeric_limits<double>::quiet_NaN());  // NaN: the face does not receive
    for (std::size_t row = 0; row < r.faces.size(); ++row)
      if (static_cast<vtkIdType>(r.faces[row]) < n) a->SetValue(static_cast<vtkIdType>(r.faces[row]), (*values)[row]);
    poly->GetCellData()->AddArray(a);
  }
  poly->GetCellData()->SetActiveScalars("irradiation_total_kwh_m2");
  return poly;
}

vtkSmartPointer<vtkPolyData> map_polydata(const Scene& scene, const IrradianceResult& r, const SunHoursMap& map) {
  vtkSmartPointer<vtkPolyData> poly = detail::make_sun_hours_polydata(map);
  vtkCellData* cd = poly->GetCellData();
  cd->GetArray("sun_hours")->SetName("irradiation_direct_kwh_m2");
  poly->GetFieldData()->RemoveArray("total_hours");  // hours of a sun-hours map: not this map's
  std::map<std::size_t, std::size_t> row_of;
  for (std::size_t row = 0; row < r.faces.size(); ++row) row_of[r.faces[row]] = row;
  const auto n = static_cast<vtkIdType>(map.cells.size());
  const char* names[] = {"irradiation_sky_diffuse_kwh_m2", "irradiation_ground_reflected_kwh_m2", "irradiation_total_kwh_m2"};
  vtkSmartPointer<vtkDoubleArray> arrays[3];
  for (int k = 0; k < 3; ++k) {
    arrays[k] = vtkSmartPointer<vtkDoubleArray>::New();
    arrays[k]->SetName(names[k]);
    arrays[k]->SetNumberOfTuples(n);
  }
  for (vtkIdType c = 0; c < n; ++c) {
    const SunHoursCell& cell = map.cells[static_cast<std::size_t>(c)];
    const std::size_t row = row_of.at(cell.face_id);
    arrays[0]->SetValue(c, r.sky_diffuse[row]);
    arrays[1]->SetValue(c, r.ground_reflected[row]);
    arrays[2]->SetValue(c, cell.sun_hours + r.sky_diffuse[row] + r.ground_reflected[row]);
  }
  for (auto& a : arrays) cd->AddArray(a);
  cd->SetActiveScalars("irradiation_total_kwh_m2");
  detail::shift_to_origin(poly, scene);
  return poly;
}

}  // namespace

std::vector<IrradianceGroup> irradiance_groups(const Scene& scene, const IrradianceResult& r, IrradianceGrouping grouping) {
  std::map<std::size_t, std::size_t> row_of;
  for (std::size_t row = 0; row < r.faces.size(); ++row) row_of[r.faces[row]] = row;
  std::vector<IrradianceGroup> groups;
  auto add_faces = [&](IrradianceGroup& g, std::size_t first, std::size_t count) {
    for (std::size_t f = first; f < first + count; ++f) {
      const auto it = row_of.find(f);
      if (it != row_of.end()) g.rows.push_back(it->second);
    }
  };
  if (grouping == IrradianceGrouping::Surface) {
    for (const NamedSurface& s : named_surfaces(scene)) {
      IrradianceGroup g;
      g.name = s.label;
      for (std::size_t f : s.faces) add_faces(g, f, 1);
      groups.push_back(std::move(g));
    }
  } else {
    for (const SceneObject& o : scene_objects(scene, true, grouping == IrradianceGrouping::Mesh)) {
      IrradianceGroup g;
      g.name = o.id;
      g.type = o.type;
      for (std::size_t m : o.meshes) add_faces(g, scene.meshes[m].first_face, scene.meshes[m].face_count);
      groups.push_back(std::move(g));
    }
  }
  for (IrradianceGroup& g : groups) {
    g.monthly_total.assign(12, 0.0);
    if (!r.scene_reflected.empty()) g.scene_reflected = 0.0;
    for (std::size_t row : g.rows) {
      const double a = r.area[row];
      g.area += a;
      g.sky_view_factor += r.sky_view_factor[row] * a;
      g.ground_view_factor += r.ground_view[row] * a;
      g.direct += r.direct[row] * a;
      g.sky_diffuse += r.sky_diffuse[row] * a;
      g.ground_reflected += r.ground_reflected[row] * a;
      g.total += r.total[row] * a;
      if (!r.scene_reflected.empty()) g.scene_reflected += r.scene_reflected[row] * a;
      g.sky_diffuse_unshaded += r.sky_diffuse_unshaded[row] * a;
      for (std::size_t m = 0; m < 12; ++m) g.monthly_total[m] += r.monthly_total[row * 12 + m] * a;
    }
    if (g.area > 0.0) {
      for (double* v : {&g.sky_view_factor, &g.ground_view_factor, &g.direct, &g.sky_diffuse, &g.ground_reflected,
                        &g.total, &g.sky_diffuse_unshaded})
        *v /= g.area;
      if (!r.scene_reflected.empty()) g.scene_reflected /= g.area;
      for (double& m : g.monthly_total) m /= g.area;
    }
  }
  return groups;
}

std::vector<fs::path> write_irradiance_outputs(const fs::path& outdir, const Scene& scene, const Weather& weather,
                                               const IrradianceResult& result, const IrradianceRunInfo& run,
                                               const IrradianceFiles& files) {
  detail::make_output_directory(outdir);
  detail::remove_stale_report(outdir / "report.json");
  detail::StagedFiles staging(outdir);
  const auto write = [&](const std::string& name, const std::function<void(std::ostream&)>& text) {
    detail::write_staged_stream(staging.stage(name), text);
  };
  const std::vector<IrradianceGroup> surfaces = irradiance_groups(scene, result, IrradianceGrouping::Surface);
  write("irradiation.csv", [&](std::ostream& out) { write_irradiation_csv(out, surfaces); });
  if (files.hourly)
    write("irradiance_hourly.csv", [&](std::ostream& out) { write_hourly_csv(out, weather, result, surfaces); });
  if (files.energyplus)
    write("energyplus-diffuse-shading.csv", [&](std::ostream& out) { write_energyplus_csv(out, surfaces); });
  vtkSmartPointer<vtkPolyData> faces = faces_polydata(scene, result);
  detail::shift_to_origin(faces, scene);  // like every other dataset (Scene::origin)
  const auto faces_file = staging.stage("faces.vtp");
  detail::write_polydata(faces, faces_file.temp, faces_file.final_path);
  if (files.map != nullptr) {
    const auto map_file = staging.stage("irradiation_map.vtp");
    detail::write_polydata(map_polydata(scene, result, *files.map), map_file.temp, map_file.final_path);
  }
  write("report.json", [&](std::ostream& out) { out << report_json(scene, weather, result, run).dump(2) << "\n"; });
  return staging.commit();
}

}  // namespace shadow
