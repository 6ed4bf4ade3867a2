// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/shaded_mesh.hpp"

#include "geometry/newell_normal.hpp"  // libshadow/src/geometry: header-only, glm only
#include "geometry/unit_vector.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace shadow::render {
namespace {

using geometry::unit_or_zero;

/// Newell's normal (not normalised): its length is twice the polygon's area.
glm::dvec3 newell(const std::vector<glm::dvec3>& polygon) { return geometry::newell_normal(polygon); }

struct Triangle {
  glm::dvec3 a, b, c;
  bool lit = false;
  glm::dvec3 lo, hi;  // bounding box
};

Triangle make_triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, bool lit) {
  return {a, b, c, lit, glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))};
}

/// Ear clipping of a simple polygon in the plane with normal `normal` (the polygon's own
/// orientation). Fragments are simple, so an ear always exists; if rounding hides every ear,
/// the rest is fanned rather than dropped.
std::vector<Triangle> triangulate(const std::vector<glm::dvec3>& polygon, const glm::dvec3& normal,
                                  bool lit) {
  std::vector<Triangle> out;
  std::vector<glm::dvec3> p = polygon;
  auto cross_along_normal = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return glm::dot(glm::cross(b - a, c - a), normal);
  };
  auto inside = [&](const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return cross_along_normal(a, b, q) > 0 && cross_along_normal(b, c, q) > 0 &&
           cross_along_normal(c, a, q) > 0;
  };
  while (p.size() > 3) {
    const std::size_t n = p.size();
    bool clipped = false;
    for (std::size_t i = 0; i < n && !clipped; ++i) {
      const glm::dvec3& a = p[(i + n - 1) % n];
      const glm::dvec3& b = p[i];
      const glm::dvec3& c = p[(i + 1) % n];
      const double turn = cross_along_normal(a, b, c);
      if (turn < 0) continue;  // reflex corner
      bool empty = true;
      if (turn > 0) {
        for (std::size_t j = 0; j < n && empty; ++j) {
          if (j == i || j == (i + n - 1) % n || j == (i + 1) % n) continue;
          if (inside(p[j], a, b, c)) empty = false;
        }
      }
      if (!empty) continue;
      if (turn > 0) out.push_back(make_triangle(a, b, c, lit));  // a collinear corner just goes
      p.erase(p.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) break;
  }
  for (std::size_t i = 1; i + 1 < p.size(); ++i)
    if (cross_along_normal(p[0], p[i], p[i + 1]) > 0) out.push_back(make_triangle(p[0], p[i], p[i + 1], lit));
  return out;
}

/// Sutherland–Hodgman: the part of convex `polygon` inside triangle `t` (both on one plane).
std::vector<glm::dvec3> clip(const std::vector<glm::dvec3>& polygon, const Triangle& t) {
  const glm::dvec3 tn = glm::cross(t.b - t.a, t.c - t.a);
  std::vector<glm::dvec3> current = polygon;
  const glm::dvec3 corners[3] = {t.a, t.b, t.c};
  for (int e = 0; e < 3 && !current.empty(); ++e) {
    const glm::dvec3& from = corners[e];
    const glm::dvec3& to = corners[(e + 1) % 3];
    const glm::dvec3 inward = glm::cross(tn, to - from);
    auto side = [&](const glm::dvec3& q) { return glm::dot(inward, q - from); };
    std::vector<glm::dvec3> next;
    for (std::size_t i = 0; i < current.size(); ++i) {
      const glm::dvec3& p = current[i];
      const glm::dvec3& q = current[(i + 1) % current.size()];
      const double sp = side(p);
      const double sq = side(q);
      if (sp >= 0) next.push_back(p);
      if ((sp >= 0) != (sq >= 0)) next.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    current.swap(next);
  }
  return current;
}

bool boxes_overlap(const glm::dvec3& lo1, const glm::dvec3& hi1, const glm::dvec3& lo2, const glm::dvec3& hi2) {
  return lo1.x <= hi2.x && lo2.x <= hi1.x && lo1.y <= hi2.y && lo2.y <= hi1.y && lo1.z <= hi2.z &&
         lo2.z <= hi1.z;
}

glm::dvec3 centroid(const std::vector<glm::dvec3>& polygon) {
  glm::dvec3 sum(0.0);
  for (const glm::dvec3& p : polygon) sum += p;
  return sum / static_cast<double>(polygon.size());
}

glm::dvec3 clamp01(const glm::dvec3& c) { return glm::clamp(c, glm::dvec3(0.0), glm::dvec3(1.0)); }

double shoulder(double x, double knee) {
  if (!(x > knee)) return std::max(x, 0.0);
  const double room = 1.0 - knee;
  return knee + room * (1.0 - std::exp(-(x - knee) / room));
}

/// Scales and maps the shaded colours into [0, 1] (see Exposure).
void apply_exposure(ColouredMesh& mesh, const Exposure& exposure) {
  std::vector<glm::dvec3>& colours = mesh.triangle_colours.empty() ? mesh.point_colours : mesh.triangle_colours;
  double scale = exposure.scale;
  if (exposure.automatic && !colours.empty()) {
    std::vector<double> brightest(colours.size());
    for (std::size_t i = 0; i < colours.size(); ++i)
      brightest[i] = std::max({colours[i].r, colours[i].g, colours[i].b});
    const double rank = std::clamp(exposure.percentile, 0.0, 1.0) * static_cast<double>(brightest.size() - 1);
    const auto nth = brightest.begin() + static_cast<std::ptrdiff_t>(rank);
    std::nth_element(brightest.begin(), nth, brightest.end());
    if (*nth > exposure.target) scale *= exposure.target / *nth;
  }
  mesh.exposure = scale;
  const double knee = std::clamp(exposure.knee, 0.0, 0.999);
  for (glm::dvec3& c : colours) {
    c *= scale;
    if (exposure.soft_shoulder) c = glm::dvec3(shoulder(c.r, knee), shoulder(c.g, knee), shoulder(c.b, knee));
    c = clamp01(c);
  }
}

}  // namespace

