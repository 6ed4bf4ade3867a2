// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the names the output files give lights and their arrays. VTK-free, so that
// report.json and the VTK datasets agree on them without report_json.cpp seeing VTK.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace shadow::detail {

/// `name` reduced to [A-Za-z0-9_] (anything else becomes '_'), so it can be part of an array name.
std::string sanitize_array_name(const std::string& name);

/// The names used for per-light arrays (`lit_fraction_<name>`): sanitized, never empty, and
/// unique among `light_ids` (a clash gets the light id appended).
std::vector<std::string> light_array_names(const Scene& scene,
                                           const std::vector<std::size_t>& light_ids);

/// The light ids that have at least one FaceLighting entry, ascending.
std::vector<std::size_t> lights_with_results(const ShadowResult& result);

/// The name of light `light_id`, or "light<id>" for a light that is not in the scene
/// (ShadowEngine::compute can be given any light).
std::string light_display_name(const Scene& scene, std::size_t light_id);

}  // namespace shadow::detail
