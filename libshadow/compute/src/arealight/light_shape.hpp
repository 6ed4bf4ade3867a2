// SPDX-License-Identifier: GPL-3.0-or-later
// The shape of an extended light (Light::is_extended) as the exact area-light code uses it: one
// planar polygon, of points (an area light, a disk's circumscribed regular polygon) or of
// directions (a sun disk's circumscribed cone of directions, cut at unit distance). No CGAL.
#pragma once

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <vector>

namespace shadow::arealight {

/// Sides of the regular polygon circumscribed about a disk or a sun disk. Circumscribed, so that
/// the polygon holds the disk: what sees all of the polygon sees all of the disk (fully lit is
/// an inner bound) and what sees none of it sees none of the disk (umbra is an inner bound).
/// Its vertices lie r / cos(pi / 32) = 1.00484 r from the centre (docs/area-lights.md).
constexpr int kDiskSides = 32;

/// An extended light as one planar polygon.
struct LightShape {
  /// Points: counter-clockwise seen from the side the light shines to (its front). Directions:
  /// the orientation does not matter (the cone's own plane is the plane at infinity).
  std::vector<glm::dvec3> polygon;
  /// True: `polygon` holds points (area, disk); false: directions toward the light (sun disk),
  /// every one a point of the plane through `direction` at unit distance.
  bool finite = true;
};

/// The polygon of an extended light: an area light's own polygon; a disk's regular kDiskSides-gon
/// about its centre in its plane, circumscribed with a relative margin of 1e-9 (and a few ulps
/// of its position) so that rounding cannot cut into the disk; a sun disk's kDiskSides-gon of
/// directions about `to_light` (unit) at unit distance, circumscribed about the circle of radius
/// tan(angular_diameter / 2) with the same margin.
LightShape light_shape(const Light& light);

}  // namespace shadow::arealight
