// SPDX-License-Identifier: GPL-3.0-or-later
/// @file radiosity_output.hpp
/// @brief Writing a radiosity solution: radiosity.vtp and report.json (docs/radiosity.md).
#pragma once

#include <shadow/radiosity.hpp>
#include <shadow/scene.hpp>

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace shadow {

/// What report.json records of the run besides the solution.
struct RadiosityRunInfo {
  std::string scene;        ///< the scene file as given
  std::string started_utc;  ///< ISO 8601 (utc_now(), output.hpp); empty: null
  RadiosityOptions options;
  double seconds = 0.0;     ///< wall time of the solution
};

/// The report: libshadow_version, kind ("radiosity"), scene, run (started_utc, options), summary (elements, shots,
/// converged, unshot_fraction, error_estimate, balance in W), faces[] (id, mesh, name, area,
/// reflectance, emittance, elements and the area-weighted radiosity, irradiance and
/// direct_irradiance in W/m^2).
void write_radiosity_report_json(std::ostream& out, const Scene& scene, const RadiosityResult& result,
                                 const RadiosityRunInfo& run);

/// Writes `radiosity.vtp` (one cell per element; cell arrays radiosity, irradiance,
/// direct_irradiance, reflectance, emittance (W/m^2 or 1), face_id, element_id, and
/// reflectance_rgb: the material's RGB reflectance, 3 components) and then
/// `report.json` into `outdir` (which must exist; a caller holding it as an OutputDirectory
/// keeps others out), each under a temporary name renamed into place when complete.
/// @returns the paths written.
/// @throws OutputError
std::vector<std::filesystem::path> write_radiosity_outputs(const std::filesystem::path& outdir, const Scene& scene,
                                                           const RadiosityResult& result,
                                                           const RadiosityRunInfo& run);

/// A radiosity result read back from its files, for pictures (`shadow render --radiosity`).
struct RadiosityFiles {
  std::filesystem::path vtp;     ///< the radiosity.vtp read
  std::filesystem::path report;  ///< the report.json beside it; empty when there is none
  /// One per cell of radiosity.vtp, in its order: polygon (in the scene's coordinates: the
  /// file's `origin` added back), face_id, radiosity, irradiance, direct_irradiance,
  /// reflectance, emittance, radiosity_rgb and irradiance_rgb (the scalar value on every channel
  /// for a file without them); area computed from the polygon.
  std::vector<RadiosityElement> elements;
  /// Per element, the material's RGB reflectance (the file's `reflectance_rgb`; a result
  /// written before that array existed gives the scalar reflectance on every channel).
  std::vector<glm::dvec3> reflectance_rgb;
  /// report.json's faces (id, name, mesh), to check the result against a scene.
  struct ReportFace {
    std::size_t id = 0;
    std::string name;
    std::string mesh;
  };
  std::vector<ReportFace> report_faces;
};

/// Reads a `shadow radiosity` result: `path` is its OUTDIR, its radiosity.vtp or its
/// report.json. The report, when present, must be a radiosity report (kind "radiosity", or
/// no kind and summary.elements: results written before the kind) whose element count is the
/// file's. @throws InputError naming the file and the place (a missing file, not a radiosity
/// result, a missing or non-finite array value, a cell of fewer than 3 points)
RadiosityFiles read_radiosity_files(const std::filesystem::path& path);

/// Checks that `files` was computed on `scene`: every face_id is a scene face, and every face
/// the report lists has the scene face's name and mesh.
/// @throws InputError naming the file, the place and the two faces
void check_radiosity_files(const Scene& scene, const RadiosityFiles& files);

}  // namespace shadow
