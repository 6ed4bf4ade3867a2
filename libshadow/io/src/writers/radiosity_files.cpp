// SPDX-License-Identifier: GPL-3.0-or-later
// The files of a radiosity solution (docs/radiosity.md): radiosity.vtp and report.json.
#include <shadow/radiosity_output.hpp>

#include "writers/face_identity_json.hpp"
#include "writers/staged_files.hpp"
#include "writers/vtk_datasets.hpp"
#include "writers/vtm_writer.hpp"
#include "writers/vtp_writer.hpp"

#include <shadow/output.hpp>
#include <shadow/version.hpp>

#include <nlohmann/json.hpp>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt64Array.h>

#include <cmath>
#include <string>
#include <system_error>

namespace shadow {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

vtkSmartPointer<vtkPolyData> make_radiosity_polydata(const Scene& scene, const RadiosityResult& result) {
  const std::size_t n = result.elements.size();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  auto array = [n](const char* name) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfValues(static_cast<vtkIdType>(n));
    return a;
  };
  auto radiosity = array("radiosity"), irradiance = array("irradiance"), direct = array("direct_irradiance"),
       reflectance = array("reflectance"), emittance = array("emittance");
  auto face_id = vtkSmartPointer<vtkTypeInt64Array>::New();
  face_id->SetName("face_id");
  face_id->SetNumberOfValues(static_cast<vtkIdType>(n));
  auto rgb_array = [n](const char* name) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(3);
    a->SetNumberOfTuples(static_cast<vtkIdType>(n));
    return a;
  };
  auto radiosity_rgb = rgb_array("radiosity_rgb"), irradiance_rgb = rgb_array("irradiance_rgb");
  auto element_id = vtkSmartPointer<vtkTypeInt64Array>::New();
  element_id->SetName("element_id");
  element_id->SetNumberOfValues(static_cast<vtkIdType>(n));
  // The material's RGB reflectance, for pictures (shadow render --radiosity --radiosity-mode colour):
  // the solution is one channel, the wall's colour is the scene's.
  auto reflectance_rgb = vtkSmartPointer<vtkDoubleArray>::New();
  reflectance_rgb->SetName("reflectance_rgb");
  reflectance_rgb->SetNumberOfComponents(3);
  reflectance_rgb->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const RadiosityElement& e = result.elements[i];
    cells->InsertNextCell(static_cast<vtkIdType>(e.polygon.size()));
    for (const glm::dvec3& v : e.polygon) cells->InsertCellPoint(points->InsertNextPoint(v.x, v.y, v.z));
    const auto c = static_cast<vtkIdType>(i);
    radiosity->SetValue(c, e.radiosity);
    irradiance->SetValue(c, e.irradiance);
    direct->SetValue(c, e.direct_irradiance);
    reflectance->SetValue(c, e.reflectance);
    emittance->SetValue(c, e.emittance);
    face_id->SetValue(c, static_cast<vtkTypeInt64>(e.face_id));
    element_id->SetValue(c, static_cast<vtkTypeInt64>(i));
    radiosity_rgb->SetTuple3(c, e.radiosity_rgb.x, e.radiosity_rgb.y, e.radiosity_rgb.z);
    irradiance_rgb->SetTuple3(c, e.irradiance_rgb.x, e.irradiance_rgb.y, e.irradiance_rgb.z);
    // A material given one reflectance (or built in code without a colour) is grey.
    glm::dvec3 rgb = e.face_id < scene.faces.size() ? scene.material_of(e.face_id).reflectance_rgb : glm::dvec3(0.0);
    if (rgb == glm::dvec3(0.0)) rgb = glm::dvec3(e.reflectance);
    reflectance_rgb->SetTuple3(c, rgb.r, rgb.g, rgb.b);
  }
  poly->SetPoints(points);
  poly->SetPolys(cells);
  for (vtkDataArray* a : {static_cast<vtkDataArray*>(radiosity), static_cast<vtkDataArray*>(irradiance),
                          static_cast<vtkDataArray*>(direct), static_cast<vtkDataArray*>(reflectance),
                          static_cast<vtkDataArray*>(emittance), static_cast<vtkDataArray*>(face_id),
                          static_cast<vtkDataArray*>(element_id), static_cast<vtkDataArray*>(reflectance_rgb),
                          static_cast<vtkDataArray*>(radiosity_rgb), static_cast<vtkDataArray*>(irradiance_rgb)})
    poly->GetCellData()->AddArray(a);
  poly->GetCellData()->SetActiveScalars("radiosity");
  return poly;
}

}  // namespace

