// SPDX-License-Identifier: GPL-3.0-or-later
/// @file shaded_mesh.hpp
/// @brief From exact per-light fragments to coloured polygons ready to draw (no VTK here).
///
/// Each face has one set of lit/shadowed fragments per light. To shade a point we need its
/// visibility for every light at once, so the per-light sets of a face are overlaid: the
/// fragments are triangulated and intersected (convex clipping in double precision), giving
/// cells that are wholly lit or wholly shadowed for every light. Their edges are the exact
/// shadow edges of the fragments (rounded to double once), not a shadow map's staircase.
#pragma once

#include "render/camera.hpp"

#include <shadow/lighting.hpp>
#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace shadow::render {

/// Shading methods of seed 000.
enum class Shading {
  Flat,     ///< one colour per cell, evaluated at its centroid
  Gouraud,  ///< colours evaluated at cell vertices, interpolated across the cell
  Phong,    ///< colours evaluated per pixel (cells subdivided to about a pixel; see docs/lighting.md)
};

std::string to_string(Shading shading);
bool parse_shading(const std::string& name, Shading& shading);

/// One convex cell of a face on which every light is either lit or shadowed throughout.
struct OverlayCell {
  std::size_t face_id = 0;
  std::vector<glm::dvec3> polygon;  ///< convex, on the face's plane
  std::vector<bool> lit;            ///< one entry per scene light
};

/// The overlay of every light's fragments on every face that has fragments for every light.
/// `result` must hold fragments for every light of `scene` (compute_shadows with polygons on).
std::vector<OverlayCell> overlay_fragments(const Scene& scene, const ShadowResult& result);

/// Triangles (as point index triples) with a colour per point (for Gouraud and Phong) or per
/// triangle (for Flat). Colours are linear RGB clamped to [0, 1].
struct ColouredMesh {
  std::vector<glm::dvec3> points;
  std::vector<std::size_t> triangles;   ///< 3 point indices per triangle
  std::vector<glm::dvec3> point_colours;     ///< Gouraud, Phong: one per point
  std::vector<glm::dvec3> triangle_colours;  ///< Flat: one per triangle
};

/// What to shade and how.
struct ShadeOptions {
  LightingSettings lighting;
  Shading shading = Shading::Gouraud;
  Camera camera;
  int image_height = 600;  ///< with the camera's view angle, sets the pixel size for Phong
  /// Phong: the largest number of triangles; past it the subdivision is coarser than a pixel.
  std::size_t max_triangles = 2'000'000;
};

/// Colours the overlay cells with the lighting model (materials from `scene`).
ColouredMesh shade_cells(const Scene& scene, const std::vector<OverlayCell>& cells,
                         const ShadeOptions& options);

}  // namespace shadow::render
