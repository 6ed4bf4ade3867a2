// SPDX-License-Identifier: GPL-3.0-or-later
// Internal entry to the Blinn plane-shadow path with faces already prepared (the engine's).
#pragma once

#include "core/convex_solid.hpp"
#include "core/face_prep.hpp"

#include <shadow/shadows.hpp>

#include <cstddef>
#include <vector>

namespace shadow::planes {

/// How a plane-light pair's images are cut into tiles that are united on their own threads, and
/// whether convex solids cast as one. The defaults are the library's; the tests force small tiles
/// (and turn the solids off) to check that neither changes a result. Tiles depend on the images
/// only, never on the thread count.
struct Tiling {
  std::size_t tile_from = 2000;  ///< a pair with fewer images is united as one tile
  std::size_t per_tile = 600;    ///< otherwise about this many images a tile (at most 16 x 16 tiles)
  double tile_over_image = 10;   ///< tiles at least this many median image widths wide (0: any)
  bool solids = true;            ///< closed convex solids between the plane and the light cast as one
  bool shear = true;             ///< under a directional light, tiles are strips along the shadows
};

/// compute_plane_shadows with the faces' preparation and the closed convex solids given (see
/// core::FacePrep and exact::find_convex_solids; `solid_of[f]` is face f's solid or -1). A
/// solid wholly between a plane and the light casts on it as one convex polygon.
std::vector<PlaneShadow> plane_shadows(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                       const std::vector<core::ConvexSolid>& solids, const std::vector<int>& solid_of,
                                       const ShadowOptions& options, const Tiling& tiling = {});

/// shadow::compute_plane_shadows with the given tiling (faces prepared on options.threads).
std::vector<PlaneShadow> compute_plane_shadows(const Scene& scene, const ShadowOptions& options, const Tiling& tiling);

}  // namespace shadow::planes
