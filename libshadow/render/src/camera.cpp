// SPDX-License-Identifier: GPL-3.0-or-later
#include <shadow/render/camera.hpp>

#include "geometry/newell_normal.hpp"  // libshadow/compute/src/geometry: header-only, glm only

#include <shadow/error.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace shadow::render {
namespace {

/// The words of a name, lower case, split at anything that is not a letter or a digit.
std::vector<std::string> words_of(const std::string& name) {
  std::vector<std::string> words(1);
  for (char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) != 0) words.back().push_back(static_cast<char>(std::tolower(u)));
    else if (!words.back().empty()) words.emplace_back();
  }
  if (words.back().empty()) words.pop_back();
  return words;
}

/// True when a word of `name` starts with one of `keys` ("walls" is named like "wall").
bool named_like(const std::string& name, std::initializer_list<const char*> keys) {
  for (const std::string& word : words_of(name))
    for (const char* key : keys)
      if (word.rfind(key, 0) == 0) return true;
  return false;
}

bool named_like_ground(const std::string& name) {
  return named_like(name, {"ground", "floor", "terrain", "site", "lawn"});
}

bool named_like_building(const std::string& name) {
  return named_like(name, {"building", "bldg", "house", "wall", "roof", "facade", "tower", "office", "home",
                           "shed", "garage"});
}

struct Box {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  void add(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  [[nodiscard]] bool empty() const { return !(lo.x <= hi.x); }
  [[nodiscard]] double plan_area() const { return empty() ? 0.0 : (hi.x - lo.x) * (hi.y - lo.y); }
};

/// The part of segment a-b (in plan) inside the box's plan [lo, hi] (Liang–Barsky); false when
/// it misses the box.
bool clip_to_plan(glm::dvec2& a, glm::dvec2& b, const Box& box) {
  double t0 = 0.0, t1 = 1.0;
  const glm::dvec2 d = b - a;
  const double p[4] = {-d.x, d.x, -d.y, d.y};
  const double q[4] = {a.x - box.lo.x, box.hi.x - a.x, a.y - box.lo.y, box.hi.y - a.y};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
  }
  if (t0 > t1) return false;
  const glm::dvec2 start = a;
  a = start + t0 * d;
  b = start + t1 * d;
  return true;
}

}  // namespace

std::optional<std::size_t> ground_mesh(const Scene& scene) {
  // A city model's terrain is its ground (the largest, if it has several).
  std::optional<std::size_t> terrain;
  std::vector<double> plan(scene.meshes.size(), 0.0);
  for (const Face& face : scene.faces)
    if (face.mesh < plan.size()) plan[face.mesh] += 0.5 * std::abs(geometry::newell_normal(face.vertices).z);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    if (scene.meshes[m].object_type == "TINRelief" && scene.meshes[m].face_count > 0 &&
        (!terrain || plan[m] > plan[*terrain]))
      terrain = m;
  if (terrain) return terrain;
  // By name, for meshes whose model says nothing of what they are: an EnergyPlus
  // Shading:Site group or a CityJSON object named "...site..." is not the ground.
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    if (named_like_ground(scene.meshes[m].name) && scene.meshes[m].face_count > 0 &&
        scene.meshes[m].object_type.empty() && scene.meshes[m].first_face < scene.faces.size() &&
        scene.faces[scene.meshes[m].first_face].kind.empty())
      return m;

  // By shape: faces all facing up, nothing below it, larger in plan than everything else.
  std::vector<Box> boxes(scene.meshes.size());
  std::vector<char> upward(scene.meshes.size(), 1);
  std::vector<double> area(scene.meshes.size(), 0.0);
  for (const Face& face : scene.faces) {
    if (face.mesh >= boxes.size()) continue;
    for (const glm::dvec3& v : face.vertices) boxes[face.mesh].add(v);
    const glm::dvec3 n = geometry::newell_normal(face.vertices);
    const double length = glm::length(n);
    area[face.mesh] += 0.5 * length;
    if (!(length > 0.0) || n.z < 0.9 * length) upward[face.mesh] = 0;
  }
  std::optional<std::size_t> best;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (!upward[m] || boxes[m].empty()) continue;
    Box rest;
    for (std::size_t o = 0; o < scene.meshes.size(); ++o)
      if (o != m && !boxes[o].empty()) {
        rest.add(boxes[o].lo);
        rest.add(boxes[o].hi);
      }
    if (rest.empty()) continue;  // a lone mesh is the model, not a ground under one
    const double tolerance = 1e-9 * std::max(1.0, glm::length(rest.hi - rest.lo));
    if (boxes[m].hi.z > rest.lo.z + tolerance) continue;
    if (boxes[m].plan_area() < rest.plan_area()) continue;
    if (!best || area[m] > area[*best]) best = m;
  }
  return best;
}

