// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: checks shared by validate_scene and the engine (which also takes lights that were
// never part of a validated scene).
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

/// The cheap part of validation that the library cannot do without (scenes built in code may
/// skip validate_scene): every face vertex, plane point, normal and window finite and within
/// max_coordinate. Linear in the number of vertices.
/// @throws InputError naming the face's source (or `face N`) or the plane.
void check_scene_numbers(const Scene& scene);

/// InputError text when `v` is not finite or beyond max_coordinate, else empty.
std::string coordinate_problem(const glm::dvec3& v, const char* what);

}  // namespace shadow::detail
