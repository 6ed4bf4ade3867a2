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

/// The largest `angular_diameter` accepted on a directional light, in degrees. The sun's is
/// about 0.53; a sky patch of a few tens of degrees is still a sensible extended source.
constexpr double max_angular_diameter = 60.0;

/// Throws InputError {file, path + ".<key>"} if the light is unusable: non-finite or zero
/// direction, non-finite position, unknown type, bad intensity or colour; an angular_diameter
/// outside [0, max_angular_diameter]; an area light's polygon that check_area_polygon rejects;
/// a disk's non-finite or zero normal or a radius that is not > 0.
void check_light(const Light& light, const std::string& file, const std::string& path);

/// Throws InputError {file, path or path[i]} unless `polygon` is a usable area light: at least
/// 3 vertices, finite and within max_coordinate, no vertex repeating the one before it, non-zero
/// area, planar within 1e-6 of its size, and simple (no two edges meet but neighbours).
void check_area_polygon(const std::vector<glm::dvec3>& polygon, const std::string& file, const std::string& path);

/// The point (or direction) that stands for an extended light where one point is needed: an area
/// light's area centroid (doubles), a disk's centre, a sun disk's central direction, as a Point
/// or Directional light with the same intensity and colour. Point lights come back as they are.
/// FaceLighting::lit_area of an extended light is this light's (docs/area-lights.md).
Light centre_light(const Light& light);

/// The one place that turns ShadowOptions::lights into light ids (empty: every scene light),
/// sorted and without repeats, each checked with check_light. Used by the face engine and the
/// plane shadows alike, so both reject the same lights the same way.
/// @throws InputError for an index that is not a scene light, or an unusable light.
std::vector<std::size_t> resolve_lights(const Scene& scene, const std::vector<std::size_t>& requested);

}  // namespace shadow::detail
