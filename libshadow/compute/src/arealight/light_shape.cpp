// SPDX-License-Identifier: GPL-3.0-or-later
// The polygon of an extended light (light_shape.hpp). Doubles only: the exact code lifts it onto
// an exact plane (exact::make_exact_face), a move of a few ulps that the margin covers.
#include "arealight/light_shape.hpp"

#include "geometry/unit_vector.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace shadow::arealight {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// The regular polygon about `centre` in the plane with unit normal `n`, counter-clockwise seen
/// from the side `n` points to, circumscribed about the circle of radius `radius` with margin.
std::vector<glm::dvec3> circumscribed(const glm::dvec3& centre, const glm::dvec3& n, double radius) {
  const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(n, helper));
  const glm::dvec3 v = glm::cross(n, u);  // u x v = n: counter-clockwise seen from n's side
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const double scale = std::max({std::abs(centre.x), std::abs(centre.y), std::abs(centre.z), radius});
  const double r = radius / std::cos(kPi / kDiskSides) * (1 + 1e-9) + 64 * eps * scale;
  std::vector<glm::dvec3> polygon;
  for (int i = 0; i < kDiskSides; ++i) {
    const double angle = 2 * kPi * i / kDiskSides;
    polygon.push_back(centre + r * (std::cos(angle) * u + std::sin(angle) * v));
  }
  return polygon;
}

}  // namespace

LightShape light_shape(const Light& light) {
  LightShape shape;
  if (light.type == LightType::Area) {
    shape.polygon = light.polygon;
  } else if (light.type == LightType::Disk) {
    shape.polygon = circumscribed(light.position, geometry::unit(light.normal), light.radius);
  } else {
    // Directions toward the sun: the cone of half-angle a about c cuts the plane c . x = 1 in the
    // circle of radius tan(a) about c. Counter-clockwise seen from the far side of that plane
    // (from the sun, looking back): the cone's "front" faces the scene, as a luminaire's does.
    const glm::dvec3 c = geometry::unit(light.to_light);
    const double half = light.angular_diameter * kPi / 360.0;
    shape.polygon = circumscribed(c, -c, std::tan(half));
    shape.finite = false;
  }
  return shape;
}

}  // namespace shadow::arealight
