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

/// The report: libshadow_version, scene, run (started_utc, options), summary (elements, shots,
/// converged, unshot_fraction, error_estimate, balance in W), faces[] (id, mesh, name, area,
/// reflectance, emittance, elements and the area-weighted radiosity, irradiance and
/// direct_irradiance in W/m^2).
void write_radiosity_report_json(std::ostream& out, const Scene& scene, const RadiosityResult& result,
                                 const RadiosityRunInfo& run);

/// Writes `radiosity.vtp` (one cell per element; cell arrays radiosity, irradiance,
/// direct_irradiance, reflectance, emittance (W/m^2 or 1), face_id, element_id) and then
/// `report.json` into `outdir` (which must exist; a caller holding it as an OutputDirectory
/// keeps others out), each under a temporary name renamed into place when complete.
/// @returns the paths written.
/// @throws OutputError
std::vector<std::filesystem::path> write_radiosity_outputs(const std::filesystem::path& outdir, const Scene& scene,
                                                           const RadiosityResult& result,
                                                           const RadiosityRunInfo& run);

}  // namespace shadow
