// SPDX-License-Identifier: GPL-3.0-or-later
// Reads back what write_radiosity_outputs wrote (radiosity.vtp and report.json), for pictures of
// the result. It sits beside the writer, not in readers/: the array names are the writer's, and
// VTK's messages go through the writers' capture (writers/vtk_errors.hpp) instead of stderr.
#include <shadow/error.hpp>
#include <shadow/radiosity_output.hpp>

#include "writers/vtk_errors.hpp"

#include <nlohmann/json.hpp>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <fstream>
#include <string>
#include <system_error>

namespace shadow {
namespace {

namespace fs = std::filesystem;

/// report.json: its kind, its element count and its faces; an error when it is another result.
void read_report(RadiosityFiles& files, std::size_t& elements) {
  const std::string file = files.report.string();
  std::ifstream in(files.report, std::ios::binary);
  if (!in) throw InputError({file, ""}, "cannot open the report");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError({file, ""}, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object()) throw InputError({file, ""}, "not the report of `shadow radiosity` (not an object)");
  const nlohmann::json summary = j.value("summary", nlohmann::json::object());
  const bool counted = summary.is_object() && summary.contains("elements") && summary["elements"].is_number_unsigned();
  const std::string kind = j.contains("kind") && j["kind"].is_string() ? j["kind"].get<std::string>() : "";
  // Results written before report.json had a kind are told by their element count.
  if (kind != "radiosity" && !(kind.empty() && counted))
    throw InputError({file, "kind"}, "not the report of `shadow radiosity` (its kind is " +
                                         (kind.empty() ? std::string("missing") : "\"" + kind + "\"") +
                                         ", not \"radiosity\")");
  if (!counted) throw InputError({file, "summary.elements"}, "missing or not a count");
  elements = summary["elements"].get<std::size_t>();
  if (!j.contains("faces") || !j["faces"].is_array()) return;
  for (std::size_t i = 0; i < j["faces"].size(); ++i) {
    const nlohmann::json& f = j["faces"][i];
    if (!f.is_object() || !f.contains("id") || !f["id"].is_number_unsigned())
      throw InputError({file, "faces[" + std::to_string(i) + "].id"}, "missing or not a face id");
    RadiosityFiles::ReportFace face;
    face.id = f["id"].get<std::size_t>();
    if (f.contains("name") && f["name"].is_string()) face.name = f["name"].get<std::string>();
    if (f.contains("mesh") && f["mesh"].is_string()) face.mesh = f["mesh"].get<std::string>();
    files.report_faces.push_back(std::move(face));
  }
}

/// The cell array `name` of radiosity.vtp with `components` components, or an error.
vtkDataArray* cell_array(vtkPolyData* poly, const char* name, int components, const std::string& file) {
  vtkDataArray* a = poly->GetCellData()->GetArray(name);
  if (a == nullptr) throw InputError({file, std::string("cell array ") + name}, "missing: not a radiosity result");
  if (a->GetNumberOfComponents() != components || a->GetNumberOfTuples() != poly->GetNumberOfCells())
    throw InputError({file, std::string("cell array ") + name},
                     "has " + std::to_string(a->GetNumberOfTuples()) + " values of " +
                         std::to_string(a->GetNumberOfComponents()) + " components for " +
                         std::to_string(poly->GetNumberOfCells()) + " cells");
  return a;
}

double finite_value(vtkDataArray* a, vtkIdType cell, int component, const std::string& file) {
  const double v = a->GetComponent(cell, component);
  if (!std::isfinite(v))
    throw InputError({file, std::string("cell ") + std::to_string(cell) + " " + a->GetName()}, "not a finite number");
  return v;
}

vtkSmartPointer<vtkPolyData> read_vtp(const fs::path& path) {
  const std::string file = path.string();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError({file, ""}, "not found: give the OUTDIR of `shadow radiosity`, its radiosity.vtp or its report.json");
  vtkNew<vtkXMLPolyDataReader> reader;
  if (reader->CanReadFile(file.c_str()) == 0) throw InputError({file, ""}, "not a VTK XML polydata file");
  vtkNew<detail::VtkErrorCapture> errors;  // VTK's messages become one InputError line
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->AddObserver(vtkCommand::WarningEvent, errors);
  reader->SetReaderErrorObserver(errors);
  reader->SetParserErrorObserver(errors);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);  // "returned failure for request"
  reader->SetFileName(file.c_str());
  reader->Update();
  if (!errors->message().empty() || reader->GetOutput() == nullptr)
    throw InputError({file, ""}, "cannot read: " + (errors->message().empty() ? std::string("no data") : errors->reason()));
  vtkSmartPointer<vtkPolyData> poly = reader->GetOutput();
  return poly;
}

}  // namespace

