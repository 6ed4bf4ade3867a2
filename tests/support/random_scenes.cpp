// SPDX-License-Identifier: GPL-3.0-or-later
#include "support/scene_builders.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>
#include <random>

namespace shadow::test {

Scene random_scene(std::uint64_t seed) {
  Scene scene;
  std::mt19937_64 rng(seed);
  auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  auto integer = [&](int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); };
  // Box coordinates on a 1/64 grid: exact in binary, like many CAD exports.
  auto grid = [](double v) { return std::round(v * 64.0) / 64.0; };
  add_mesh(scene, "ground", {rectangle_z(-20, -20, 20, 20, 0)});
  std::vector<Polygon3> boxes;
  const int box_count = integer(1, 6);
  for (int b = 0; b < box_count; ++b) {
    const double x = grid(uniform(-10, 8)), y = grid(uniform(-10, 8));
    const double z = integer(0, 2) == 0 ? grid(uniform(0.5, 3)) : 0.0;
    const double w = grid(uniform(0.5, 4)), d = grid(uniform(0.5, 4)), h = grid(uniform(0.5, 6));
    for (const Polygon3& f : box_faces({x, y, z}, {x + w, y + d, z + h})) boxes.push_back(f);
  }
  add_mesh(scene, "boxes", boxes);
  std::vector<Polygon3> panels;
  const int panel_count = integer(1, 4);
  for (int p = 0; p < panel_count; ++p) {
    const int n = integer(3, 8);
    const bool star = n >= 5 && integer(0, 1) == 1;
    Polygon3 poly;
    for (int v = 0; v < n; ++v) {
      const double angle = 2.0 * M_PI * (v + uniform(-0.3, 0.3)) / n;
      const double radius = (star && v % 2 == 1) ? uniform(0.3, 0.8) : uniform(1.0, 3.0);
      poly.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0.0);
    }
    const glm::dvec3 axis(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    const double angle = uniform(0, M_PI);
    const glm::dmat3 rotation = glm::length(axis) > 1e-3
                                    ? glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis)))
                                    : glm::dmat3(1.0);
    const glm::dvec3 centre(uniform(-8, 8), uniform(-8, 8), uniform(1.5, 8));
    for (glm::dvec3& v : poly) v = rotation * v + centre;
    panels.push_back(poly);
  }
  add_mesh(scene, "panels", panels);
  if (integer(0, 1) == 0) {
    scene.lights.push_back(directional_light("sun", sun_direction(uniform(10, 80), uniform(0, 360))));
  } else {
    scene.lights.push_back(point_light("lamp", {uniform(-12, 12), uniform(-12, 12), uniform(0.5, 14)}));
  }
  return scene;
}

Scene transformed(const Scene& scene, double scale, glm::dvec3 axis, double angle_rad, glm::dvec3 t) {
  const glm::dmat3 rotation = glm::dmat3(glm::rotate(glm::dmat4(1.0), angle_rad, glm::normalize(axis)));
  Scene out = scene;
  for (Face& f : out.faces)
    for (glm::dvec3& v : f.vertices) v = scale * (rotation * v) + t;
  for (Light& l : out.lights) {
    l.to_light = rotation * l.to_light;
    l.position = scale * (rotation * l.position) + t;
  }
  for (Plane& p : out.planes) {
    p.point = scale * (rotation * p.point) + t;
    p.normal = rotation * p.normal;
  }
  return out;
}

std::vector<std::size_t> faces_of_mesh(const Scene& scene, std::size_t mesh) {
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < scene.faces.size(); ++f)
    if (scene.faces[f].mesh == mesh) faces.push_back(f);
  return faces;
}

std::vector<Polygon3> l_prism_triangles(glm::dvec3 at, double height, bool floor, bool roof) {
  const double x[6] = {0, 2, 2, 1, 1, 0}, y[6] = {0, 0, 1, 1, 2, 2};  // counter-clockwise from above
  auto p = [&](int i, double z) { return at + glm::dvec3(x[i] * 3, y[i] * 3, z); };
  std::vector<Polygon3> faces;
  for (int i = 0; i < 6; ++i) {
    const int j = (i + 1) % 6;
    faces.push_back({p(i, 0), p(j, 0), p(j, height)});
    faces.push_back({p(i, 0), p(j, height), p(i, height)});
  }
  const int fan[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};  // the L from its corner (0, 0)
  for (const auto& t : fan) {
    if (roof) faces.push_back({p(t[0], height), p(t[1], height), p(t[2], height)});
    if (floor) faces.push_back({p(t[0], 0), p(t[2], 0), p(t[1], 0)});
  }
  return faces;
}

}  // namespace shadow::test
