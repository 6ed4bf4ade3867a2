// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench light-visibility: the exact visible fraction of extended lights at ground points
// of a generated city (bench_light_visibility.cpp).
#pragma once

#include <cstddef>

namespace bench {

/// Times light_visibility (and light_irradiance) for a sun disk, a disk and an area light over a
/// city of `boxes` boxes at `points` seeded ground points with each of `threads`; prints a table.
int run_light_visibility(std::size_t boxes, std::size_t points, unsigned threads);

/// Times ShadowEngine::compute for a city of `boxes` boxes under a sun disk of `diameter` degrees
/// (35 degrees up), on `threads` threads: the whole (regions and fragment visibility) and the
/// fragment visibility alone (fill_fragment_visibility on the same fragments), the regions being
/// the rest; prints them with a checksum of every output value (to compare two builds).
int run_area_city(std::size_t boxes, double diameter, unsigned threads);

}  // namespace bench
