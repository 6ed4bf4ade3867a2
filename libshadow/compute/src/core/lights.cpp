// SPDX-License-Identifier: GPL-3.0-or-later
// The one place that resolves and checks lights (validation, the face engine, the plane shadows).
#include "core/lights.hpp"

#include "core/input_checks.hpp"

#include "geometry/newell_normal.hpp"

#include <shadow/error.hpp>
#include <shadow/validation.hpp>

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace shadow {

using detail::coordinate_problem;
using detail::finite;
using detail::format_number;

namespace {

/// Twice the signed area of the 2D polygon (u, v) (shoelace, relative to the first vertex).
double twice_area_2d(const std::vector<std::array<double, 2>>& q) {
  double a = 0;
  for (std::size_t i = 1; i + 1 < q.size(); ++i)
    a += (q[i][0] - q[0][0]) * (q[i + 1][1] - q[0][1]) - (q[i + 1][0] - q[0][0]) * (q[i][1] - q[0][1]);
  return a;
}

double cross_2d(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Segments [a, b] and [c, d] touch or cross (doubles; collinear overlaps count).
bool segments_meet(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c,
                   const std::array<double, 2>& d) {
  const double d1 = cross_2d(a, b, c), d2 = cross_2d(a, b, d), d3 = cross_2d(c, d, a), d4 = cross_2d(c, d, b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  auto on = [](const std::array<double, 2>& p, const std::array<double, 2>& q, const std::array<double, 2>& r,
               double side) {  // r on segment pq, given side = cross(p, q, r)
    return side == 0 && std::min(p[0], q[0]) <= r[0] && r[0] <= std::max(p[0], q[0]) &&
           std::min(p[1], q[1]) <= r[1] && r[1] <= std::max(p[1], q[1]);
  };
  return on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4);
}

}  // namespace

void detail::check_area_polygon(const std::vector<glm::dvec3>& polygon, const std::string& file,
                                const std::string& path) {
  const std::size_t n = polygon.size();
  if (n < 3)
    throw InputError({file, path}, "an area light's polygon needs at least 3 vertices, got " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i) {
    const std::string problem = coordinate_problem(polygon[i], "coordinate");
    if (!problem.empty()) throw InputError({file, path + "[" + std::to_string(i) + "]"}, "vertex has a " + problem);
  }
  for (std::size_t i = 0; i < n; ++i)
    if (polygon[i] == polygon[(i + 1) % n])
      throw InputError({file, path + "[" + std::to_string((i + 1) % n) + "]"},
                       "vertex repeats the one before it");
  // Newell's normal relative to the first vertex; the plane through the centroid.
  glm::dvec3 normal(0.0), centroid(0.0), lo = polygon[0], hi = polygon[0];
  for (std::size_t i = 0; i < n; ++i) {
    normal += geometry::newell_term(polygon[i] - polygon[0], polygon[(i + 1) % n] - polygon[0]);
    centroid += polygon[i] - polygon[0];
    lo = glm::min(lo, polygon[i]);
    hi = glm::max(hi, polygon[i]);
  }
  centroid /= static_cast<double>(n);
  const glm::dvec3 extent = hi - lo;
  const double diameter = std::max({extent.x, extent.y, extent.z});
  const double length = std::sqrt(normal.x * normal.x + normal.y * normal.y + normal.z * normal.z);
  if (!(length > 1e-12 * diameter * diameter))
    throw InputError({file, path}, "the polygon has zero area (its vertices are collinear or coincide)");
  const glm::dvec3 unit = normal / length;
  double worst = 0;
  std::size_t worst_vertex = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 d = polygon[i] - polygon[0] - centroid;
    const double distance = std::fabs(unit.x * d.x + unit.y * d.y + unit.z * d.z);
    if (distance > worst) worst = distance, worst_vertex = i;
  }
  if (worst > 1e-6 * diameter)
    throw InputError({file, path + "[" + std::to_string(worst_vertex) + "]"},
                     "the polygon is not planar: this vertex is " + format_number(worst) +
                         " from the plane of the others (allowed: 1e-6 x its size, " +
                         format_number(1e-6 * diameter) + ")");
  // Simple: no two edges meet except neighbours at their shared vertex, in the chart that drops
  // the normal's dominant axis.
  int k = 2;
  if (std::fabs(unit.x) >= std::fabs(unit.y) && std::fabs(unit.x) >= std::fabs(unit.z)) k = 0;
  else if (std::fabs(unit.y) >= std::fabs(unit.z)) k = 1;
  std::vector<std::array<double, 2>> q(n);
  for (std::size_t i = 0; i < n; ++i) q[i] = {polygon[i][(k + 1) % 3], polygon[i][(k + 2) % 3]};
  if (twice_area_2d(q) == 0)
    throw InputError({file, path}, "the polygon has zero area (its vertices are collinear or coincide)");
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      const bool neighbours = b == a + 1 || (a == 0 && b == n - 1);
      if (neighbours) {
        // Neighbours share one vertex; they must not fold back onto each other.
        const std::size_t shared = b == a + 1 ? b : a, p = b == a + 1 ? a : b, r = b == a + 1 ? (b + 1) % n : 1;
        const auto& A = q[p];
        const auto& S = q[shared];
        const auto& C = q[r];
        if (n > 3 && cross_2d(A, S, C) == 0 && (C[0] - S[0]) * (A[0] - S[0]) + (C[1] - S[1]) * (A[1] - S[1]) > 0)
          throw InputError({file, path + "[" + std::to_string(shared) + "]"},
                           "the polygon is not simple: its edges fold back at this vertex");
        continue;
      }
      if (segments_meet(q[a], q[(a + 1) % n], q[b], q[(b + 1) % n]))
        throw InputError({file, path},
                         "the polygon is not simple: edge " + std::to_string(a) + "-" + std::to_string((a + 1) % n) +
                             " meets edge " + std::to_string(b) + "-" + std::to_string((b + 1) % n));
    }
}

