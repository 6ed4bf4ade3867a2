// SPDX-License-Identifier: GPL-3.0-or-later
#include "support/scene_builders.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>
#include <random>

namespace shadow::test {

std::size_t add_mesh(Scene& scene, const std::string& name, const std::vector<Polygon3>& polygons,
                     bool receiver) {
  Mesh mesh;
  mesh.name = name;
  mesh.first_face = scene.faces.size();
  mesh.face_count = polygons.size();
  mesh.receiver = receiver;
  const std::size_t mesh_id = scene.meshes.size();
  scene.meshes.push_back(mesh);
  for (std::size_t p = 0; p < polygons.size(); ++p) {
    Face face;
    face.vertices = polygons[p];
    face.mesh = mesh_id;
    face.source = {"test", name + "[" + std::to_string(p) + "]"};
    scene.faces.push_back(face);
  }
  return mesh.first_face;
}

std::vector<Polygon3> box_faces(glm::dvec3 lo, glm::dvec3 hi) {
  const double x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
  return {
      {{x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}},  // top (+z)
      {{x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}},  // bottom (-z)
      {{x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}},  // south (-y)
      {{x1, y1, z0}, {x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}},  // north (+y)
      {{x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}},  // east (+x)
      {{x0, y1, z0}, {x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}},  // west (-x)
  };
}

Polygon3 rectangle_z(double x0, double y0, double x1, double y1, double z, bool up) {
  Polygon3 r{{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  if (!up) std::swap(r[1], r[3]);
  return r;
}

Light directional_light(const std::string& name, glm::dvec3 to_light) {
  Light l;
  l.name = name;
  l.type = LightType::Directional;
  l.to_light = to_light;
  return l;
}

Light point_light(const std::string& name, glm::dvec3 position) {
  Light l;
  l.name = name;
  l.type = LightType::Point;
  l.position = position;
  return l;
}

glm::dvec3 sun_direction(double elevation_deg, double azimuth_deg) {
  const double e = glm::radians(elevation_deg), a = glm::radians(azimuth_deg);
  return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

Scene make_city(std::size_t boxes, double extent, std::uint64_t seed) {
  Scene scene;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, extent), size(2.0, 10.0), height(3.0, 30.0);
  add_mesh(scene, "ground", {rectangle_z(-10, -10, extent + 10, extent + 10, 0)});
  std::vector<Polygon3> faces;
  for (std::size_t b = 0; b < boxes; ++b) {
    // Round to centimetres, as survey data would be.
    auto cm = [](double v) { return std::round(v * 100.0) / 100.0; };
    const double x = cm(pos(rng)), y = cm(pos(rng));
    const double w = cm(size(rng)), d = cm(size(rng)), h = cm(height(rng));
    for (const Polygon3& f : box_faces({x, y, 0}, {x + w, y + d, h})) faces.push_back(f);
  }
  add_mesh(scene, "buildings", faces);
  return scene;
}

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

}  // namespace shadow::test
