// SPDX-License-Identifier: GPL-3.0-or-later
// The exact sign of det[next - corner, prev - corner, d] for input doubles: whether direction d
// leaves a planar face's front or back side (or lies in its plane). On intervals first, in
// rationals only when they hold 0 (a wall edge-on to the sun). The exact engine and the fast path
// decide a face's facing under a directional light with it, so they agree to the last bit.
#pragma once

#include <CGAL/Interval_nt.h>
#include <gmpxx.h>
#include <glm/vec3.hpp>

namespace shadow::geometry {

/// Sign (-1, 0, 1) of det[next - corner, prev - corner, d], exactly.
inline int exact_facing_sign(const glm::dvec3& corner, const glm::dvec3& next, const glm::dvec3& prev,
                             const glm::dvec3& d) {
  {
    using IA = CGAL::Interval_nt<false>;
    CGAL::Protect_FPU_rounding<true> guard;
    IA u[3], v[3], w[3];
    for (int c = 0; c < 3; ++c) {
      u[c] = IA(next[c]) - IA(corner[c]);
      v[c] = IA(prev[c]) - IA(corner[c]);
      w[c] = IA(d[c]);
    }
    const IA det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                   u[2] * (v[0] * w[1] - v[1] * w[0]);
    if (det.inf() > 0) return 1;
    if (det.sup() < 0) return -1;
  }
  mpq_class u[3], v[3], w[3];
  for (int c = 0; c < 3; ++c) {
    u[c] = mpq_class(next[c]) - mpq_class(corner[c]);
    v[c] = mpq_class(prev[c]) - mpq_class(corner[c]);
    w[c] = mpq_class(d[c]);
  }
  const mpq_class det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                        u[2] * (v[0] * w[1] - v[1] * w[0]);
  return sgn(det);
}

}  // namespace shadow::geometry
