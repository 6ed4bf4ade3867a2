// SPDX-License-Identifier: GPL-3.0-or-later
// The code under test: a deliberately simple shadow-ray estimate of a face's lit fraction, as a
// small ray tracer would compute it. Sample points on the face, start each shadow ray a little
// off the surface (the "bias", to keep the ray from hitting its own face), and test it against
// every face of the scene (fanned into triangles: convex faces only).
#pragma once

#include <shadow/scene.hpp>
#include <shadow/testing.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace simple {

/// Moeller-Trumbore: distance t along `dir` at which the ray from `o` meets triangle abc, or -1.
inline double hit_triangle(glm::dvec3 o, glm::dvec3 dir, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(dir, e2);
  const double det = glm::dot(e1, p);
  if (std::abs(det) < 1e-14) return -1;
  const glm::dvec3 s = o - a;
  const double u = glm::dot(s, p) / det;
  if (u < 0 || u > 1) return -1;
  const glm::dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(dir, q) / det;
  if (v < 0 || u + v > 1) return -1;
  return glm::dot(e2, q) / det;
}

/// Lit fraction of `face_id` under `light_id` from `samples` shadow rays started `bias` along
/// the face's normal. `bias` must be positive: the rays start in front of the surface.
inline double lit_fraction(const shadow::Scene& scene, std::size_t face_id, std::size_t light_id, int samples,
                           std::uint64_t seed, double bias) {
  const shadow::Face& face = scene.faces[face_id];
  const shadow::Light& light = scene.lights[light_id];
  const glm::dvec3 n = glm::normalize(glm::cross(face.vertices[1] - face.vertices[0], face.vertices[2] - face.vertices[0]));
  const auto points = shadow::testing::sample_face(scene, face_id, static_cast<std::size_t>(samples), seed);
  if (points.empty()) return std::numeric_limits<double>::quiet_NaN();
  int lit = 0;
  for (const glm::dvec3& p : points) {
    const glm::dvec3 origin = p + bias * n;
    const bool point_light = light.type == shadow::LightType::Point;
    const glm::dvec3 dir = point_light ? light.position - origin : glm::normalize(light.to_light);
    if (glm::dot(n, dir) <= 0) continue;  // the face looks away
    const double t_max = point_light ? 1.0 : std::numeric_limits<double>::infinity();
    bool blocked = false;
    for (const shadow::Face& other : scene.faces) {
      for (std::size_t v = 1; v + 1 < other.vertices.size() && !blocked; ++v) {
        const double t = hit_triangle(origin, dir, other.vertices[0], other.vertices[v], other.vertices[v + 1]);
        blocked = t > 0 && t < t_max;
      }
      if (blocked) break;
    }
    lit += !blocked;
  }
  return static_cast<double>(lit) / static_cast<double>(points.size());
}

}  // namespace simple