std::vector<MeshRole> mesh_roles(const Scene& scene) {
  std::vector<MeshRole> roles(scene.meshes.size(), MeshRole::Other);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    if (named_like_building(scene.meshes[m].name)) roles[m] = MeshRole::Building;
  if (const auto ground = ground_mesh(scene)) roles[*ground] = MeshRole::Ground;
  return roles;
}

std::vector<char> stray_meshes(const Scene& scene, std::optional<std::size_t> ground) {
  std::vector<char> stray(scene.meshes.size(), 0);
  std::vector<Box> boxes(scene.meshes.size());
  for (const Face& face : scene.faces)
    if (face.mesh < boxes.size() && (!ground || face.mesh != *ground))
      for (const glm::dvec3& v : face.vertices) boxes[face.mesh].add(v);
  std::vector<std::size_t> meshes;
  for (std::size_t m = 0; m < boxes.size(); ++m)
    if (!boxes[m].empty()) meshes.push_back(m);
  if (meshes.size() < 10) return stray;
  // The median of the meshes' centres in plan, and how far most of them lie from it.
  auto median = [](std::vector<double> values, double q) {
    const auto k = values.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), k, values.end());
    return *k;
  };
  std::vector<double> xs, ys, sizes;
  for (std::size_t m : meshes) {
    xs.push_back(0.5 * (boxes[m].lo.x + boxes[m].hi.x));
    ys.push_back(0.5 * (boxes[m].lo.y + boxes[m].hi.y));
    sizes.push_back(glm::length(boxes[m].hi - boxes[m].lo));
  }
  const glm::dvec2 centre(median(xs, 0.5), median(ys, 0.5));
  std::vector<double> distances;
  for (std::size_t i = 0; i < meshes.size(); ++i) distances.push_back(glm::length(glm::dvec2(xs[i], ys[i]) - centre));
  const double reach = 4.0 * std::max(median(distances, 0.8), median(sizes, 0.5));
  std::size_t count = 0;
  for (std::size_t i = 0; i < meshes.size(); ++i) count += distances[i] > reach ? 1 : 0;
  if (count == 0 || 10 * count > meshes.size()) return stray;  // a spread-out scene is framed whole
  for (std::size_t i = 0; i < meshes.size(); ++i) stray[meshes[i]] = distances[i] > reach ? 1 : 0;
  return stray;
}

std::vector<glm::dvec3> framed_points(const Scene& scene, Framing framing) {
  std::vector<glm::dvec3> points;
  const std::optional<std::size_t> ground = framing == Framing::Shadows ? ground_mesh(scene) : std::nullopt;
  // A few meshes far from all the others (a city sample with one building 600 m away) would
  // shrink the rest to a corner: the default framing leaves them out.
  const std::vector<char> stray =
      framing == Framing::Shadows ? stray_meshes(scene, ground) : std::vector<char>(scene.meshes.size(), 0);
  auto framed = [&](const Face& face) { return face.mesh >= stray.size() || !stray[face.mesh]; };
  bool has_model = false;
  if (ground)
    for (const Face& face : scene.faces) has_model = has_model || face.mesh != *ground;
  if (!ground || !has_model) {
    for (const Face& face : scene.faces)
      if (framed(face)) points.insert(points.end(), face.vertices.begin(), face.vertices.end());
    return points;
  }

  Box ground_box, model_box;
  double ground_height = 0.0;
  std::size_t ground_vertices = 0;
  std::vector<Box> mesh_boxes(scene.meshes.size());
  for (const Face& face : scene.faces)
    for (const glm::dvec3& v : face.vertices) {
      if (face.mesh == *ground) {
        ground_box.add(v);
        ground_height += v.z;
        ++ground_vertices;
      } else if (framed(face)) {
        points.push_back(v);
        model_box.add(v);
        mesh_boxes[face.mesh].add(v);
      }
    }
  ground_height /= static_cast<double>(ground_vertices);
  // A low sun's shadow runs to the horizon: frame shadows up to twice the model's size.
  const double reach = 2.0 * std::max(glm::length(model_box.hi - model_box.lo), 1e-9);

  // The shadows of each mesh lie inside the projections of its bounding box's corners (a
  // projection from a point or a direction keeps convex sets convex).
  std::vector<glm::dvec3> sources;  // point-like positions of point, area and disk lights
  for (const Box& box : mesh_boxes) {
    if (box.empty()) continue;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 v((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                         (corner & 4) ? box.hi.z : box.lo.z);
      const double height = v.z - ground_height;
      if (!(height > 0.0)) continue;
      for (const Light& light : scene.lights) {
        // Each ray along which the corner's shadow runs: from the light's point-like sources
        // through the corner, or along the light's direction. A light at or below the ground
        // lights none of it.
        sources.clear();
        if (light.type == LightType::Directional) {
          if (!(light.to_light.z > 0.0)) continue;
          sources.push_back(v + light.to_light);
        } else if (light.type == LightType::Area) {
          sources = light.polygon;
        } else {
          sources.push_back(light.position);
        }
        for (const glm::dvec3& s : sources) {
          if (!(s.z > ground_height)) continue;
          const glm::dvec3 d = v - s;
          glm::dvec2 end;
          if (d.z < 0.0) {  // the ray goes down and meets the ground's plane
            const glm::dvec3 hit = v + d * (height / -d.z);
            end = glm::dvec2(hit.x, hit.y);
          } else {
            const glm::dvec2 flat(d.x, d.y);
            const double length = glm::length(flat);
            if (!(length > 0.0)) continue;
            end = glm::dvec2(v.x, v.y) + flat * (reach / length);
          }
          glm::dvec2 start(v.x, v.y);
          const glm::dvec2 run = end - start;
          if (glm::length(run) > reach) end = start + run * (reach / glm::length(run));
          if (!clip_to_plan(start, end, ground_box)) continue;
          points.emplace_back(end.x, end.y, ground_height);
        }
      }
    }
  }
  return points;
}

