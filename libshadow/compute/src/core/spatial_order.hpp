// SPDX-License-Identifier: GPL-3.0-or-later
// The order in which receivers are computed: along a space-filling curve through the scene, so
// that consecutive receivers have nearly the same casters. A scene's faces come in whatever
// order its files list them (a generated or exported city: its buildings in no spatial order);
// taken in that order, every receiver's grid query and culling read casters' faces, vertices and
// boxes that the receivers before it did not, and a million faces' culling waited on memory for
// most of its time. The order changes no result: each receiver is computed on its own.
#pragma once

#include "core/convex_solid.hpp"
#include "core/cull_scene.hpp"
#include "runtime/parallel.hpp"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace shadow::core {

/// The Morton code of a point of the local frame (CullScene's: the scene's box centred on the
/// origin, its diagonal `diameter`, so every coordinate within half of it), 21 bits an axis:
/// close codes are close points, mostly. A coordinate out of that reach is clamped to its end;
/// one that is not finite counts as the lower end.
inline std::uint64_t morton_code(const glm::dvec3& p, double diameter) {
  auto spread = [](std::uint64_t x) {  // 21 bits to every third of 63
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
  };
  constexpr double kCells = 1 << 21;
  std::uint64_t code = 0;
  for (int a = 0; a < 3; ++a) {
    const double t = (p[a] / diameter + 0.5) * kCells;  // [-D/2, D/2] onto [0, 2^21)
    const std::uint64_t q = std::isfinite(t) ? static_cast<std::uint64_t>(std::clamp(t, 0.0, kCells - 1)) : 0;
    code |= spread(q) << a;
  }
  return code;
}

/// A permutation of `count` receivers (face_of(r) their faces) along the Morton curve of their
/// places: a face's first vertex, or for a face of a convex solid (solid_of), the solid's first
/// vertex, so that a solid's faces stay together. The codes' top 32 bits (10 of x, 11 of y and
/// z: cells of a 1,024th and a 2,048th of the scene's diagonal) are sorted, stably: a solid's
/// faces, and any faces in one cell, keep their order. The places on `threads` threads; the
/// order does not depend on them. More rows than 32 bits number: the given order.
template <class FaceOf>
std::vector<std::size_t> spatial_order(const CullScene& cull, const std::vector<int>& solid_of,
                                       const std::vector<ConvexSolid>& solids, std::size_t count, FaceOf&& face_of,
                                       unsigned threads = 1) {
  std::vector<std::size_t> order(count);
  if (count > UINT32_MAX) {  // (rows would not fit below the codes)
    for (std::size_t r = 0; r < count; ++r) order[r] = r;
    return order;
  }
  // Each row's code above its index.
  std::vector<std::uint64_t> keyed(count);
  runtime::parallel_for_blocks(count, 16384, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r) {
      const std::size_t f = face_of(r);
      const int s = f < solid_of.size() ? solid_of[f] : -1;
      glm::dvec3 p(0.0);
      if (s >= 0 && !solids[static_cast<std::size_t>(s)].vertices.empty())
        p = solids[static_cast<std::size_t>(s)].vertices.front() - cull.origin;
      else if (cull.faces[f].count > 0)
        p = cull.vertices[cull.faces[f].first];
      keyed[r] = (morton_code(p, cull.diameter) >> 31) << 32 | static_cast<std::uint64_t>(r);
    }
  });
  if (count < 4096) {
    std::sort(keyed.begin(), keyed.end());  // (code, row): stable by construction
  } else {
    // Two stable passes over the code's 16-bit halves (the low one first): O(count), where a
    // comparison sort of a million faces took a tenth of a second.
    std::vector<std::uint64_t> scratch(count);
    std::vector<std::size_t> start(65537);
    for (int shift = 32; shift < 64; shift += 16) {
      std::fill(start.begin(), start.end(), 0);
      for (const std::uint64_t k : keyed) ++start[((k >> shift) & 0xffff) + 1];
      for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
      for (const std::uint64_t k : keyed) scratch[start[(k >> shift) & 0xffff]++] = k;
      keyed.swap(scratch);
    }
  }
  for (std::size_t i = 0; i < count; ++i) order[i] = static_cast<std::size_t>(keyed[i] & 0xffffffffULL);
  return order;
}

}  // namespace shadow::core
