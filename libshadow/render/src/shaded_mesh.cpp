// SPDX-License-Identifier: GPL-3.0-or-later
#include <shadow/render/shaded_mesh.hpp>

#include "geometry/newell_normal.hpp"  // libshadow/compute/src/geometry: header-only, glm only
#include "geometry/unit_vector.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <array>
#include <cstdio>
#include <map>
#include <unordered_map>
#include <utility>

namespace shadow::render {
namespace {

using geometry::unit_or_zero;

/// Newell's normal (not normalised): its length is twice the polygon's area.
glm::dvec3 newell(const std::vector<glm::dvec3>& polygon) { return geometry::newell_normal(polygon); }

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

struct PointHash {
  std::size_t operator()(const std::array<double, 3>& p) const {
    std::size_t h = 0;
    for (double c : p) h = h * 1000003u ^ std::hash<double>{}(c);
    return h;
  }
};

struct EdgeHash {
  std::size_t operator()(const std::pair<std::size_t, std::size_t>& e) const {
    return std::hash<std::size_t>{}(e.first * 0x9E3779B97F4A7C15ull ^ e.second);
  }
};

}  // namespace

glm::dvec3 expose(const glm::dvec3& linear, const Exposure& exposure, double scale);

namespace {

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
  for (glm::dvec3& c : colours) c = expose(c, exposure, scale);
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

namespace {

/// A triangle of a face's cells over shared vertex ids, and the cell it lies in.
struct Tri {
  std::array<std::size_t, 3> v;
  std::size_t cell;
};

/// Phong's refinement of a face's triangles: longest-edge bisection (Rivara) of every edge longer
/// than `pixels_per_edge` pixels seen from `eye`, an edge split at the same midpoint from both
/// sides (`vertex` numbers the points, appending new ones to `points`), until none is too long,
/// 64 rounds, or more than `max_triangles` triangles.
template <class Vertex>
void bisect_long_edges(std::vector<Tri>& tris, std::vector<glm::dvec3>& points, const Vertex& vertex,
                       const glm::dvec3& eye, double pixels_per_edge, double pixel_at_unit_distance,
                       std::size_t max_triangles) {
  using Edge = std::pair<std::size_t, std::size_t>;  // ends in increasing order
  auto key = [](std::size_t a, std::size_t b) { return a < b ? Edge{a, b} : Edge{b, a}; };
  auto too_long = [&](std::size_t a, std::size_t b) {
    const glm::dvec3 m = 0.5 * (points[a] + points[b]);
    return glm::length(points[b] - points[a]) >
           pixels_per_edge * pixel_at_unit_distance * glm::length(m - eye);
  };
  auto longest = [&](const Tri& t) {  // index i of the longest edge v[i] -> v[i + 1]
    int best = 0;
    double length = -1.0;
    for (int i = 0; i < 3; ++i) {
      const double l = glm::length(points[t.v[(i + 1) % 3]] - points[t.v[i]]);
      if (l > length) {
        length = l;
        best = i;
      }
    }
    return best;
  };
  std::unordered_map<Edge, std::size_t, EdgeHash> midpoint;
  for (int round = 0; round < 64; ++round) {
    std::unordered_map<Edge, bool, EdgeHash> marked;
    marked.reserve(2 * tris.size());
    for (const Tri& t : tris)
      for (int i = 0; i < 3; ++i)
        if (too_long(t.v[i], t.v[(i + 1) % 3])) marked[key(t.v[i], t.v[(i + 1) % 3])] = true;
    if (marked.empty()) break;
    // Closure: a triangle with a marked edge has its longest edge marked too.
    for (bool changed = true; changed;) {
      changed = false;
      for (const Tri& t : tris) {
        bool any = false;
        for (int i = 0; i < 3; ++i) any = any || marked.count(key(t.v[i], t.v[(i + 1) % 3])) > 0;
        const int l = longest(t);
        if (any && marked.emplace(key(t.v[l], t.v[(l + 1) % 3]), true).second) changed = true;
      }
    }
    auto split_point = [&](std::size_t a, std::size_t b) {
      const Edge e = key(a, b);
      const auto found = midpoint.find(e);
      if (found != midpoint.end()) return found->second;
      // From the edge's ordered ends: the same bits whichever triangle asks.
      const std::size_t m = vertex(0.5 * (points[e.first] + points[e.second]));
      midpoint.emplace(e, m);
      return m;
    };
    std::vector<Tri> next;
    next.reserve(tris.size() * 2);
    for (const Tri& t : tris) {
      // Bisect the longest edge, then in each half the marked original edge, if any.
      const int l = longest(t);
      const std::size_t a = t.v[l], b = t.v[(l + 1) % 3], c = t.v[(l + 2) % 3];
      if (!marked.count(key(a, b))) {
        next.push_back(t);
        continue;
      }
      const std::size_t m = split_point(a, b);
      // Halves (a, m, c) and (m, b, c); their original edges are c-a and b-c.
      if (marked.count(key(c, a))) {
        const std::size_t q = split_point(c, a);
        next.push_back({{a, m, q}, t.cell});
        next.push_back({{m, c, q}, t.cell});
      } else {
        next.push_back({{a, m, c}, t.cell});
      }
      if (marked.count(key(b, c))) {
        const std::size_t q = split_point(b, c);
        next.push_back({{m, b, q}, t.cell});
        next.push_back({{m, q, c}, t.cell});
      } else {
        next.push_back({{m, b, c}, t.cell});
      }
    }
    tris.swap(next);
    if (tris.size() > max_triangles) break;
  }
}

}  // namespace

ColouredMesh shade_cells(const Scene& scene, const std::vector<OverlayCell>& cells,
                         const ShadeOptions& options) {
  ColouredMesh mesh;
  const Camera& camera = options.camera;
  // Material lookup once per face, not once per shaded point: by the face's type or mesh.
  const DisplayGroups groups = display_groups(scene, options.palette);
  auto colour_at = [&](const glm::dvec3& p, const glm::dvec3& normal, const OverlayCell& cell) {
    ShadingPoint point{p, normal, camera.eye};
    return shade(point, groups.groups[groups.face_group[cell.face_id]].material, scene.lights, cell.lit,
                 options.lighting);
  };

  // Phong: the size of a pixel at distance 1, to refine the triangles to about a pixel.
  const double pixel_at_unit_distance =
      2.0 * std::tan(0.5 * camera.fov_degrees * M_PI / 180.0) / std::max(1, options.image_height);
  double pixels_per_edge = 1.5;
  if (options.shading == Shading::Phong) {
    // Coarser if the fine refinement would be too large (about (edge / target)^2 triangles each).
    auto count = [&](double pixels) {
      double total = 0.0;
      for (const OverlayCell& cell : cells) {
        const glm::dvec3 c = centroid(cell.polygon);
        for (std::size_t i = 0; i < cell.polygon.size(); ++i) {
          const glm::dvec3 &a = cell.polygon[i], &b = cell.polygon[(i + 1) % cell.polygon.size()];
          const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
          const double target = pixels * pixel_at_unit_distance * glm::length((a + b + c) / 3.0 - camera.eye);
          total += std::max(1.0, 2.0 * std::pow(longest / std::max(target, 1e-300), 2.0));
        }
      }
      return total;
    };
    while (count(pixels_per_edge) > static_cast<double>(options.max_triangles) && pixels_per_edge < 1e6)
      pixels_per_edge *= 1.5;
  }

  // Face by face (the overlay lists a face's cells together): each cell is fanned from its
  // centroid, so every point of a cell's boundary (the overlay puts the neighbours' vertices on
  // it) is a vertex, and neighbouring triangles meet vertex to vertex. Phong refines that mesh
  // by longest-edge bisection (Rivara), splitting an edge at the same midpoint from both sides:
  // the refined mesh stays conforming, and the rasteriser leaves no crack between triangles.
  std::size_t begin = 0;
  while (begin < cells.size()) {
    std::size_t end = begin;
    while (end < cells.size() && cells[end].face_id == cells[begin].face_id) ++end;
    const glm::dvec3 normal = unit_or_zero(newell(scene.faces[cells[begin].face_id].vertices));

    if (options.shading == Shading::Flat) {
      for (std::size_t k = begin; k < end; ++k) {
        const OverlayCell& cell = cells[k];
        const glm::dvec3 c = centroid(cell.polygon);
        const glm::dvec3 colour = colour_at(c, normal, cell);
        const std::size_t base = mesh.points.size();
        mesh.points.push_back(c);
        for (const glm::dvec3& p : cell.polygon) mesh.points.push_back(p);
        const std::size_t n = cell.polygon.size();
        for (std::size_t i = 0; i < n; ++i) {
          mesh.triangles.insert(mesh.triangles.end(), {base, base + 1 + i, base + 1 + (i + 1) % n});
          mesh.triangle_colours.push_back(colour);
        }
      }
      begin = end;
      continue;
    }

    // The face's triangles over shared vertex ids.
    std::vector<glm::dvec3> points;
    std::unordered_map<std::array<double, 3>, std::size_t, PointHash> id_of;
    auto vertex = [&](const glm::dvec3& p) {
      const auto [it, added] = id_of.try_emplace({p.x, p.y, p.z}, points.size());
      if (added) points.push_back(p);
      return it->second;
    };
    std::vector<Tri> tris;
    for (std::size_t k = begin; k < end; ++k) {
      const OverlayCell& cell = cells[k];
      const std::size_t c = vertex(centroid(cell.polygon));
      const std::size_t n = cell.polygon.size();
      for (std::size_t i = 0; i < n; ++i)
        tris.push_back({{c, vertex(cell.polygon[i]), vertex(cell.polygon[(i + 1) % n])}, k});
    }

    if (options.shading == Shading::Phong)
      bisect_long_edges(tris, points, vertex, camera.eye, pixels_per_edge, pixel_at_unit_distance, options.max_triangles);

    // Colours at each (vertex, cell): a vertex on a shadow edge has one colour per side.
    std::unordered_map<std::pair<std::size_t, std::size_t>, std::size_t, EdgeHash> point_of;
    point_of.reserve(2 * tris.size());
    for (const Tri& t : tris) {
      std::size_t ids[3];
      for (int i = 0; i < 3; ++i) {
        const auto [it, added] = point_of.try_emplace({t.v[i], t.cell}, mesh.points.size());
        if (added) {
          mesh.points.push_back(points[t.v[i]]);
          mesh.point_colours.push_back(colour_at(points[t.v[i]], normal, cells[t.cell]));
        }
        ids[i] = it->second;
      }
      mesh.triangles.insert(mesh.triangles.end(), {ids[0], ids[1], ids[2]});
    }
    begin = end;
  }
  apply_exposure(mesh, options.exposure);
  return mesh;
}

glm::dvec3 expose(const glm::dvec3& linear, const Exposure& exposure, double scale) {
  glm::dvec3 c = linear * scale;
  const double knee = std::clamp(exposure.knee, 0.0, 0.999);
  if (exposure.soft_shoulder) c = glm::dvec3(shoulder(c.r, knee), shoulder(c.g, knee), shoulder(c.b, knee));
  return clamp01(c);
}

namespace {

bool one_of(const std::string& s, std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (s == n) return true;
  return false;
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

/// The scene material a mesh names, or null.
const Material* named_material(const Scene& scene, std::size_t mesh) {
  const std::string& name = scene.meshes[mesh].material;
  if (name.empty()) return nullptr;
  for (const Material& material : scene.materials)
    if (material.name == name) return &material;
  return nullptr;
}

/// True when every face of mesh `m` has a display type (and the mesh has faces).
bool typed_mesh(const Scene& scene, std::size_t m) {
  const Mesh& mesh = scene.meshes[m];
  if (mesh.face_count == 0) return false;
  for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count && f < scene.faces.size(); ++f)
    if (display_type(scene, f).empty()) return false;
  return true;
}

}  // namespace

std::string display_type(const Scene& scene, std::size_t face_id) {
  const Face& face = scene.faces[face_id];
  // What the surface is, when the model says it (EnergyPlus surface types, CityJSON semantics).
  const std::string& k = face.kind;
  if (one_of(k, {"Window", "GlassDoor", "TubularDaylightDome", "TubularDaylightDiffuser"})) return "windows (glass)";
  if (k == "Door") return "doors";
  if (k == "Shading") return "shading";
  if (k == "Wall") return "walls";
  if (k == "Roof" || k == "RoofSurface") return "roofs";
  if (k == "Floor" || k == "Ceiling") return "floors, ceilings";
  // Else what the city object is (CityJSON 1.0 to 2.0 types).
  const std::string& t = face.mesh < scene.meshes.size() ? scene.meshes[face.mesh].object_type : std::string();
  if (t.empty() || t == "zone") return "";  // an EnergyPlus zone: its faces' kinds say it all
  if (starts_with(t, "Building")) return "buildings";
  if (one_of(t, {"TINRelief", "LandUse"})) return "terrain";
  if (one_of(t, {"PlantCover", "SolitaryVegetationObject"})) return "vegetation";
  if (one_of(t, {"WaterBody", "Waterway"})) return "water";
  if (one_of(t, {"Road", "Railway", "TransportSquare"})) return "roads";
  if (starts_with(t, "Bridge")) return "bridges";
  return "other city objects";
}

std::vector<Material> display_materials(const Scene& scene, const std::optional<Palette>& palette) {
  std::vector<Material> materials(scene.meshes.size());
  const std::vector<MeshRole> roles = mesh_roles(scene);
  // Meshes whose every face has a type take their colours from display_groups and no turn of
  // the rotating colours; with them in the scene, the first other mesh is not made to look
  // like a building.
  std::vector<char> typed(scene.meshes.size(), 0);
  bool any_building = std::find(roles.begin(), roles.end(), MeshRole::Building) != roles.end();
  if (palette)
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
      typed[m] = typed_mesh(scene, m) ? 1 : 0;
      any_building = any_building || typed[m];
    }
  std::size_t next_other = any_building ? 1 : 0;  // without buildings, the first other mesh looks like one
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (const Material* named = named_material(scene, m)) {
      materials[m] = *named;  // the scene's materials win
      continue;
    }
    if (!palette) continue;
    Material& material = materials[m];
    material.k_a = palette->k_a;
    material.k_d = palette->k_d;
    material.k_s = palette->k_s;
    material.shininess = palette->shininess;
    if (typed[m]) {
      material.color = palette->other;  // its faces are drawn by type (display_groups)
    } else if (roles[m] == MeshRole::Ground) {
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

DisplayGroups display_groups(const Scene& scene, const std::optional<Palette>& palette) {
  DisplayGroups out;
  out.face_group.assign(scene.faces.size(), 0);
  const std::vector<Material> by_mesh = display_materials(scene, palette);
  const std::vector<MeshRole> roles = mesh_roles(scene);
  std::map<std::string, std::size_t> index;         // a group's key -> its index
  std::vector<std::vector<std::string>> mesh_names;  // per group, for groups labelled by meshes
  std::vector<std::size_t> last_mesh;                // per group, the last mesh named
  auto group_of = [&](const std::string& key, const std::string& label, const Material& material) {
    const auto [it, added] = index.try_emplace(key, out.groups.size());
    if (added) {
      out.groups.push_back({label, material});
      mesh_names.emplace_back();
      last_mesh.push_back(scene.meshes.size());
    }
    return it->second;
  };
  auto colour_key = [](const Material& m) {
    char text[160];
    std::snprintf(text, sizeof text, "colour %.17g %.17g %.17g %.17g %.17g", m.color.r, m.color.g, m.color.b, m.k_a, m.k_d);
    return std::string(text);
  };
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const std::size_t m = scene.faces[f].mesh;
    if (m >= scene.meshes.size()) continue;
    std::size_t g = 0;
    const std::string type = palette && named_material(scene, m) == nullptr ? display_type(scene, f) : std::string();
    if (!type.empty()) {
      Material material;
      material.name = type;
      material.k_a = palette->k_a;
      material.k_d = palette->k_d;
      material.k_s = palette->k_s;
      material.shininess = palette->shininess;
      if (type == "windows (glass)") {
        material.color = palette->glass;
        material.k_s = palette->glass_k_s;
        material.shininess = palette->glass_shininess;
      } else if (type == "doors") material.color = palette->door;
      else if (type == "shading") material.color = palette->shading;
      else if (type == "walls" || type == "buildings") material.color = palette->building;
      else if (type == "roofs") material.color = palette->roof;
      else if (type == "floors, ceilings") material.color = palette->floor;
      else if (type == "terrain") material.color = palette->ground;
      else if (type == "vegetation") material.color = palette->vegetation;
      else if (type == "water") material.color = palette->water;
      else if (type == "roads") material.color = palette->road;
      else if (type == "bridges") material.color = palette->bridge;
      else material.color = palette->other;
      g = group_of("type " + type, type, material);
    } else {
      // Labelled by the meshes that share the colour, as before types.
      g = group_of(colour_key(by_mesh[m]), "", by_mesh[m]);
      if (last_mesh[g] != m) {
        const std::string& name = scene.meshes[m].name;
        mesh_names[g].push_back(roles[m] == MeshRole::Ground && name.find("ground") == std::string::npos
                                    ? name + " (ground)"
                                    : name);
        last_mesh[g] = m;
      }
    }
    out.face_group[f] = g;
  }
  for (std::size_t g = 0; g < out.groups.size(); ++g) {
    const std::vector<std::string>& names = mesh_names[g];
    if (names.empty()) continue;
    std::string label;
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (i == 2) {
        label += " and " + std::to_string(names.size() - 2) + " more";
        break;
      }
      label += (i ? ", " : "") + names[i];
    }
    out.groups[g].label = label;
  }
  return out;
}

}  // namespace shadow::render