std::string to_string(Shading shading) {
  switch (shading) {
    case Shading::Flat: return "flat";
    case Shading::Gouraud: return "gouraud";
    case Shading::Phong: return "phong";
  }
  return "?";
}

bool parse_shading(const std::string& name, Shading& shading) {
  for (Shading s : {Shading::Flat, Shading::Gouraud, Shading::Phong}) {
    if (to_string(s) == name) {
      shading = s;
      return true;
    }
  }
  return false;
}

std::vector<OverlayCell> overlay_fragments(const Scene& scene, const ShadowResult& result) {
  const std::size_t light_count = scene.lights.size();
  // Triangles of every face, per light; fragments come ordered by face then light.
  std::map<std::size_t, std::vector<std::vector<Triangle>>> by_face;
  for (const Fragment& f : result.fragments) {
    if (f.face_id >= scene.faces.size() || f.light_id >= light_count || f.polygon.size() < 3) continue;
    auto& lights = by_face[f.face_id];
    if (lights.empty()) lights.resize(light_count);
    const glm::dvec3 normal = newell(scene.faces[f.face_id].vertices);
    for (Triangle& t : triangulate(f.polygon, normal, f.lit)) lights[f.light_id].push_back(t);
  }

  std::vector<OverlayCell> cells;
  for (auto& [face_id, lights] : by_face) {
    const double face_area = 0.5 * glm::length(newell(scene.faces[face_id].vertices));
    // Pieces below this are rounding slivers along shared edges.
    const double negligible = 1e-12 * face_area;
    std::vector<OverlayCell> current;
    for (std::size_t k = 0; k < light_count; ++k) {
      const std::vector<Triangle>& triangles = lights[k];
      if (k == 0) {
        for (const Triangle& t : triangles) {
          OverlayCell cell;
          cell.face_id = face_id;
          cell.polygon = {t.a, t.b, t.c};
          cell.lit.assign(light_count, false);
          cell.lit[0] = t.lit;
          current.push_back(std::move(cell));
        }
        continue;
      }
      std::vector<OverlayCell> next;
      for (const OverlayCell& cell : current) {
        glm::dvec3 lo = cell.polygon.front(), hi = cell.polygon.front();
        for (const glm::dvec3& p : cell.polygon) {
          lo = glm::min(lo, p);
          hi = glm::max(hi, p);
        }
        for (const Triangle& t : triangles) {
          if (!boxes_overlap(lo, hi, t.lo, t.hi)) continue;
          std::vector<glm::dvec3> piece = clip(cell.polygon, t);
          if (piece.size() < 3 || 0.5 * glm::length(newell(piece)) <= negligible) continue;
          OverlayCell split = cell;
          split.polygon = std::move(piece);
          split.lit[k] = t.lit;
          next.push_back(std::move(split));
        }
      }
      current.swap(next);
    }
    for (OverlayCell& cell : current) cells.push_back(std::move(cell));
  }
  return cells;
}

