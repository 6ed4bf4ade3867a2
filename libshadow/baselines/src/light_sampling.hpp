// SPDX-License-Identifier: GPL-3.0-or-later
// Extended lights in the shifted frame and the maps from the unit square onto them, shared by the
// soft-shadow rays (soft_shadows.cpp) and the path tracer's next-event estimation
// (path_tracer.cpp), so that both sample a light in the same measure.
#pragma once

#include "sampling.hpp"

#include <shadow/scene.hpp>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace shadow::baselines_detail {

constexpr double kPi = 3.14159265358979323846;

/// An extended light in the shifted frame, checked.
struct ExtendedLight {
  LightType type = LightType::Area;
  bool sun = false;              ///< directional with angular_diameter > 0
  glm::dvec3 centre{0.0};        ///< area: centroid; disk: centre (shifted)
  glm::dvec3 normal{0.0};        ///< area, disk: unit normal of the front
  glm::dvec3 to_light{0.0};      ///< sun: unit direction to its centre
  glm::dvec3 e1{0.0}, e2{0.0};   ///< disk, sun: unit axes across the normal / direction
  double size = 0;               ///< area: sqrt(area); disk: diameter; sun: angular diameter (radians)
  double radius = 0;             ///< disk
  double area = 0;               ///< area, disk: the emitting area (the disk's as a circle)
  double cos_half = 1;           ///< sun: cos(angular_diameter / 2)
  std::vector<std::array<glm::dvec3, 3>> triangles;  ///< area light (shifted)
  std::vector<double> cumulative;  ///< area: cumulative area shares, ending at 1

  [[nodiscard]] ShiftedLight centre_light() const {
    ShiftedLight l;
    l.point = !sun;
    l.position = centre;
    l.to_light = to_light;
    return l;
  }
  /// A point that does not see the front of an area or disk light sees none of it.
  [[nodiscard]] bool behind(const glm::dvec3& p) const { return !sun && !(glm::dot(normal, p - centre) > 0); }

  /// Area or disk light: the point of the light that (u1, u2) in [0, 1)^2 maps to, uniformly by
  /// area (an area light: u1 picks the triangle by its share of the area; a disk: the concentric
  /// square-to-disk map, which keeps strata compact).
  [[nodiscard]] glm::dvec3 surface_point(double u1, double u2) const;
  /// Sun disk: the direction toward the disk that (u1, u2) maps to, uniformly by solid angle.
  [[nodiscard]] glm::dvec3 sun_direction(double u1, double u2) const;
};

/// An orthonormal pair across the unit vector n.
void basis(const glm::dvec3& n, glm::dvec3& e1, glm::dvec3& e2);

/// The extended light `light` in the frame shifted by `shift`, checked as the engine checks it.
/// @throws InputError for a light that is not extended or unusable.
ExtendedLight extended_light(const Scene& scene, const Light& light, const glm::dvec3& shift);

}  // namespace shadow::baselines_detail
