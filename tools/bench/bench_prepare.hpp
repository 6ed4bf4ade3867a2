// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench prepare: what precedes the per-sun work on a generated city, validation and the
// convex-solid search, against the reference implementations they replaced (bench_prepare.cpp).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace bench {

/// For each city size (make_city(boxes, 500 sqrt(boxes / 1000), 2026), as `shadow-bench
/// low-sun` builds it) and each thread count: validate_scene against
/// detail::validate_scene_reference, and exact::find_convex_solids against
/// exact::find_convex_solids_reference, side by side in one process, the fastest of `repeat`
/// runs each; checks that each pair's outcomes are identical. Prints a table; 1 on a difference.
/// `new_only`: leave the references out (to profile the new code alone; nothing is compared).
int run_prepare(const std::vector<std::size_t>& sizes, const std::vector<unsigned>& threads, int repeat, bool new_only);

/// Writes the same city (a `sun` at `elevation`, azimuth 135) as `DIR/scene.json` with its
/// meshes in `DIR/ground.obj` and `DIR/buildings.obj`, for timing `shadow compute` as a whole
/// process (load, validation, preparation, compute, files). `ground_only`: only the ground
/// receives (`"receivers": ["ground"]`).
int write_city(std::size_t boxes, double elevation, bool ground_only, const std::string& dir);

}  // namespace bench