RadiosityFiles read_radiosity_files(const fs::path& path) {
  RadiosityFiles files;
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw InputError({path.string(), ""}, "not found: give the OUTDIR of `shadow radiosity`, its radiosity.vtp or its report.json");
  const fs::path dir = fs::is_directory(path, ec) ? path : path.parent_path();
  if (!fs::is_directory(path, ec) && path.filename() != "radiosity.vtp" && path.filename() != "report.json")
    throw InputError({path.string(), ""}, "expected the OUTDIR of `shadow radiosity`, its radiosity.vtp or its report.json");
  files.vtp = dir / "radiosity.vtp";
  std::size_t counted = 0;
  bool has_report = false;
  if (fs::is_regular_file(dir / "report.json", ec)) {
    files.report = dir / "report.json";
    read_report(files, counted);
    has_report = true;
  }
  if (!fs::exists(files.vtp, ec))
    throw InputError({files.vtp.string(), ""}, has_report ? "missing beside report.json: the result is incomplete"
                                                          : "not found: give the OUTDIR of `shadow radiosity`");
  const std::string file = files.vtp.string();
  vtkSmartPointer<vtkPolyData> poly = read_vtp(files.vtp);
  const vtkIdType cells = poly->GetNumberOfCells();
  if (has_report && static_cast<std::size_t>(cells) != counted)
    throw InputError({file, ""}, std::to_string(cells) + " cells but report.json counts " + std::to_string(counted) +
                                     " elements: the files are of different runs");
  vtkDataArray* radiosity = cell_array(poly, "radiosity", 1, file);
  vtkDataArray* irradiance = cell_array(poly, "irradiance", 1, file);
  vtkDataArray* direct = cell_array(poly, "direct_irradiance", 1, file);
  vtkDataArray* reflectance = cell_array(poly, "reflectance", 1, file);
  vtkDataArray* emittance = cell_array(poly, "emittance", 1, file);
  vtkDataArray* face_id = cell_array(poly, "face_id", 1, file);
  vtkDataArray* rgb = poly->GetCellData()->GetArray("reflectance_rgb") != nullptr
                          ? cell_array(poly, "reflectance_rgb", 3, file)
                          : nullptr;
  // Colour solutions (radiosity.vtp from a colour-solving libshadow) carry each channel's
  // irradiance; older files have one, the same for every channel.
  vtkDataArray* irradiance_rgb = poly->GetCellData()->GetArray("irradiance_rgb") != nullptr
                                     ? cell_array(poly, "irradiance_rgb", 3, file)
                                     : nullptr;
  vtkDataArray* radiosity_rgb = poly->GetCellData()->GetArray("radiosity_rgb") != nullptr
                                    ? cell_array(poly, "radiosity_rgb", 3, file)
                                    : nullptr;
  // The writer shifted the points by the scene's origin (a city far from 0): add it back.
  glm::dvec3 origin(0.0);
  if (vtkDataArray* o = poly->GetFieldData()->GetArray("origin"); o != nullptr && o->GetNumberOfComponents() == 3 &&
                                                                 o->GetNumberOfTuples() == 1)
    origin = glm::dvec3(o->GetComponent(0, 0), o->GetComponent(0, 1), o->GetComponent(0, 2));
  vtkNew<vtkIdList> ids;
  files.elements.resize(static_cast<std::size_t>(cells));
  files.reflectance_rgb.resize(static_cast<std::size_t>(cells));
  for (vtkIdType c = 0; c < cells; ++c) {
    RadiosityElement& e = files.elements[static_cast<std::size_t>(c)];
    poly->GetCellPoints(c, ids);
    if (ids->GetNumberOfIds() < 3)
      throw InputError({file, "cell " + std::to_string(c)}, "has " + std::to_string(ids->GetNumberOfIds()) + " points, not a polygon");
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
      double p[3];
      poly->GetPoint(ids->GetId(k), p);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        throw InputError({file, "cell " + std::to_string(c)}, "a point is not finite");
      e.polygon.push_back(glm::dvec3(p[0], p[1], p[2]) + origin);
    }
    glm::dvec3 twice(0.0);
    for (std::size_t k = 1; k + 1 < e.polygon.size(); ++k)
      twice += glm::cross(e.polygon[k] - e.polygon[0], e.polygon[k + 1] - e.polygon[0]);
    e.area = 0.5 * glm::length(twice);
    const double face = finite_value(face_id, c, 0, file);
    if (face < 0.0) throw InputError({file, "cell " + std::to_string(c) + " face_id"}, "negative");
    e.face_id = static_cast<std::size_t>(face);
    e.radiosity = finite_value(radiosity, c, 0, file);
    e.irradiance = finite_value(irradiance, c, 0, file);
    e.direct_irradiance = finite_value(direct, c, 0, file);
    e.reflectance = finite_value(reflectance, c, 0, file);
    e.emittance = finite_value(emittance, c, 0, file);
    for (int k = 0; k < 3; ++k) {
      e.irradiance_rgb[k] = irradiance_rgb != nullptr ? finite_value(irradiance_rgb, c, k, file) : e.irradiance;
      e.radiosity_rgb[k] = radiosity_rgb != nullptr ? finite_value(radiosity_rgb, c, k, file) : e.radiosity;
    }
    glm::dvec3& colour = files.reflectance_rgb[static_cast<std::size_t>(c)];
    if (rgb != nullptr)
      for (int k = 0; k < 3; ++k) colour[k] = finite_value(rgb, c, k, file);
    else
      colour = glm::dvec3(e.reflectance);
  }
  return files;
}

