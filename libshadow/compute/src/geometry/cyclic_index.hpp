// SPDX-License-Identifier: GPL-3.0-or-later
// The next vertex of a closed polygon without `%`: a 64-bit division costs tens of cycles, and the
// fast path's inner loops (the boundary union's edge against edge, the clips) took one per edge.
#pragma once

#include <cstddef>

namespace shadow::geometry {

/// (a + 1) % n for a < n: the index after a around a polygon of n vertices.
constexpr std::size_t cyclic_next(std::size_t a, std::size_t n) { return a + 1 == n ? 0 : a + 1; }

}  // namespace shadow::geometry