Camera frame_points(const Scene& scene, const std::vector<glm::dvec3>& points, double aspect, double margin,
                    double fov_degrees) {
  Camera camera;
  camera.fov_degrees = fov_degrees;
  Box box;
  for (const glm::dvec3& p : points) box.add(p);
  if (box.empty() || !(aspect > 0.0)) return camera;
  camera.target = 0.5 * (box.lo + box.hi);
  const double radius = std::max(0.5 * glm::length(box.hi - box.lo), 1e-9);
  // From 45 degrees above the horizon, on a side turned 70 degrees (40 to 90, below) from the
  // one the first light's shadows fall to: the camera sees both lit and shadowed walls and the
  // shadows running across the picture in front of what casts them. (Straight from the shadow
  // side, as before, every wall in view was a wall in shadow.)
  glm::dvec3 shadow_side(0.0, -1.0, 0.0);
  if (!scene.lights.empty()) {
    const Light& light = scene.lights.front();
    glm::dvec3 source = light.position;
    if (light.type == LightType::Area && !light.polygon.empty()) {
      source = glm::dvec3(0.0);
      for (const glm::dvec3& p : light.polygon) source += p / static_cast<double>(light.polygon.size());
    }
    const glm::dvec3 to_light =
        light.type == LightType::Directional ? light.to_light : source - camera.target;
    const glm::dvec3 flat(-to_light.x, -to_light.y, 0.0);
    if (glm::length(flat) > 1e-9 * glm::length(to_light)) shadow_side = glm::normalize(flat);
  }
  const double turn = 70.0 * M_PI / 180.0;
  const double elevation = 45.0 * M_PI / 180.0;
  auto view_from = [&](double azimuth_turn) {
    const double t = turn + azimuth_turn;
    const glm::dvec3 side(shadow_side.x * std::cos(t) - shadow_side.y * std::sin(t),
                          shadow_side.x * std::sin(t) + shadow_side.y * std::cos(t), 0.0);
    return glm::normalize(glm::dvec3(-side.x * std::cos(elevation), -side.y * std::cos(elevation),
                                     -std::sin(elevation)));
  };
  // Closed solids show as much front as back from any side; open geometry (the walls of a
  // room) need not. When the shadow side sees clearly more backs than fronts of the upright
  // faces, take the one of eight sides that sees most fronts.
  auto front_seen = [&](const glm::dvec3& v) {
    double seen = 0.0;
    for (const Face& face : scene.faces) {
      const glm::dvec3 n = geometry::newell_normal(face.vertices);
      seen -= n.x * v.x + n.y * v.y;
    }
    return seen;
  };
  double total = 0.0;
  for (const Face& face : scene.faces) {
    const glm::dvec3 n = geometry::newell_normal(face.vertices);
    total += std::abs(n.x) + std::abs(n.y);
  }
  // Of the sides 40 to 90 degrees from the shadow side (either way round), the one that sees
  // most of the walls the first light lights: a camera looking square at the walls in shadow of
  // a block laid out on a grid would show nothing lit but the roofs.
  double chosen = 0.0;
  if (!scene.lights.empty()) {
    const Light& light = scene.lights.front();
    const glm::dvec3 l = light.type == LightType::Directional ? light.to_light : light.position - camera.target;
    auto lit_seen = [&](const glm::dvec3& v) {
      double seen = 0.0;
      for (const Face& face : scene.faces) {
        const glm::dvec3 n = geometry::newell_normal(face.vertices);
        if (glm::dot(n, l) > 0.0) seen += std::max(0.0, -(n.x * v.x + n.y * v.y));
      }
      return seen;
    };
    double most = lit_seen(view_from(0.0));
    for (double degrees : {-10.0, 10.0, -20.0, 20.0, -30.0, -140.0, -130.0, -150.0, -120.0, -160.0, -110.0}) {
      const double offset = degrees * M_PI / 180.0;
      const double seen = lit_seen(view_from(offset));
      if (seen > 1.05 * most + 1e-12 * total) {
        most = seen;
        chosen = offset;
      }
    }
  }
  glm::dvec3 view = view_from(chosen);
  double best = front_seen(view);
  if (best < -0.05 * total) {
    for (int k : {1, -1, 2, -2, 3, -3, 4}) {
      const glm::dvec3 candidate = view_from(chosen + k * M_PI / 4.0);
      const double seen = front_seen(candidate);
      if (seen > best + 1e-9 * total) {
        best = seen;
        view = candidate;
      }
    }
  }
  const glm::dvec3 right = glm::normalize(glm::cross(view, glm::dvec3(0.0, 0.0, 1.0)));
  const glm::dvec3 up = glm::cross(right, view);
  const double fill = 1.0 / (1.0 + std::max(0.0, margin));
  const double tan_vertical = std::tan(0.5 * camera.fov_degrees * M_PI / 180.0) * fill;
  const double tan_horizontal = tan_vertical * aspect;

  // The nearest distance at which every point is in view (tighter than the bounding sphere,
  // mostly empty air for a flat scene seen at an angle); then the target moves sideways to
  // centre the picture, and the fit is repeated.
  double distance = 0.0;
  for (int pass = 0; pass < 4; ++pass) {
    distance = 0.0;
    for (const glm::dvec3& v : points) {
      const glm::dvec3 offset = v - camera.target;
      const double depth = glm::dot(offset, view);  // positive: beyond the target
      distance = std::max({distance, std::abs(glm::dot(offset, right)) / tan_horizontal - depth,
                           std::abs(glm::dot(offset, up)) / tan_vertical - depth});
    }
    distance = std::max(distance, 0.1 * radius);
    if (pass == 3) break;
    const glm::dvec3 eye = camera.target - distance * view;
    double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
    for (const glm::dvec3& v : points) {
      const glm::dvec3 offset = v - eye;
      const double depth = glm::dot(offset, view);
      if (!(depth > 0.0)) continue;
      const double x = glm::dot(offset, right) / depth;
      const double y = glm::dot(offset, up) / depth;
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, y);
      y_hi = std::max(y_hi, y);
    }
    if (!(x_lo <= x_hi)) break;
    camera.target += distance * (0.5 * (x_lo + x_hi) * right + 0.5 * (y_lo + y_hi) * up);
  }
  camera.eye = camera.target - distance * view;
  camera.up = {0.0, 0.0, 1.0};
  return camera;
}

