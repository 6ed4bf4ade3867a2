// SPDX-License-Identifier: GPL-3.0-or-later
/// @file irradiance_output.hpp
/// @brief The files of `shadow irradiance` (docs/irradiance.md): report.json, irradiation.csv,
/// irradiance_hourly.csv, faces.vtp and energyplus-diffuse-shading.csv.
#pragma once

#include <shadow/irradiance.hpp>
#include <shadow/scene.hpp>
#include <shadow/weather.hpp>

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace shadow {

/// What report.json says about the run.
struct IrradianceRunInfo {
  std::string scene;    ///< the scene file as given
  std::string weather;  ///< the weather file as given
  std::string from, to; ///< the period as given (empty: the whole file)
  unsigned threads = 0;
  double seconds_total = 0.0;  ///< loading to writing
  std::string started_utc;
};

/// Which files to write besides report.json, irradiation.csv and faces.vtp.
struct IrradianceFiles {
  bool hourly = false;      ///< irradiance_hourly.csv
  bool energyplus = false;  ///< energyplus-diffuse-shading.csv
  /// irradiation_map.vtp when set: irradiation_map()'s cells with cell arrays
  /// `irradiation_direct_kwh_m2` (the cell's own), `irradiation_sky_diffuse_kwh_m2`,
  /// `irradiation_ground_reflected_kwh_m2` (its face's), `irradiation_total_kwh_m2` (their sum,
  /// active), `face_id`, `region_id`, `area`.
  const SunHoursMap* map = nullptr;
};

/// Results per named surface, object or mesh: area-weighted means of the faces' (kWh/m2).
struct IrradianceGroup {
  std::string name;
  std::string type;                 ///< objects: their type; surfaces and meshes: empty
  std::vector<std::size_t> rows;    ///< rows of the result
  double area = 0.0;
  double sky_view_factor = 0.0;
  double ground_view_factor = 0.0;  ///< area-weighted, as sky_view_factor
  double direct = 0.0, sky_diffuse = 0.0, ground_reflected = 0.0, total = 0.0;
  /// What the scene's faces reflect onto the group (kWh/m2; NaN unless --reflections ran).
  double scene_reflected = std::numeric_limits<double>::quiet_NaN();
  double sky_diffuse_unshaded = 0.0;
  std::vector<double> monthly_total;  ///< 12 months
};

/// The result per named surface (named_surfaces()), per object (scene_objects()) or per mesh.
enum class IrradianceGrouping { Surface, Object, Mesh };
std::vector<IrradianceGroup> irradiance_groups(const Scene& scene, const IrradianceResult& result,
                                               IrradianceGrouping grouping);

/// Writes the files into `outdir` (created if missing): each under a temporary name first,
/// moved into place when all are complete, report.json last (an older report.json is removed
/// before anything is written). Returns the files written.
/// @throws OutputError
std::vector<std::filesystem::path> write_irradiance_outputs(const std::filesystem::path& outdir, const Scene& scene,
                                                            const Weather& weather, const IrradianceResult& result,
                                                            const IrradianceRunInfo& run, const IrradianceFiles& files);

/// One face's total irradiation read back from a `shadow irradiance` result.
struct FaceIrradiation {
  std::size_t face = 0;      ///< face_id in the scene the result was computed on
  std::string label;         ///< face_label() of that face, as the report wrote it
  double total_kwh_m2 = 0.0;  ///< annual_irradiation_kwh_m2.total: over the run's period
};

/// What read_irradiation_report takes from report.json (the parts a picture needs).
struct IrradiationReport {
  std::filesystem::path file;  ///< the report.json read
  std::string scene;           ///< run.scene: the scene file the run read
  std::string sky;             ///< run.sky
  std::size_t hours = 0;       ///< run.period.hours
  std::vector<FaceIrradiation> faces;
};

/// Reads the report.json of a `shadow irradiance` result: `path` is the OUTDIR or the report
/// itself. @throws InputError naming the file, the place and the problem (not found, not JSON,
/// not an irradiance report, a face without a finite total).
IrradiationReport read_irradiation_report(const std::filesystem::path& path);

/// Each scene face's total irradiation (kWh/m2) from `report`, NaN for faces it does not list.
/// @throws InputError when the report does not fit `scene` (a face id out of range, or a label
/// that is not the scene face's: the result was computed on another scene).
std::vector<double> face_irradiation(const Scene& scene, const IrradiationReport& report);

}  // namespace shadow
