// SPDX-License-Identifier: GPL-3.0-or-later
// Exact shadows on planes through Blinn's projection matrix.
//
// For a plane p = (n, c) and a light l, a point of the plane is in shadow when its segment to the
// light meets a face strictly on the light's side of the plane. Every caster is clipped to that
// side (s = p.(x, 1) > 0 once p is turned toward the light) and to the prism or pyramid from the
// light over a square window on the plane (a point light at the height of some geometry casts a
// shadow without end), then mapped by the exact rational matrix M = (p.l) I - l p^T with the
// homogeneous divide, and the images are united exactly.
//
// A caster is a face's convex piece, or a whole closed convex solid (a box) when all of it lies
// between the plane and the light: it then casts the convex hull of its projected vertices.
// Casters are projected in parallel (plain GMP rationals, which threads may share for reading);
// the images are then cut along a grid of tiles fixed by the images alone (never by the thread
// count), each tile is united on its own thread, and the tiles' regions are joined back by
// their shared border edges. Under a directional light the images are united in the chart
// sheared along the shadows, so that tiles are strips that long shadows seldom cross. See
// docs/algorithm.md, "Shadows on planes (Blinn)".
//
// This path shares no clipping or projection code with the per-face engine on purpose: a face
// lying in a plane must come out of both with the same shadow, and the tests check that. It
// shares only the search for convex solids (exact/convex_solids.hpp).
#include "planes/plane_steps.hpp"
#include "geometry/box_sides.hpp"
#include "geometry/clip_convex.hpp"
#include "core/culling.hpp"
#include "exact/convex_solids.hpp"
#include "exact/exact_faces.hpp"
#include "runtime/parallel.hpp"
#include "planes/plane_shadows.hpp"
#include "exact/regions.hpp"
#include "core/input_checks.hpp"
#include "core/lights.hpp"

#include <shadow/validation.hpp>
#include <shadow/shadows.hpp>

#include <CGAL/Interval_nt.h>
#include <CGAL/version.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow {
namespace planes {
namespace {

/// Units of this many casters are one work item of the projection phase.
constexpr std::size_t kUnitsPerItem = 128;

}  // namespace
}  // namespace planes

namespace planes {

using namespace steps;


std::vector<PlaneShadow> plane_shadows(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                       const std::vector<core::ConvexSolid>& solids, const std::vector<int>& solid_of,
                                       const ShadowOptions& options, const Tiling& tiling) {
  const std::vector<std::size_t> light_ids = shadow::detail::resolve_lights(scene, options.lights);
  const unsigned threads = runtime::resolve_threads(runtime::checked_threads(options.threads));
  if (!(options.plane_window >= 0 && options.plane_window <= max_coordinate))
    throw InputError({"", "ShadowOptions::plane_window"},
                     "must be in [0, 2^500 (about 3.27e150)], got " + shadow::detail::format_number(options.plane_window));
  if (scene.planes.empty() || light_ids.empty()) return {};

  const core::SceneFrame frame = core::scene_frame(scene);
  const double window = options.plane_window > 0 ? options.plane_window : 10.0 * frame.diagonal;
  for (std::size_t plane_id = 0; plane_id < scene.planes.size(); ++plane_id) {
    const double own = scene.planes[plane_id].window > 0 ? scene.planes[plane_id].window : window;
    // The window's corners must be finite numbers to become exact rationals.
    const glm::dvec3 lo = frame.centre - own, hi = frame.centre + own;
    if (!std::isfinite(own) || !std::isfinite(lo.x + lo.y + lo.z) || !std::isfinite(hi.x + hi.y + hi.z))
      throw InputError({"", "planes[" + std::to_string(plane_id) + "].window"},
                       "the plane-shadow window is too large to represent (" + std::to_string(own) + ")");
  }

  // What casts, in face order: a solid at its first face, every other face on its own.
  std::vector<std::vector<std::size_t>> solid_faces(solids.size());
  std::vector<Unit> units;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const int s = tiling.solids && f < solid_of.size() ? solid_of[f] : -1;
    if (s < 0) {
      units.push_back({-1, f});
      continue;
    }
    std::vector<std::size_t>& faces = solid_faces[static_cast<std::size_t>(s)];
    if (faces.empty()) units.push_back({s, f});
    faces.push_back(f);
  }

  const std::size_t pair_count = scene.planes.size() * light_ids.size();
  std::vector<Pair> pairs(pair_count);
  for (std::size_t item = 0; item < pair_count; ++item) {
    const std::size_t plane_id = item / light_ids.size();
    const double own = scene.planes[plane_id].window;
    pairs[item] = make_pair(scene, plane_id, light_ids[item % light_ids.size()], frame, own > 0 ? own : window, tiling.shear);
  }

