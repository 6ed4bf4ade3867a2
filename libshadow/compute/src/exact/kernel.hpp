// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL types used inside the exact core. Include only from src/exact/*.cpp: CGAL must stay out
// of public headers (compile time, and users should not need CGAL to include libshadow).
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <glm/vec3.hpp>

#include <gmp.h>
#include <mpfr.h>

#include <iterator>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow::exact {

// Epeck: lazy exact rationals with interval filters. Boolean operations need exact
// constructions (double constructions give wrong areas or crash on shadow unions).
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = Kernel::FT;
using Point2 = Kernel::Point_2;
using Point3 = Kernel::Point_3;
using Vector3 = Kernel::Vector_3;
using Polygon2 = CGAL::Polygon_2<Kernel>;
using PolygonWithHoles2 = CGAL::Polygon_with_holes_2<Kernel>;
using PolygonSet2 = CGAL::Polygon_set_2<Kernel>;

/// An affine function f(p) = a.p + b on 3D points; its sign decides a half-space.
struct Affine3 {
  Vector3 a;
  FT b;
  [[nodiscard]] FT operator()(const Point3& p) const {
    return a.x() * p.x() + a.y() * p.y() + a.z() * p.z() + b;
  }
};

/// The sum of `terms` added as a balanced binary tree (`terms` is consumed). A running lazy sum
/// of n terms is a DAG n deep, and evaluating it exactly recurses n frames deep: a face of
/// 100,000 vertices overflowed the stack. Balanced, the depth is log2(n).
inline FT balanced_sum(std::vector<FT>& terms) {
  if (terms.empty()) return FT(0);
  for (std::size_t width = 1; width < terms.size(); width *= 2)
    for (std::size_t a = 0; a + width < terms.size(); a += 2 * width) terms[a] = terms[a] + terms[a + width];
  return terms[0];
}

/// Below this many vertices a polygon's area is summed one triangle after the other (CGAL's
/// own order: a DAG that deep is harmless, and no vector of terms is allocated); from it on, as
/// a balanced tree.
constexpr std::size_t kBalancedAreaFrom = 64;

/// Signed area (counter-clockwise positive) of the polygon through points [begin, end): the fan
/// of triangles from the first vertex (differences keep the interval filters tight), summed as
/// a balanced tree for long polygons (Polygon_2::area() sums one triangle after the other, and
/// evaluating such a sum exactly recursed 100,000 frames deep; see balanced_sum).
template <class It>
FT polygon_area(It begin, It end) {
  const auto n = static_cast<std::size_t>(std::distance(begin, end));
  if (n < 3) return FT(0);
  if (n < kBalancedAreaFrom) return CGAL::polygon_area_2(begin, end, Kernel());
  std::vector<FT> terms;
  terms.reserve(n - 2);
  const Point2& first = *begin;
  It b = std::next(begin);
  for (It c = std::next(b); c != end; ++b, ++c) terms.push_back(CGAL::area(first, *b, *c));
  return balanced_sum(terms);
}
inline FT polygon_area(const Polygon2& polygon) { return polygon_area(polygon.vertices_begin(), polygon.vertices_end()); }

namespace detail {
template <class Rational>
void rational_to_mpq(const Rational& q, mpq_t out) {
  if constexpr (std::is_same_v<Rational, mpq_class>) {
    mpq_set(out, q.get_mpq_t());
  } else {
    mpq_set(out, q.mpq());  // CGAL::Gmpq
  }
}
}  // namespace detail

/// Copies the exact rational value of an FT into `out` (mpq_t, initialised by the caller).
inline void exact_to_mpq(const FT& value, mpq_t out) { detail::rational_to_mpq(CGAL::exact(value), out); }

/// The double nearest to an exact rational (one correct rounding, ties to even).
inline double round_mpq_to_double(mpq_srcptr q) {
  mpfr_t r;
  mpfr_init2(r, 53);
  mpfr_set_q(r, q, MPFR_RNDN);
  const double d = mpfr_get_d(r, MPFR_RNDN);
  mpfr_clear(r);
  return d;
}

/// The double nearest to an exact value (one correct rounding, ties to even).
inline double round_to_double(const FT& value) {
  mpq_t q;
  mpq_init(q);
  exact_to_mpq(value, q);
  const double d = round_mpq_to_double(q);
  mpq_clear(q);
  return d;
}

/// The double nearest to an exact value (ties to even), as round_to_double, but without an exact
/// evaluation when the interval filter already pins the value to one double. CGAL::to_double
/// is not this: it returns the midpoint of the current interval, which depends on what was
/// evaluated before (and so on the thread that computed it). Zero comes back as +0.
inline double nearest_double(const FT& value) {
  const std::pair<double, double> i = CGAL::to_interval(value);
  if (i.first == i.second) return i.first + 0.0;
  return round_to_double(value);
}

/// A point's coordinates, each the double nearest to the exact one (nearest_double).
inline glm::dvec3 nearest_doubles(const Point3& p) {
  return {nearest_double(p.x()), nearest_double(p.y()), nearest_double(p.z())};
}

/// sqrt(value) for an exact non-negative rational, rounded to double. The rational is first
/// rounded to 256 bits, so the result is the correctly rounded root except in cases closer
/// than 2^-200 to a rounding boundary.
inline double sqrt_mpq_to_double(mpq_srcptr q) {
  mpfr_t r;
  mpfr_init2(r, 256);
  mpfr_set_q(r, q, MPFR_RNDN);
  mpfr_sqrt(r, r, MPFR_RNDN);
  const double d = mpfr_get_d(r, MPFR_RNDN);
  mpfr_clear(r);
  return d;
}
inline double sqrt_to_double(const FT& value) {
  mpq_t q;
  mpq_init(q);
  exact_to_mpq(value, q);
  const double d = sqrt_mpq_to_double(q);
  mpq_clear(q);
  return d;
}

}  // namespace shadow::exact
