// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: what ShadowEngine prepares once per scene, shared by engine/shadow_engine.cpp
// (one light at a time) and engine/series.cpp (many suns together).
#pragma once

#include "core/culling.hpp"
#include "core/convex_solid.hpp"
#include "core/face_prep.hpp"
#include "exact/exact_receiver.hpp"
#include "exact/lazy_geometry.hpp"
#include "fast/fast_receiver.hpp"

#include <shadow/shadows.hpp>

#include <memory>
#include <vector>

namespace shadow {

struct ShadowEngine::Impl {
  const Scene* scene = nullptr;
  std::vector<core::FacePrep> prep;
  std::vector<double> face_area;
  core::CullScene cull;

  std::vector<core::ConvexSolid> solids;
  std::vector<int> solid_of;  ///< per face: index into solids, or -1

  /// Per-thread state: the exact engine's and the fast path's, and the counts of both.
  struct Worker {
    exact::ExactWorker exact;  // Epeck objects are never shared between threads
    fast::Worker fast;         // Arithmetic::Fast: the fast path's scratch state
    ShadowStats stats;
  };

  /// Result for one receiving face under one light (fragment_id local to the item).
  using Item = exact::ReceiverResult;

  void compute_light(const Light& light, std::size_t light_id, const ShadowOptions& options,
                     std::vector<Worker>& workers, const std::vector<std::size_t>& receivers,
                     std::vector<Item>& items, std::size_t progress_base, std::size_t progress_total) const;

  /// compute_light for an extended light (Light::is_extended): the centre's lit areas, then the
  /// exact fully-lit, penumbra and umbra regions (arealight/).
  void compute_extended_light(const Light& light, std::size_t light_id, const ShadowOptions& options,
                              std::vector<Worker>& workers, const std::vector<std::size_t>& receivers,
                              std::vector<Item>& items, std::size_t progress_base, std::size_t progress_total) const;

  /// Computes `lights` (reported as `light_ids`) on every receiving face.
  ShadowResult run(const std::vector<const Light*>& lights, const std::vector<std::size_t>& light_ids,
                   const ShadowOptions& options) const;

  static ShadowResult assemble(std::vector<std::vector<Item>>& per_light,
                               const std::vector<Worker>& workers);
};

namespace engine_detail {

/// The exact form of a light: a point (w = 1) or a direction at infinity (w = 0).
using exact::to_exact_light;  // exact/lazy_geometry.hpp

/// The exact sign of receiver f's plane at the light (its facing): 0 for a degenerate face; one
/// determinant of the input doubles for an exactly planar face under a directional light (no
/// exact face built: half the receivers of a sun face away from it); else from its exact face.
inline int receiver_side(const core::PreparedScene& ctx, exact::ExactWorker& w, std::size_t f, const Light& light_in,
                         const exact::ExactLight& light) {
  const core::FacePrep& fp = (*ctx.prep)[f];
  if (fp.degenerate) return 0;
  if (fp.exactly_planar && light_in.type == LightType::Directional)
    return exact::directional_facing_sign(ctx.scene->faces[f].vertices, fp, light_in.to_light);
  return CGAL::sign(exact::plane_at_light(w.face(ctx, f), light));
}

}  // namespace engine_detail
}  // namespace shadow