Camera default_camera(const Scene& scene, double aspect) {
  return frame_points(scene, framed_points(scene, Framing::Scene), aspect);
}

Camera resolve_camera(const Scene& scene, const CameraRequest& request, double aspect) {
  Camera camera = frame_points(scene, framed_points(scene, request.framing), aspect, request.margin);
  if (scene.camera) {
    const shadow::Camera& given = *scene.camera;
    if (given.eye) camera.eye = *given.eye;
    if (given.target) camera.target = *given.target;
    if (given.up) camera.up = *given.up;
    if (given.fov_degrees) camera.fov_degrees = *given.fov_degrees;
  }
  if (request.target) camera.target = *request.target;
  if (request.eye) camera.eye = *request.eye;
  if (request.up) camera.up = *request.up;
  if (request.fov_degrees) camera.fov_degrees = *request.fov_degrees;

  // A camera that cannot look is bad input: name the options, or the scene's "camera", that
  // made it so.
  const bool view_from_options = request.eye || request.target;
  const SourceLocation view_source =
      view_from_options ? SourceLocation{"", "--eye/--target"} : SourceLocation{request.scene_file, "camera"};
  const glm::dvec3 view = camera.target - camera.eye;
  const double view_length = glm::length(view);
  if (!(view_length > 0.0) || !std::isfinite(view_length))
    throw InputError(view_source, "the camera's eye and target are the same point");
  const double up_length = glm::length(camera.up);
  if (!(up_length > 0.0) || !std::isfinite(up_length) ||
      glm::length(glm::cross(view / view_length, camera.up / up_length)) <= 1e-12)
    throw InputError(request.up || view_from_options ? SourceLocation{"", "--up"}
                                                     : SourceLocation{request.scene_file, "camera.up"},
                     "the camera's up direction is zero or parallel to the view direction (from eye to "
                     "target)");
  return camera;
}

}  // namespace shadow::render
