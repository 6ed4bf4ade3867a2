// SPDX-License-Identifier: GPL-3.0-or-later
/// @file area_lights.hpp
/// @brief How much of an extended light (an area light, a disk, the sun's disk) a point sees.
///
/// A point on a receiver sees part of an extended light: the light's surface minus what the
/// scene's faces hide of it, seen from the point. That is itself a shadow problem, with the light
/// as the receiver and the point as a point light, and libshadow solves it with the same exact
/// machinery. The regions on faces (fully lit, penumbra, umbra) come with compute_shadows and
/// ShadowEngine::compute when a light is extended (FaceLighting::fully_lit_area, ...).
/// See docs/area-lights.md.
#pragma once

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace shadow {

/// A point on a receiving face: the face is known so that it does not hide the light from its
/// own points.
struct SurfacePoint {
  std::size_t face_id = 0;
  glm::dvec3 position{0.0};
};

/// The visible fraction (0..1) of the extended light `light` from each of `points`: the area
/// (for a directional light with angular_diameter, the solid angle) of the part of the light that
/// no face hides, over the whole light's, exact and rounded once where the light is a polygon
/// (docs/area-lights.md states the disks' error). A point behind the light's front, or whose face
/// looks away from all of the light, sees 0 of it.
/// @throws InputError for a light that is not extended or is unusable, or a face_id out of range.
std::vector<double> light_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                                     unsigned threads = 0);

}  // namespace shadow
