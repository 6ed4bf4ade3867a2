// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path (ShadowOptions::arithmetic = Arithmetic::Fast): one receiver under one light,
// with the exact engine's culling, the clipping and projection in doubles, and the union with
// Clipper on an integer grid fitted to the receiver's chart box. Every result carries a bound
// on its lit-area error; receivers where the double route is ill-conditioned are handed back to
// the exact engine. No CGAL and no Clipper types here: the engine includes this header.
#pragma once

#include "core/culling.hpp"
#include "core/face_prep.hpp"
#include "core/prepared_scene.hpp"
#include "core/tiles.hpp"
#include "fast/cluster_scratch.hpp"

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace shadow::fast {

/// What the computation reads from the prepared engine (all shared, read-only).

namespace receiver_job {
struct ReceiverScratch;  // fast/receiver_job.hpp (Clipper's types)
}
/// Deletes a receiver_job::ReceiverScratch (defined where that type is complete).
struct ReceiverScratchDelete {
  void operator()(receiver_job::ReceiverScratch* scratch) const noexcept;
};

/// Per-thread scratch state.
struct FastWorker {
  core::CasterCandidates casters;  ///< the same candidate casters as the exact engine's
  ClusterScratch cluster;          ///< the clustered union's vectors (fast/cluster_union.hpp)
  WindowClipScratch window;        ///< the clip to a convex receiver's vectors (fast/window_clip.hpp)
  /// The receiver job's vectors (casts, hulls, clips): receiver_scratch() makes them on first use.
  std::unique_ptr<receiver_job::ReceiverScratch, ReceiverScratchDelete> receiver;
  /// The receiver job's vectors (`receiver`), made on first use.
  receiver_job::ReceiverScratch& receiver_scratch();
};

/// What compute_receiver did with a receiver (or tile).
enum class Outcome {
  Done,   ///< computed: `out`, `fragments` and `stats` filled as below
  Exact,  ///< ill-conditioned in doubles: compute it exactly instead
  Split,  ///< too many casters (core::TileRequest::split_above): split it into tiles; nothing filled
};

/// Computes receiver `face_id` under `light` (see docs/numeric-contract.md, "The fast path"). On
/// Outcome::Done fills `out` (with lit_area_error_bound), appends the fragments (fragment_id
/// local to the receiver, from 0) when `polygons`, and adds to `stats`; on Outcome::Exact `stats`
/// is untouched, and `out` and `fragments` may hold partial results that the caller discards.
/// With tiles: computes `tiles.tile` of the face when set (its chart box
/// replaces the face's; fragments and areas are the tile's, `out.shadow_area` its shadow), or
/// asks for tiles (Outcome::Split, `split_candidates` set) when the face has more candidate
/// casters than `tiles.split_above`.
Outcome compute_receiver(const core::PreparedScene& context, FastWorker& worker, std::size_t face_id, std::size_t light_id,
                         const Light& light, const core::LightSpaceGrid* grid, bool polygons, FaceLighting& out,
                         std::vector<Fragment>& fragments, ShadowStats& stats, const core::TileRequest& tiles,
                         std::size_t& split_candidates);

}  // namespace shadow::fast
