// SPDX-License-Identifier: GPL-3.0-or-later
// Depth maps from a light, shared by the hard shadow map (shadow_map.cpp) and the soft-shadow
// map baselines (soft_shadows.cpp: percentage-closer filtering and penumbra estimation).
// Directional light: one orthographic map looking along the light, its square window fitted to
// given points across the light. Point: a cube map of six 90-degree perspective maps storing
// the distance from the light. Depths are float32, computed in double from shifted coordinates.
#pragma once

#include "sampling.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace shadow::baselines_detail {

/// A triangle in a map's image coordinates (texel units, texel centres at +0.5) with what is
/// needed to get its depth at a texel centre.
struct MapTriangle {
  glm::dvec2 p[3];
  double depth[3];         // orthographic: depth at each vertex (interpolated linearly)
  glm::dvec3 normal{0.0};  // perspective: plane n . x = offset in the cube face's local frame
  double plane = 0.0;
};

/// One depth map: R x R floats, nearest depth to the light per texel (+inf: empty).
struct DepthMap {
  int resolution = 0;
  std::vector<float> depth;
  std::vector<MapTriangle> triangles;
};

/// Where a point lands in a light's depth maps.
struct MapPoint {
  int face = 0;        ///< cube face (0 for an orthographic map)
  double x = 0, y = 0; ///< continuous texel coordinates (texel i covers [i, i + 1))
  double depth = 0;    ///< the point's depth (distance from a point light; along the light otherwise)
  double foot = 0;     ///< a texel's world size at this depth
  bool inside = false; ///< in the map (false: in front of nothing, counts as lit)
};

/// The depth maps of one light.
struct LightMaps {
  ShiftedLight light;
  int resolution = 0;
  std::vector<DepthMap> maps;  ///< 1 (orthographic) or 6 (cube)
  glm::dvec3 u{0.0}, v{0.0};   ///< orthographic: axes across the light
  double a0 = 0, b0 = 0, texel = 1;
  double min_depth = 0;        ///< the nearest depth stored anywhere (+inf for an empty map)

  /// Where `p` (shifted) lands.
  [[nodiscard]] MapPoint locate(const glm::dvec3& p) const;
  /// The stored depth of the texel under `m` (its floor, clamped into a cube face); +inf outside
  /// an orthographic map.
  [[nodiscard]] float stored(const MapPoint& m) const;
  /// The point where the ray of the light through map position (face, x, y) meets the plane
  /// through `p0` with normal `n`; false when it does not (parallel, or behind the light).
  [[nodiscard]] bool on_plane(int face, double x, double y, const glm::dvec3& p0, const glm::dvec3& n,
                              glm::dvec3& out) const;
  [[nodiscard]] std::size_t bytes() const;
};

/// Shifted triangles (3 points each) of every non-degenerate face, and the diagonal of their box.
std::vector<glm::dvec3> scene_triangles(const Scene& scene, const Setup& setup, double& diagonal);

/// Rasterises `triangles` into the maps of `light` (directional: window fitted across the light
/// to `window_points`, shifted) at `resolution` texels a side, on `threads` threads.
LightMaps build_light_maps(const std::vector<glm::dvec3>& triangles, double diagonal, const ShiftedLight& light,
                           const std::vector<glm::dvec3>& window_points, int resolution, unsigned threads);

}  // namespace shadow::baselines_detail
