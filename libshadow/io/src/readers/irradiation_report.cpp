// SPDX-License-Identifier: GPL-3.0-or-later
// Reads back what `shadow irradiance` wrote (report.json), for pictures of the result: each
// face's total irradiation, checked against the scene it is drawn on.
#include <shadow/irradiance_output.hpp>
#include <shadow/error.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace shadow {

namespace fs = std::filesystem;

IrradiationReport read_irradiation_report(const fs::path& path) {
  IrradiationReport report;
  std::error_code ec;
  report.file = fs::is_directory(path, ec) ? path / "report.json" : path;
  const std::string file = report.file.string();
  std::ifstream in(report.file, std::ios::binary);
  if (!in) throw InputError({file, ""}, "cannot open the irradiance report (give the OUTDIR of `shadow irradiance` or its report.json)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError({file, ""}, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("kind", std::string()) != "irradiance")
    throw InputError({file, "kind"}, "not the report of `shadow irradiance` (its kind is not \"irradiance\")");
  if (!j.contains("faces") || !j["faces"].is_array()) throw InputError({file, "faces"}, "missing or not an array");
  const nlohmann::json run = j.value("run", nlohmann::json::object());
  if (run.is_object()) {
    if (run.contains("scene") && run["scene"].is_string()) report.scene = run["scene"].get<std::string>();
    if (run.contains("sky") && run["sky"].is_string()) report.sky = run["sky"].get<std::string>();
    if (run.contains("period") && run["period"].is_object() && run["period"].contains("hours") &&
        run["period"]["hours"].is_number_unsigned())
      report.hours = run["period"]["hours"].get<std::size_t>();
  }
  for (std::size_t i = 0; i < j["faces"].size(); ++i) {
    const nlohmann::json& f = j["faces"][i];
    const std::string place = "faces[" + std::to_string(i) + "]";
    if (!f.is_object() || !f.contains("face") || !f["face"].is_number_unsigned())
      throw InputError({file, place + ".face"}, "missing or not a face id");
    const nlohmann::json* total = nullptr;
    if (f.contains("annual_irradiation_kwh_m2") && f["annual_irradiation_kwh_m2"].is_object() &&
        f["annual_irradiation_kwh_m2"].contains("total"))
      total = &f["annual_irradiation_kwh_m2"]["total"];
    if (total == nullptr || !total->is_number() || !std::isfinite(total->get<double>()))
      throw InputError({file, place + ".annual_irradiation_kwh_m2.total"}, "missing or not a finite number");
    FaceIrradiation face;
    face.face = f["face"].get<std::size_t>();
    if (f.contains("label") && f["label"].is_string()) face.label = f["label"].get<std::string>();
    face.total_kwh_m2 = total->get<double>();
    report.faces.push_back(std::move(face));
  }
  return report;
}

std::vector<double> face_irradiation(const Scene& scene, const IrradiationReport& report) {
  std::vector<double> values(scene.faces.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < report.faces.size(); ++i) {
    const FaceIrradiation& f = report.faces[i];
    const std::string place = "faces[" + std::to_string(i) + "]";
    if (f.face >= scene.faces.size())
      throw InputError({report.file.string(), place + ".face"},
                       "face " + std::to_string(f.face) + " is not in the scene (" + std::to_string(scene.faces.size()) +
                           " faces): the result was computed on another scene");
    if (!f.label.empty() && f.label != face_label(scene, f.face))
      throw InputError({report.file.string(), place + ".label"},
                       "\"" + f.label + "\" is face " + std::to_string(f.face) + " of the result but the scene's face " +
                           std::to_string(f.face) + " is \"" + face_label(scene, f.face) +
                           "\": the result was computed on another scene");
    values[f.face] = f.total_kwh_m2;
  }
  return values;
}

}  // namespace shadow
