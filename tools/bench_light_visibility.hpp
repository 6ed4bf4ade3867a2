// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench light-visibility: the exact visible fraction of extended lights at ground points
// of a generated city (bench_light_visibility.cpp).
#pragma once

#include <cstddef>

namespace bench {

/// Times light_visibility (and light_irradiance) for a sun disk, a disk and an area light over a
/// city of `boxes` boxes at `points` seeded ground points with each of `threads`; prints a table.
int run_light_visibility(std::size_t boxes, std::size_t points, unsigned threads);

}  // namespace bench