  // Projection: every pair's casters in chunks of units, all on the same workers.
  const std::size_t chunks = (units.size() + kUnitsPerItem - 1) / kUnitsPerItem;
  std::vector<std::vector<Image>> chunk_images(pair_count * chunks);
  std::vector<char> chunk_reaches(pair_count * chunks, 0);
  runtime::parallel_for(pair_count * chunks, threads, [&](unsigned, std::size_t item) {
    const Pair& P = pairs[item / chunks];
    if (!P.casts) return;
    const std::size_t first = (item % chunks) * kUnitsPerItem;
    bool reaches = false;
    cast_units(scene, prep, solids, solid_faces, units, first, std::min(units.size(), first + kUnitsPerItem), P,
               chunk_images[item], reaches);
    chunk_reaches[item] = reaches;
  });

  // Tiles: a grid fixed by each pair's images; each image goes to the tiles its box meets.
  std::vector<std::vector<Image>> images(pair_count);
  std::vector<Grid> grids(pair_count);
  std::vector<std::vector<std::vector<std::size_t>>> members(pair_count);
  std::vector<std::pair<std::size_t, std::size_t>> tile_items;  // (pair, tile)
  std::vector<PlaneShadow> shadows(pair_count);
  for (std::size_t a = 0; a < pair_count; ++a) {
    PlaneShadow& out = shadows[a];
    out.plane_id = pairs[a].plane_id;
    out.light_id = pairs[a].light_id;
    out.window_half_size = pairs[a].window;
    for (std::size_t c = 0; c < chunks; ++c) {
      std::vector<Image>& part = chunk_images[a * chunks + c];
      out.reaches_window |= chunk_reaches[a * chunks + c] != 0;
      for (Image& image : part) images[a].push_back(std::move(image));
      part = {};
    }
    grids[a] = make_grid(images[a], tiling);
    const Grid& grid = grids[a];
    members[a].resize(grid.tiles());
    for (std::size_t m = 0; m < images[a].size(); ++m) {
      const std::array<double, 4>& box = images[a][m].box;
      std::size_t first[2], last[2];  // the columns and rows the box meets (closed bounds)
      for (int axis = 0; axis < 2; ++axis) {
        const std::vector<double>& cuts = grid.cuts[axis];
        first[axis] = static_cast<std::size_t>(std::lower_bound(cuts.begin(), cuts.end(), box[axis]) - cuts.begin());
        last[axis] = static_cast<std::size_t>(std::upper_bound(cuts.begin(), cuts.end(), box[axis + 2]) - cuts.begin());
      }
      for (std::size_t row = first[1]; row <= last[1]; ++row)
        for (std::size_t column = first[0]; column <= last[0]; ++column) members[a][row * grid.columns() + column].push_back(m);
    }
    for (std::size_t t = 0; t < grid.tiles(); ++t)
      if (!members[a][t].empty()) tile_items.emplace_back(a, t);
  }

  // Unions: every pair's tiles on the same workers, the tiles with the most images first (the
  // workers take items in order: a large tile taken last would leave the others idle). Each
  // tile writes its own result, so the order changes no result.
  std::stable_sort(tile_items.begin(), tile_items.end(), [&](const auto& x, const auto& y) {
    return members[x.first][x.second].size() > members[y.first][y.second].size();
  });
  std::vector<std::vector<TileResult>> tiles(pair_count);
  for (std::size_t a = 0; a < pair_count; ++a) tiles[a].resize(grids[a].tiles());
  runtime::parallel_for(tile_items.size(), threads, [&](unsigned, std::size_t item) {
    const auto [a, t] = tile_items[item];
    unite_tile(scene, pairs[a], images[a], grids[a], members[a][t], t, tiles[a][t]);
  });
  for (std::size_t a = 0; a < pair_count; ++a)
    if (pairs[a].casts) assemble(pairs[a], tiles[a], shadows[a]);
  return shadows;
}

}  // namespace planes

std::vector<PlaneShadow> planes::compute_plane_shadows(const Scene& scene, const ShadowOptions& options,
                                                       const Tiling& tiling) {
  shadow::detail::check_scene_numbers(scene);  // the scene may never have been validated
  const unsigned threads = runtime::resolve_threads(runtime::checked_threads(options.threads));
  std::vector<core::FacePrep> prep(scene.faces.size());
  runtime::parallel_for_blocks(scene.faces.size(), runtime::block_of(scene.faces.size(), threads), threads,
                               [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      if (scene.faces[f].degenerate || scene.faces[f].vertices.size() < 3) prep[f].degenerate = true;
      else prep[f] = exact::prepare_face(scene.faces[f].vertices);
    }
  });
  std::vector<int> solid_of;
  const std::vector<core::ConvexSolid> solids = exact::find_convex_solids(scene, prep, solid_of, threads);
  return planes::plane_shadows(scene, prep, solids, solid_of, options, tiling);
}

std::vector<PlaneShadow> compute_plane_shadows(const Scene& scene, const ShadowOptions& options) {
  // Nothing counted: 0 of 0, about every 100 ms, so that the callback can stop the call.
  const runtime::TickScope ticks(options.progress ? std::function<void()>([&] { options.progress(Progress{0, 0}); })
                                               : std::function<void()>());
  return planes::compute_plane_shadows(scene, options, planes::Tiling{});
}

}  // namespace shadow
