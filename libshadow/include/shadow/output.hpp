// SPDX-License-Identifier: GPL-3.0-or-later
/// @file output.hpp
/// @brief Writing results: VTK XML files for ParaView and report.json.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <vector>

namespace shadow {

/// A file could not be written (the message names the path and the system's reason).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes every output file into `outdir` (created if missing):
/// `fragments.vtp`, `faces.vtp`, `plane_shadows.vtp`, `lights.vtp`, `report.json` and
/// `scene.vtm` (ParaView multiblock of all of them). An existing `report.json` is removed
/// first; files are written under temporary names and renamed into place only when all of them
/// are complete, `report.json` last. So `report.json` is the sign of a complete set: an
/// interrupted run never leaves a directory that looks complete.
/// @returns the paths written, in the order they were put in place.
/// @throws OutputError
std::vector<std::filesystem::path> write_outputs(const std::filesystem::path& outdir,
                                                 const Scene& scene, const ShadowResult& result);

/// The report: libshadow_version, scene, lights[], faces[] (id, mesh, area, lights[] with
/// light, lit_area, shadow_area, lit_fraction, faces_light), planes[] (name, plane, light,
/// shadow_area, reaches_window, ...), summary, stats, warnings. `summary.arithmetic` is "exact"
/// or "fast"; for the fast path each face's light entries, and `summary.per_light`, also carry
/// `lit_area_error_bound`, and `stats` carries `fast_exact_fallbacks` and `fast_collapsed`.
void write_report_json(std::ostream& out, const Scene& scene, const ShadowResult& result);

}  // namespace shadow
