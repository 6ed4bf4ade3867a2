// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: a face's unit normal, azimuth and tilt for report.json and faces.vtp
// (conventions of docs/scene-format.md, as EnergyPlus states them).
#pragma once

#include "geometry/newell_normal.hpp"

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cmath>
#include <limits>

namespace shadow::detail {

struct FaceOrientation {
  glm::dvec3 normal{0.0};  ///< unit normal of the front (zero for a face without area)
  double azimuth = std::numeric_limits<double>::quiet_NaN();  ///< degrees clockwise from north, [0, 360)
  double tilt = std::numeric_limits<double>::quiet_NaN();     ///< degrees from facing up: 0 up, 90 vertical, 180 down
};

/// The front's unit normal (Newell's, in long double relative to the first vertex, so a small
/// face far from the origin keeps its direction), its tilt (angle from +z) and its azimuth:
/// the direction of the normal's horizontal part, clockwise from true north, where the model's
/// +y points `north_axis_degrees` clockwise from true north (Scene::sun's north axis; 0: +y is
/// north, +x east). A horizontal face (no horizontal part) has azimuth 0.
inline FaceOrientation face_orientation(const Face& face, double north_axis_degrees) {
  FaceOrientation o;
  if (face.vertices.size() < 3) return o;
  using Real = long double;
  glm::vec<3, Real> n(0);
  const glm::vec<3, Real> origin(face.vertices[0]);
  for (std::size_t a = 0; a < face.vertices.size(); ++a)
    n += geometry::newell_term(glm::vec<3, Real>(face.vertices[a]) - origin,
                               glm::vec<3, Real>(face.vertices[(a + 1) % face.vertices.size()]) - origin);
  const Real length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  if (!(length > 0) || !std::isfinite(static_cast<double>(length))) return o;
  o.normal = glm::dvec3(static_cast<double>(n.x / length), static_cast<double>(n.y / length),
                        static_cast<double>(n.z / length));
  constexpr double degrees = 180.0 / 3.14159265358979323846;
  const double horizontal = std::hypot(o.normal.x, o.normal.y);
  o.tilt = std::atan2(horizontal, o.normal.z) * degrees;
  double azimuth = horizontal > 0 ? std::atan2(o.normal.x, o.normal.y) * degrees + north_axis_degrees : 0.0;
  azimuth = std::fmod(azimuth, 360.0);
  if (azimuth < 0) azimuth += 360.0;
  if (azimuth >= 360.0) azimuth = 0.0;
  o.azimuth = azimuth;
  return o;
}

/// The north axis azimuths are measured with: the scene's sun's, else 0.
inline double north_axis_of(const Scene& scene) { return scene.sun ? scene.sun->north_axis : 0.0; }

}  // namespace shadow::detail
