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

/// det[next - corner, prev - corner, d] in number type N (differences and products in N).
template <class N>
N facing_determinant(const glm::dvec3& corner, const glm::dvec3& next, const glm::dvec3& prev, const glm::dvec3& d) {
  N u[3], v[3], w[3];
  for (int c = 0; c < 3; ++c) {
    u[c] = N(next[c]) - N(corner[c]);
    v[c] = N(prev[c]) - N(corner[c]);
    w[c] = N(d[c]);
  }
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/// Sign (-1, 0, 1) of det[next - corner, prev - corner, d], exactly.
inline int exact_facing_sign(const glm::dvec3& corner, const glm::dvec3& next, const glm::dvec3& prev,
                             const glm::dvec3& d) {
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const CGAL::Interval_nt<false> det = facing_determinant<CGAL::Interval_nt<false>>(corner, next, prev, d);
    if (det.inf() > 0) return 1;
    if (det.sup() < 0) return -1;
  }
  return sgn(facing_determinant<mpq_class>(corner, next, prev, d));
}

}  // namespace shadow::geometry
