// SPDX-License-Identifier: GPL-3.0-or-later
// The ground of shadow/irradiance.hpp: the lower hemisphere's patches, which faces are the
// ground, and each face's view of the ground through the scene's obstructions (docs/irradiance.md).
#include <shadow/irradiance.hpp>

#include "irradiance/ground_view.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace shadow {

std::vector<SkyPatch> ground_patches(int count, double north_axis_degrees) {
  std::vector<SkyPatch> patches = sky_patches(count, north_axis_degrees);
  for (SkyPatch& p : patches) {
    p.altitude = -p.altitude;
    p.to_patch.z = -p.to_patch.z;
  }
  return patches;
}

std::vector<unsigned char> ground_faces(const Scene& scene) {
  // CityJSON city objects that lie on the ground (terrain, land use, traffic areas).
  static const std::array<const char*, 5> kGroundTypes = {"TINRelief", "LandUse", "Road", "Railway", "TransportSquare"};
  std::vector<unsigned char> mesh_ground(scene.meshes.size(), 0);
  if (scene.ground) {
    for (std::size_t m : *scene.ground)
      if (m < mesh_ground.size()) mesh_ground[m] = 1;
  } else {
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
      const Mesh& mesh = scene.meshes[m];
      bool ground = mesh.name == "ground";
      for (const char* type : kGroundTypes) ground = ground || mesh.object_type == type;
      mesh_ground[m] = ground ? 1 : 0;
    }
  }
  std::vector<unsigned char> ground(scene.faces.size(), 0);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    const bool of_mesh = face.mesh < mesh_ground.size() && mesh_ground[face.mesh] != 0;
    ground[f] = (of_mesh || face.kind == "GroundSurface") ? 1 : 0;
  }
  return ground;
}

namespace irradiance_detail {

void ground_views(IrradianceResult& r, const ShadowEngine& engine, const Scene& scene, const SeriesOptions& series) {
  const std::size_t rows = r.faces.size();
  const std::vector<unsigned char> ground = ground_faces(scene);
  r.on_ground.assign(rows, 0);
  bool any_ground = false;
  for (std::size_t f = 0; f < ground.size(); ++f) any_ground = any_ground || ground[f] != 0;
  for (std::size_t row = 0; row < rows; ++row) r.on_ground[row] = ground[r.faces[row]];

  std::vector<Light> lights;
  lights.reserve(r.ground_patches.size());
  for (std::size_t p = 0; p < r.ground_patches.size(); ++p) {
    Light light;
    light.name = "ground patch " + std::to_string(p);
    light.to_light = r.ground_patches[p].to_patch;
    lights.push_back(light);
  }
  if (!any_ground) {
    r.ground = engine.compute_series(lights, series);
  } else {
    // The ground faces cast no shadow here: seeing one below the horizon is seeing the ground.
    // A degenerate face keeps its id but neither casts nor receives, so the rows of this second
    // engine are the receiving faces that are not ground.
    Scene open = scene;
    for (std::size_t f = 0; f < open.faces.size(); ++f)
      if (ground[f] != 0) open.faces[f].degenerate = true;
    const ShadowEngine open_engine(open, series.threads);
    r.ground = open_engine.compute_series(lights, series);
  }

  // The lowest point of the ground faces: a face looking straight down that lies no higher
  // rests on the ground (a generated box's bottom on its ground plane) and sees none of it.
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < ground.size(); ++f)
    if (ground[f] != 0)
      for (const glm::dvec3& v : scene.faces[f].vertices) lowest = std::min(lowest, v.z);
  const auto rests_on_ground = [&](std::size_t row) {
    if (!(r.normal[row].z < -1.0 + 1e-12) || !std::isfinite(lowest)) return false;
    const double tolerance = 1e-9 * (1.0 + std::abs(lowest));
    for (const glm::dvec3& v : scene.faces[r.faces[row]].vertices)
      if (v.z > lowest + tolerance) return false;
    return true;
  };

  r.ground_view.assign(rows, 0.0);
  r.ground_view_factor_error_bound.assign(rows, 0.0);
  const bool fast = r.ground.arithmetic == Arithmetic::Fast;
  std::size_t g = 0;  // the row of r.ground: both lists ascend
  for (std::size_t row = 0; row < rows; ++row) {
    const double cos_tilt = std::clamp(r.normal[row].z, -1.0, 1.0);
    const double unobstructed = 0.5 * (1.0 - cos_tilt);
    const std::size_t face = r.faces[row];
    if (r.on_ground[row] != 0) {
      r.ground_view[row] = scene.faces[face].kind == "GroundSurface" ? 0.0 : unobstructed;
      continue;
    }
    if (rests_on_ground(row)) continue;
    while (g < r.ground.faces.size() && r.ground.faces[g] < face) ++g;
    if (g == r.ground.faces.size() || r.ground.faces[g] != face)
      throw std::logic_error("ground view: face " + std::to_string(face) + " has no row in the ground series");
    double seen = 0.0, open = 0.0, bound = 0.0;
    for (std::size_t p = 0; p < r.ground_patches.size(); ++p) {
      const double c = glm::dot(r.normal[row], r.ground_patches[p].to_patch);
      if (!(c > 0.0)) continue;
      const double weight = c * r.ground_patches[p].solid_angle;
      seen += r.ground.lit_fraction[r.ground.at(g, p)] * weight;
      open += weight;
      if (fast && r.area[row] > 0.0) bound += r.ground.lit_area_error_bound[r.ground.at(g, p)] / r.area[row] * weight;
    }
    r.ground_view[row] = open > 0.0 ? unobstructed * (seen / open) : 0.0;
    r.ground_view_factor_error_bound[row] = open > 0.0 ? unobstructed * (bound / open) : 0.0;
  }
}

}  // namespace irradiance_detail

}  // namespace shadow
