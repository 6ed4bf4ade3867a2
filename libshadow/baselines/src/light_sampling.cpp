// SPDX-License-Identifier: GPL-3.0-or-later
#include "light_sampling.hpp"

#include "core/lights.hpp"
#include "geometry/newell_normal.hpp"
#include "geometry/unit_vector.hpp"

#include <shadow/error.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace shadow::baselines_detail {

void basis(const glm::dvec3& n, glm::dvec3& e1, glm::dvec3& e2) {
  const glm::dvec3 helper = std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  e1 = glm::normalize(glm::cross(helper, n));
  e2 = glm::cross(n, e1);
}

ExtendedLight extended_light(const Scene& scene, const Light& light, const glm::dvec3& shift) {
  const SourceLocation where{scene.source.string(), "light \"" + light.name + "\""};
  if (!light.is_extended()) throw InputError(where, "soft shadows need an extended light (area, disk, or a sun with angular_diameter)");
  // The one check of lights (core/lights.hpp): the engine and the reader reject the same ones.
  detail::check_light(light, scene.source.string(), where.place);
  ExtendedLight e;
  e.type = light.type;
  if (light.type == LightType::Area) {
    const glm::dvec3 n = geometry::newell_normal(light.polygon, light.polygon[0]);
    const double len = glm::length(n);
    if (!(len > 0) || !std::isfinite(len)) throw InputError(where, "an area light's polygon has no area");
    e.normal = n / len;
    const FaceFrame fr = face_frame(light.polygon, shift);
    if (!fr.ok) throw InputError(where, "an area light's polygon has no area");
    double total = 0;
    glm::dvec3 weighted(0.0);
    for (const auto& t : triangulate(fr.polygon)) {
      std::array<glm::dvec3, 3> tri;
      for (int c = 0; c < 3; ++c) tri[static_cast<std::size_t>(c)] = light.polygon[t[static_cast<std::size_t>(c)]] - shift;
      const double a = 0.5 * glm::length(glm::cross(tri[1] - tri[0], tri[2] - tri[0]));
      if (!(a > 0)) continue;
      e.triangles.push_back(tri);
      total += a;
      e.cumulative.push_back(total);
      weighted += a * (tri[0] + tri[1] + tri[2]) / 3.0;
    }
    if (!(total > 0)) throw InputError(where, "an area light's polygon has no area");
    for (double& c : e.cumulative) c /= total;
    e.cumulative.back() = 1.0;
    e.centre = weighted / total;
    e.size = std::sqrt(total);
    e.area = total;
  } else if (light.type == LightType::Disk) {
    e.normal = geometry::unit(light.normal);
    basis(e.normal, e.e1, e.e2);
    e.centre = light.position - shift;
    e.radius = light.radius;
    e.size = 2 * light.radius;
    e.area = kPi * light.radius * light.radius;
  } else {
    e.sun = true;
    e.to_light = geometry::unit(light.to_light);  // scaled first: tiny or huge vectors too
    basis(e.to_light, e.e1, e.e2);
    e.size = light.angular_diameter * kPi / 180.0;
    e.cos_half = std::cos(0.5 * e.size);
  }
  return e;
}

glm::dvec3 ExtendedLight::surface_point(double u1, double u2) const {
  if (type == LightType::Area) {
    const auto t = static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), u1) - cumulative.begin());
    const std::size_t k = std::min(t, triangles.size() - 1);
    const double lo = k == 0 ? 0.0 : cumulative[k - 1];
    const double w = std::clamp((u1 - lo) / (cumulative[k] - lo), 0.0, 1.0);
    const double s = std::sqrt(w);
    const auto& tr = triangles[k];
    return tr[0] + s * (tr[1] - tr[0]) + s * u2 * (tr[2] - tr[1]);
  }
  // Concentric map of the square onto the disk (equal areas, strata stay compact).
  const double x = 2 * u1 - 1, y = 2 * u2 - 1;
  double r = 0, phi = 0;
  if (x != 0 || y != 0) {
    if (std::abs(x) > std::abs(y)) {
      r = x;
      phi = 0.25 * kPi * (y / x);
    } else {
      r = y;
      phi = 0.5 * kPi - 0.25 * kPi * (x / y);
    }
  }
  return centre + radius * r * (std::cos(phi) * e1 + std::sin(phi) * e2);
}

glm::dvec3 ExtendedLight::sun_direction(double u1, double u2) const {
  const double z = 1.0 - u1 * (1.0 - cos_half);
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * kPi * u2;
  return z * to_light + s * (std::cos(phi) * e1 + std::sin(phi) * e2);
}

}  // namespace shadow::baselines_detail