void check_radiosity_files(const Scene& scene, const RadiosityFiles& files) {
  for (std::size_t i = 0; i < files.elements.size(); ++i)
    if (files.elements[i].face_id >= scene.faces.size())
      throw InputError({files.vtp.string(), "cell " + std::to_string(i) + " face_id"},
                       "face " + std::to_string(files.elements[i].face_id) + " is not in the scene (" +
                           std::to_string(scene.faces.size()) + " faces): the result was computed on another scene");
  for (std::size_t i = 0; i < files.report_faces.size(); ++i) {
    const RadiosityFiles::ReportFace& f = files.report_faces[i];
    const std::string place = "faces[" + std::to_string(i) + "]";
    if (f.id >= scene.faces.size())
      throw InputError({files.report.string(), place + ".id"},
                       "face " + std::to_string(f.id) + " is not in the scene (" + std::to_string(scene.faces.size()) +
                           " faces): the result was computed on another scene");
    const Face& face = scene.faces[f.id];
    const std::string mesh = face.mesh < scene.meshes.size() ? scene.meshes[face.mesh].name : std::string();
    if (f.mesh != mesh)
      throw InputError({files.report.string(), place + ".mesh"},
                       "face " + std::to_string(f.id) + " is of mesh \"" + f.mesh + "\" in the result but of mesh \"" +
                           mesh + "\" in the scene: the result was computed on another scene");
    if (f.name != face.name)
      throw InputError({files.report.string(), place + ".name"},
                       "face " + std::to_string(f.id) + " is named \"" + f.name + "\" in the result but \"" + face.name +
                           "\" in the scene: the result was computed on another scene");
  }
}

}  // namespace shadow
