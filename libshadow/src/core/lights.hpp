// SPDX-License-Identifier: GPL-3.0-or-later
// The one place that resolves and checks lights: validation (scene/), the face engine (engine/)
// and the plane shadows (planes/) call it, so all three reject the same lights the same way, and
// the engine also checks lights that were never part of a validated scene. No CGAL.
#pragma once

#include <shadow/scene.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace shadow::detail {

/// Throws InputError {file, path + ".<key>"} if the light is unusable: non-finite or zero
/// direction, non-finite position, unknown type, bad intensity or colour.
void check_light(const Light& light, const std::string& file, const std::string& path);

/// The one place that turns ShadowOptions::lights into light ids (empty: every scene light),
/// sorted and without repeats, each checked with check_light. Used by the face engine and the
/// plane shadows alike, so both reject the same lights the same way.
/// @throws InputError for an index that is not a scene light, or an unusable light.
std::vector<std::size_t> resolve_lights(const Scene& scene, const std::vector<std::size_t>& requested);

}  // namespace shadow::detail
