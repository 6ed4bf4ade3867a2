// SPDX-License-Identifier: GPL-3.0-or-later
#include <shadow/blinn.hpp>

#include <glm/geometric.hpp>

namespace shadow {

glm::dvec4 plane_equation(const Plane& plane) {
  return {plane.normal, -glm::dot(plane.normal, plane.point)};
}

glm::dvec4 homogeneous_light(const Light& light) {
  return light.type == LightType::Point ? glm::dvec4(light.position, 1.0) : glm::dvec4(light.to_light, 0.0);
}

glm::dmat4 shadow_matrix(const glm::dvec4& p, const glm::dvec4& l) {
  const double pl = glm::dot(p, l);
  glm::dmat4 m(0.0);
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row) m[column][row] = (row == column ? pl : 0.0) - l[row] * p[column];
  return m;
}

glm::dmat4 shadow_matrix(const Plane& plane, const Light& light) {
  return shadow_matrix(plane_equation(plane), homogeneous_light(light));
}

glm::dvec3 project_with(const glm::dmat4& matrix, const glm::dvec3& point, double* w) {
  const glm::dvec4 h = matrix * glm::dvec4(point, 1.0);
  if (w) *w = h.w;
  return glm::dvec3(h) / h.w;
}

}  // namespace shadow
