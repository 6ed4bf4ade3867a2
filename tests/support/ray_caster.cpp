// SPDX-License-Identifier: GPL-3.0-or-later
#include "support/ray_caster.hpp"

#include "support/polygon_tools.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace shadow::test {

RayVerdict cast_shadow_ray(const Scene& scene, std::size_t face_id, const glm::dvec3& p,
                           const Light& light, double margin) {
  // Work relative to p: coordinates near 1e6 would otherwise lose the centimetres.
  const bool point = light.type == LightType::Point;
  const glm::dvec3 dir = point ? light.position - p : glm::normalize(light.to_light);
  const double t_max = point ? 1.0 : std::numeric_limits<double>::infinity();
  const double dir_len = glm::length(dir);

  const glm::dvec3 np = glm::normalize(newell_normal(scene.faces[face_id].vertices));
  const double facing = glm::dot(np, dir) / dir_len;
  if (facing < -1e-9) return RayVerdict::Shadowed;  // attached shadow
  if (facing <= 1e-9) return RayVerdict::Unsure;    // grazing

  bool unsure = false;
  for (std::size_t q = 0; q < scene.faces.size(); ++q) {
    if (q == face_id || scene.faces[q].degenerate) continue;
    Polygon3 poly = scene.faces[q].vertices;
    for (glm::dvec3& v : poly) v -= p;
    const glm::dvec3 n = glm::normalize(newell_normal(poly));
    const double height = glm::dot(n, poly[0]);  // distance of the plane from p (signed)
    const double denom = glm::dot(n, dir);
    if (std::abs(denom) <= 1e-12 * dir_len) {  // ray parallel to the occluder's plane
      if (std::abs(height) < margin) unsure = true;
      continue;
    }
    const double t = height / denom;
    if (t <= 0.0 || t >= t_max) {
      // Near the ends (p itself, or the point light) a hit cannot be decided in doubles.
      const double end_distance = t <= 0.0 ? std::abs(t) * dir_len : (t - t_max) * dir_len;
      if (end_distance < margin) {
        double d = 0;
        if (inside_polygon(poly, t * dir, &d) || d < margin) unsure = true;
      }
      continue;
    }
    const glm::dvec3 hit = t * dir;
    double d = 0;
    const bool inside = inside_polygon(poly, hit, &d);
    const bool near_end = t * dir_len < margin || (point && (t_max - t) * dir_len < margin);
    if (d < margin || (inside && near_end)) {
      unsure = true;
    } else if (inside) {
      return RayVerdict::Shadowed;
    }
  }
  return unsure ? RayVerdict::Unsure : RayVerdict::Lit;
}

}  // namespace shadow::test