ColouredMesh shade_cells(const Scene& scene, const std::vector<OverlayCell>& cells,
                         const ShadeOptions& options) {
  ColouredMesh mesh;
  const Camera& camera = options.camera;
  // Material lookup by name once per face, not once per shaded point.
  const std::vector<Material> materials = display_materials(scene, options.palette);
  std::vector<const Material*> material_of_face(scene.faces.size(), nullptr);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) material_of_face[f] = &materials[scene.faces[f].mesh];
  auto colour_at = [&](const glm::dvec3& p, const glm::dvec3& normal, const OverlayCell& cell) {
    ShadingPoint point{p, normal, camera.eye};
    return shade(point, *material_of_face[cell.face_id], scene.lights, cell.lit, options.lighting);
  };

  // Phong: the size of a pixel at distance 1, to subdivide cells to about a pixel.
  const double pixel_at_unit_distance =
      2.0 * std::tan(0.5 * camera.fov_degrees * M_PI / 180.0) / std::max(1, options.image_height);
  double pixels_per_segment = 1.5;
  if (options.shading == Shading::Phong) {
    // Coarser if the fine subdivision would be too large.
    auto count = [&](double pixels) {
      std::size_t total = 0;
      for (const OverlayCell& cell : cells)
        for (std::size_t i = 1; i + 1 < cell.polygon.size(); ++i) {
          const glm::dvec3 &a = cell.polygon[0], &b = cell.polygon[i], &c = cell.polygon[i + 1];
          const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
          const double target = pixels * pixel_at_unit_distance * glm::length((a + b + c) / 3.0 - camera.eye);
          const double n = std::min(512.0, std::ceil(longest / std::max(target, 1e-300)));
          total += static_cast<std::size_t>(n * n);
        }
      return total;
    };
    while (count(pixels_per_segment) > options.max_triangles) pixels_per_segment *= 1.5;
  }

  for (const OverlayCell& cell : cells) {
    const glm::dvec3 normal = unit_or_zero(newell(scene.faces[cell.face_id].vertices));
    if (options.shading == Shading::Flat) {
      const glm::dvec3 colour = colour_at(centroid(cell.polygon), normal, cell);
      const std::size_t base = mesh.points.size();
      for (const glm::dvec3& p : cell.polygon) mesh.points.push_back(p);
      for (std::size_t i = 1; i + 1 < cell.polygon.size(); ++i) {
        mesh.triangles.insert(mesh.triangles.end(), {base, base + i, base + i + 1});
        mesh.triangle_colours.push_back(colour);
      }
    } else if (options.shading == Shading::Gouraud) {
      const std::size_t base = mesh.points.size();
      for (const glm::dvec3& p : cell.polygon) {
        mesh.points.push_back(p);
        mesh.point_colours.push_back(colour_at(p, normal, cell));
      }
      for (std::size_t i = 1; i + 1 < cell.polygon.size(); ++i)
        mesh.triangles.insert(mesh.triangles.end(), {base, base + i, base + i + 1});
    } else {
      // Per pixel: a fan of the convex cell, each triangle cut into an n x n grid of
      // triangles about a pixel wide, the model evaluated at every grid point.
      for (std::size_t i = 1; i + 1 < cell.polygon.size(); ++i) {
        const glm::dvec3 a = cell.polygon[0], b = cell.polygon[i], c = cell.polygon[i + 1];
        const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        const double target =
            pixels_per_segment * pixel_at_unit_distance * glm::length((a + b + c) / 3.0 - camera.eye);
        const int n = static_cast<int>(std::clamp(std::ceil(longest / std::max(target, 1e-300)), 1.0, 512.0));
        const std::size_t base = mesh.points.size();
        auto index = [&](int row, int col) {  // row + col <= n; rows of n + 1, n, ..., 1 points
          return base + static_cast<std::size_t>(row * (n + 1) - row * (row - 1) / 2 + col);
        };
        for (int row = 0; row <= n; ++row)
          for (int col = 0; col + row <= n; ++col) {
            // Corners exactly where they were: shadow edges stay put.
            glm::dvec3 p = a + (b - a) * (static_cast<double>(col) / n) + (c - a) * (static_cast<double>(row) / n);
            if (row == 0 && col == 0) p = a;
            if (row == 0 && col == n) p = b;
            if (row == n) p = c;
            mesh.points.push_back(p);
            mesh.point_colours.push_back(colour_at(p, normal, cell));
          }
        for (int row = 0; row < n; ++row)
          for (int col = 0; col + row < n; ++col) {
            mesh.triangles.insert(mesh.triangles.end(), {index(row, col), index(row, col + 1), index(row + 1, col)});
            if (col + row + 1 < n)
              mesh.triangles.insert(mesh.triangles.end(),
                                    {index(row, col + 1), index(row + 1, col + 1), index(row + 1, col)});
          }
      }
    }
  }
  apply_exposure(mesh, options.exposure);
  return mesh;
}

std::vector<Material> display_materials(const Scene& scene, const std::optional<Palette>& palette) {
  std::vector<Material> materials(scene.meshes.size());
  const std::vector<MeshRole> roles = mesh_roles(scene);
  const bool any_building = std::find(roles.begin(), roles.end(), MeshRole::Building) != roles.end();
  std::size_t next_other = any_building ? 1 : 0;  // without buildings, the first other mesh looks like one
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const std::string& name = scene.meshes[m].material;
    const auto named = std::find_if(scene.materials.begin(), scene.materials.end(),
                                    [&](const Material& material) { return !name.empty() && material.name == name; });
    if (named != scene.materials.end()) {
      materials[m] = *named;  // the scene's materials win
      continue;
    }
    if (!palette) continue;
    Material& material = materials[m];
    material.k_a = palette->k_a;
    material.k_d = palette->k_d;
    material.k_s = palette->k_s;
    material.shininess = palette->shininess;
    if (roles[m] == MeshRole::Ground) {
      material.color = palette->ground;
    } else if (roles[m] == MeshRole::Building) {
      material.color = palette->building;
    } else {
      const std::size_t i = next_other++;
      material.color = i == 0 || palette->others.empty() ? palette->building
                                                         : palette->others[(i - 1) % palette->others.size()];
    }
  }
  return materials;
}

}  // namespace shadow::render