void write_radiosity_report_json(std::ostream& out, const Scene& scene, const RadiosityResult& result,
                                 const RadiosityRunInfo& run) {
  Json doc;
  doc["libshadow_version"] = version();
  doc["kind"] = "radiosity";  // what wrote it, as `shadow irradiance` says "irradiance"
  doc["scene"] = run.scene;
  Json options;
  options["max_element_area"] = run.options.max_element_area;
  options["patch_area"] = run.options.patch_area;
  options["tolerance"] = run.options.tolerance;
  options["max_shots"] = run.options.max_shots;
  options["threads"] = run.options.threads;
  options["method"] = run.options.method == RadiosityMethod::shooting       ? "shooting"
                      : run.options.method == RadiosityMethod::hierarchical ? "hierarchical"
                                                                            : "auto";
  options["link_separation"] = run.options.link_separation;
  options["link_rays"] = run.options.link_rays;
  options["refine_tolerance"] = run.options.refine_tolerance;
  options["refine_passes"] = run.options.refine_passes;
  options["per_light"] = run.options.per_light;
  doc["run"] = {{"started_utc", run.started_utc.empty() ? Json(nullptr) : Json(run.started_utc)},
                {"libshadow_version", version()},
                {"options", options}};
  Json balance;
  balance["emitted_W"] = number(result.emitted_power);
  balance["direct_W"] = number(result.direct_power);
  balance["absorbed_W"] = number(result.absorbed_power);
  balance["escaped_W"] = number(result.escaped_power);
  balance["unshot_W"] = number(result.unshot_power);
  balance["residual"] = number(result.balance_residual);
  Json summary;
  summary["elements"] = result.elements.size();
  summary["patches"] = result.patches;
  summary["shots"] = result.shots;
  summary["exact_evaluations"] = result.exact_evaluations;
  summary["method"] = result.hierarchical ? "hierarchical" : "shooting";
  summary["iterations"] = result.iterations;
  summary["near_links"] = result.near_links;
  summary["far_links"] = result.far_links;
  summary["initial_elements"] = result.initial_elements;
  summary["refine_passes"] = result.refine_passes;
  // Estimated only when refining (the spread is summed then): null otherwise.
  summary["discretization_error"] =
      run.options.refine_tolerance > 0 ? number(result.discretization_error) : Json(nullptr);
  summary["converged"] = result.converged;
  summary["unshot_fraction"] = number(result.unshot_fraction);
  summary["error_estimate"] = number(result.error_estimate);
  summary["colour"] = result.colour;
  summary["channel_unshot_fraction"] = number(result.channel_unshot_fraction);
  summary["seconds"] = number(run.seconds);
  summary["balance"] = balance;
  doc["summary"] = summary;
  Json faces = Json::array();
  for (const FaceRadiosity& f : result.faces) {
    Json entry;
    entry["id"] = f.face_id;
    const std::size_t mesh = f.face_id < scene.faces.size() ? scene.faces[f.face_id].mesh : 0;
    entry["mesh"] = mesh < scene.meshes.size() ? scene.meshes[mesh].name : std::string();
    detail::add_face_identity(entry, scene, f.face_id);
    const Material& m = scene.material_of(f.face_id);
    entry["material"] = m.name;
    entry["reflectance"] = m.reflectance;
    entry["emittance"] = m.emittance;
    entry["area"] = number(f.area);
    entry["elements"] = f.elements;
    entry["radiosity"] = number(f.radiosity);
    entry["irradiance"] = number(f.irradiance);
    entry["direct_irradiance"] = number(f.direct_irradiance);
    Json by_light = Json::array();
    for (double h : f.direct_irradiance_by_light) by_light.push_back(number(h));
    entry["direct_irradiance_by_light"] = std::move(by_light);
    Json all_by_light = Json::array();  // empty when not computed (options.per_light false)
    for (double h : f.irradiance_by_light) all_by_light.push_back(number(h));
    entry["irradiance_by_light"] = std::move(all_by_light);
    entry["radiosity_rgb"] = {number(f.radiosity_rgb.x), number(f.radiosity_rgb.y), number(f.radiosity_rgb.z)};
    entry["irradiance_rgb"] = {number(f.irradiance_rgb.x), number(f.irradiance_rgb.y), number(f.irradiance_rgb.z)};
    faces.push_back(std::move(entry));
  }
  doc["faces"] = std::move(faces);
  // --skip-invalid: the faces left out, as compute's report lists them.
  if (!scene.skipped_faces.empty()) doc["skipped_faces"] = detail::skipped_faces_json(scene);
  out << doc.dump(2) << "\n";
}

std::vector<fs::path> write_radiosity_outputs(const fs::path& outdir, const Scene& scene,
                                              const RadiosityResult& result, const RadiosityRunInfo& run) {
  detail::StagedFiles staging(outdir);
  const auto vtp = staging.stage("radiosity.vtp");
  const auto lights = staging.stage("lights.vtp");
  const auto vtm = staging.stage("scene.vtm");
  vtkSmartPointer<vtkPolyData> poly = make_radiosity_polydata(scene, result);
  detail::shift_to_origin(poly, scene);  // like every other dataset of a run (Scene::origin)
  detail::write_polydata(poly, vtp.temp, vtp.final_path);
  poly = detail::make_lights_polydata(scene);
  detail::shift_to_origin(poly, scene);
  detail::write_polydata(poly, lights.temp, lights.final_path);
  // The whole result in ParaView in one step, as `shadow compute`'s scene.vtm.
  detail::write_vtm({{"radiosity", "radiosity.vtp"}, {"lights", "lights.vtp"}}, vtm.temp, vtm.final_path);
  // report.json staged last, so placed last: its presence says the set is complete.
  detail::write_staged_stream(staging.stage("report.json"),
                              [&](std::ostream& out) { write_radiosity_report_json(out, scene, result, run); });
  return staging.commit();
}

}  // namespace shadow
