// SPDX-License-Identifier: GPL-3.0-or-later
// What the engine prepares once per scene and every receiver computation reads (the exact one
// and the fast path alike): plain data, no CGAL types, shared read-only between threads.
#pragma once

#include "core/convex_solid.hpp"
#include "core/culling.hpp"
#include "core/face_prep.hpp"

#include <shadow/scene.hpp>

#include <optional>
#include <vector>

namespace shadow::core {

/// The prepared scene, as the per-receiver computations see it (all shared, read-only).
struct PreparedScene {
  const Scene* scene = nullptr;
  const std::vector<FacePrep>* prep = nullptr;
  const std::vector<double>* face_area = nullptr;  ///< exact face areas, rounded once
  const CullScene* cull = nullptr;
  const std::vector<ConvexSolid>* solids = nullptr;
  const std::vector<int>* solid_of = nullptr;
  /// The least set bit of every coordinate of the scene (all are integers times 2^this), when
  /// they span few enough bits for the exact areas route's integer charts
  /// (exact/scaled_chart.hpp); nullopt otherwise.
  std::optional<int> chart_least_bit;
};

}  // namespace shadow::core
