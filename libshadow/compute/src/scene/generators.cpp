// SPDX-License-Identifier: GPL-3.0-or-later
#include <shadow/generators.hpp>

#include <cmath>
#include <random>
#include <utility>

namespace shadow {

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
    face.source = {"", name + "[" + std::to_string(p) + "]"};
    scene.faces.push_back(std::move(face));
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

std::vector<Polygon3> room_faces(glm::dvec3 lo, glm::dvec3 hi) {
  std::vector<Polygon3> faces = box_faces(lo, hi);
  for (Polygon3& f : faces) std::swap(f[1], f[3]);  // reverse a quad: front turns inward
  return faces;
}

Polygon3 rectangle_z(double x0, double y0, double x1, double y1, double z, bool up) {
  Polygon3 r{{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  if (!up) std::swap(r[1], r[3]);
  return r;
}

Polygon3 comb_polygon(std::size_t teeth, double z) {
  Polygon3 p;
  p.reserve(4 * teeth + 3);
  for (std::size_t t = 0; t < teeth; ++t) {
    const double x = static_cast<double>(teeth - t);
    p.push_back({x, 1, z});
    p.push_back({x, 10, z});
    p.push_back({x - 0.5, 10, z});
    p.push_back({x - 0.5, 1, z});
  }
  p.push_back({0, 1, z});
  p.push_back({0, 0, z});
  p.push_back({static_cast<double>(teeth), 0, z});
  return p;
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
  constexpr double kDegree = 3.14159265358979323846 / 180.0;
  const double e = elevation_deg * kDegree, a = azimuth_deg * kDegree;
  return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

namespace {
double centimetres(double v) { return std::round(v * 100.0) / 100.0; }
}  // namespace

Scene make_city(std::size_t boxes, double extent, std::uint64_t seed) {
  Scene scene;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, extent), size(2.0, 10.0), height(3.0, 30.0);
  add_mesh(scene, "ground", {rectangle_z(-10, -10, extent + 10, extent + 10, 0)});
  std::vector<Polygon3> faces;
  faces.reserve(boxes * 6);
  for (std::size_t b = 0; b < boxes; ++b) {
    const double x = centimetres(pos(rng)), y = centimetres(pos(rng));
    const double w = centimetres(size(rng)), d = centimetres(size(rng)), h = centimetres(height(rng));
    for (Polygon3& f : box_faces({x, y, 0}, {x + w, y + d, h})) faces.push_back(std::move(f));
  }
  add_mesh(scene, "buildings", faces);
  return scene;
}

Scene make_sphere_field(std::size_t spheres, double extent, std::uint64_t seed) {
  Scene scene;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, extent), radius(1.0, 4.0);
  add_mesh(scene, "ground", {rectangle_z(-10, -10, extent + 10, extent + 10, 0)});
  constexpr int kLon = 12, kLat = 6;
  std::vector<Polygon3> faces;
  faces.reserve(spheres * 2 * kLon * (kLat - 1));
  for (std::size_t s = 0; s < spheres; ++s) {
    const double r = centimetres(radius(rng));
    const glm::dvec3 c(centimetres(pos(rng)), centimetres(pos(rng)), r);
    // Ring k at polar angle pi k / kLat (k = 0: north pole); the poles are single vertices.
    auto vertex = [&](int k, int j) {
      if (k == 0) return c + glm::dvec3(0, 0, r);
      if (k == kLat) return c - glm::dvec3(0, 0, r);
      const double theta = M_PI * k / kLat, phi = 2 * M_PI * j / kLon;
      return c + r * glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    };
    for (int k = 0; k < kLat; ++k) {
      for (int j = 0; j < kLon; ++j) {
        const glm::dvec3 a = vertex(k, j), b = vertex(k + 1, j), cc = vertex(k + 1, j + 1), d = vertex(k, j + 1);
        // Counter-clockwise seen from outside; triangles keep every face exactly planar.
        if (k > 0) faces.push_back({a, b, d});
        if (k < kLat - 1) faces.push_back({b, cc, d});
      }
    }
  }
  add_mesh(scene, "spheres", faces);
  return scene;
}

Scene make_furnished_room(std::size_t tables, std::uint64_t seed) {
  Scene scene;
  std::mt19937_64 rng(seed);
  auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  const double W = 8, D = 6, H = 3;
  add_mesh(scene, "room", room_faces({0, 0, 0}, {W, D, H}));
  std::vector<Polygon3> furniture;
  auto add_box = [&](glm::dvec3 lo, glm::dvec3 hi) {
    for (Polygon3& f : box_faces(lo, hi)) furniture.push_back(std::move(f));
  };
  for (std::size_t t = 0; t < tables; ++t) {
    const double w = centimetres(uniform(0.8, 1.6)), d = centimetres(uniform(0.6, 1.0));
    const double x = centimetres(uniform(0.2, W - w - 0.2)), y = centimetres(uniform(0.2, D - d - 0.2));
    const double h = centimetres(uniform(0.7, 0.8)), leg = 0.06, top = 0.04;
    add_box({x, y, h - top}, {x + w, y + d, h});
    add_box({x, y, 0}, {x + leg, y + leg, h - top});
    add_box({x + w - leg, y, 0}, {x + w, y + leg, h - top});
    add_box({x, y + d - leg, 0}, {x + leg, y + d, h - top});
    add_box({x + w - leg, y + d - leg, 0}, {x + w, y + d, h - top});
  }
  // Shelves along the north wall, one board above another.
  for (int s = 0; s < 4; ++s) add_box({1.0, D - 0.35, 0.4 + 0.45 * s}, {3.0, D - 0.02, 0.43 + 0.45 * s});
  add_mesh(scene, "furniture", furniture);
  scene.lights.push_back(point_light("ceiling_lamp", {W / 2 + 0.13, D / 2 - 0.21, H - 0.3}));
  return scene;
}

}  // namespace shadow
