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
#include <shadow/shadows.hpp>

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

/// The irradiance (W/m^2 for a radiance in W/(m^2 sr)) that the extended light `light` delivers
/// at each of `points` through the part of it that the point sees (docs/area-light-visibility.md):
/// - area and disk lights are Lambertian emitters of radiance L = Light::intensity:
///   E = L * integral over the visible part of cos(theta) cos(theta') / r^2 dA (= pi L times the
///   point-to-visible-part form factor), by Lambert's closed-form contour integral over each
///   visible polygon; exact up to rounding for an area light; a disk is replaced by its inscribed
///   regular 1,024-gon for this (relative error below 7e-6);
/// - the sun disk (directional with angular_diameter): E = intensity * visible fraction *
///   max(0, cos(incidence)), the incidence measured to the sun's centre.
/// theta is measured to the normal of the point's face; a point that sees none of the light gets 0.
/// @throws InputError as light_visibility.
std::vector<double> light_irradiance(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                                     unsigned threads = 0);

/// Sets Fragment::visibility of every fragment in `fragments` (all of them lit by `light`, an
/// extended light, and on faces of `scene`): the visible fraction of the light at each vertex of
/// its polygon (light_visibility), taken as the limit from inside the fragment: at a vertex
/// where a face touches the receiver (a wall's foot), the value of the fragment's side, not the
/// one of the contact point itself (docs/area-light-visibility.md). Sets Fragment::irradiance
/// in the same pass (light_irradiance, with the same limit). ShadowEngine::compute and
/// compute_shadows call it for the fragments of extended lights.
/// @throws InputError as light_visibility.
void fill_fragment_visibility(const Scene& scene, const Light& light, std::vector<Fragment>& fragments,
                              unsigned threads = 0);

}  // namespace shadow