Light detail::centre_light(const Light& light) {
  if (light.type == LightType::Directional || light.type == LightType::Point) {
    Light centre = light;
    centre.angular_diameter = 0.0;
    return centre;
  }
  Light centre;
  centre.name = light.name;
  centre.type = LightType::Point;
  centre.intensity = light.intensity;
  centre.color = light.color;
  if (light.type == LightType::Disk) {
    centre.position = light.position;
  } else {
    // The area centroid (relative to the first vertex: small sums), in doubles.
    const std::vector<glm::dvec3>& p = light.polygon;
    glm::dvec3 normal(0.0), weighted(0.0);
    for (std::size_t i = 1; i + 1 < p.size(); ++i) {
      const glm::dvec3 a = p[i] - p[0], b = p[i + 1] - p[0];
      normal += glm::dvec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    }
    double total = 0;
    for (std::size_t i = 1; i + 1 < p.size(); ++i) {
      const glm::dvec3 a = p[i] - p[0], b = p[i + 1] - p[0];
      const glm::dvec3 c(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
      const double w = c.x * normal.x + c.y * normal.y + c.z * normal.z;  // signed, x |normal|
      weighted += w * (a + b) / 3.0;
      total += w;
    }
    centre.position = p[0] + (total != 0 ? weighted / total : glm::dvec3(0.0));
  }
  return centre;
}

Light centre_light(const Light& light) { return detail::centre_light(light); }

void detail::check_light(const Light& light, const std::string& file, const std::string& path) {
  if (light.type == LightType::Directional) {
    if (!finite(light.to_light)) throw InputError({file, path + ".to_light"}, "direction is not finite");
    if (light.to_light == glm::dvec3(0.0)) throw InputError({file, path + ".to_light"}, "direction has zero length");
    // A direction's length does not matter (it is normalised safely for culling, exactly
    // elsewhere): any finite non-zero vector is accepted (tests/compute/test_hard_cases.cpp).
    if (!std::isfinite(light.angular_diameter) || light.angular_diameter < 0 ||
        light.angular_diameter > max_angular_diameter)
      throw InputError({file, path + ".angular_diameter"},
                       "angular_diameter must be a number of degrees in [0, " + format_number(max_angular_diameter) +
                           "] (0: a point at infinity), got " + format_number(light.angular_diameter));
  } else if (light.type == LightType::Point) {
    if (!finite(light.position)) throw InputError({file, path + ".position"}, "position is not finite");
    const std::string problem = coordinate_problem(light.position, "coordinate");
    if (!problem.empty()) throw InputError({file, path + ".position"}, "position has a " + problem);
  } else if (light.type == LightType::Area) {
    check_area_polygon(light.polygon, file, path + ".polygon");
  } else if (light.type == LightType::Disk) {
    if (!finite(light.position)) throw InputError({file, path + ".position"}, "position is not finite");
    const std::string problem = coordinate_problem(light.position, "coordinate");
    if (!problem.empty()) throw InputError({file, path + ".position"}, "position has a " + problem);
    if (!finite(light.normal)) throw InputError({file, path + ".normal"}, "normal is not finite");
    if (light.normal == glm::dvec3(0.0)) throw InputError({file, path + ".normal"}, "normal has zero length");
    if (!std::isfinite(light.radius) || !(light.radius > 0) || light.radius > max_coordinate)
      throw InputError({file, path + ".radius"},
                       "radius must be a finite number > 0, got " + format_number(light.radius));
  } else {
    throw InputError({file, path + ".type"}, "unknown light type");
  }
  if (!std::isfinite(light.intensity) || light.intensity < 0)
    throw InputError({file, path + ".intensity"},
                     "intensity must be finite and >= 0, got " + format_number(light.intensity));
  for (int c = 0; c < 3; ++c)
    if (!(light.color[c] >= 0.0 && light.color[c] <= 1.0))  // also catches NaN
      throw InputError({file, path + ".color"},
                       "color components must be in [0, 1], got " + format_number(light.color[c]));
}

std::vector<std::size_t> detail::resolve_lights(const Scene& scene, const std::vector<std::size_t>& requested) {
  std::vector<std::size_t> ids = requested;
  if (ids.empty())
    for (std::size_t l = 0; l < scene.lights.size(); ++l) ids.push_back(l);
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (ids[i] >= scene.lights.size())
      throw InputError({"", "ShadowOptions::lights[" + std::to_string(i) + "]"},
                       "no light " + std::to_string(ids[i]) + ": the scene has " +
                           std::to_string(scene.lights.size()) + (scene.lights.size() == 1 ? " light" : " lights"));
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  for (std::size_t l : ids) check_light(scene.lights[l], scene.source.string(), "lights[" + std::to_string(l) + "]");
  return ids;
}

}  // namespace shadow
