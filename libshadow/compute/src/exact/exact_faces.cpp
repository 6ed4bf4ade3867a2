// SPDX-License-Identifier: GPL-3.0-or-later
// Exact face preparation: planes, charts, convex pieces, and the exact checks of validation.
#include "exact/exact_faces.hpp"

#include "exact/face_shape.hpp"
#include "exact/fixed_width.hpp"
#include "core/polygon_holes.hpp"
#include "geometry/newell_normal.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <cstdint>
#include <optional>

#include <gmpxx.h>

namespace shadow::exact {
namespace {

/// 2 x the signed area vector of a closed polygon (Newell's method), exact.
Vector3 exact_newell_normal(const std::vector<Point3>& p) {
  const std::size_t n = p.size();
  std::vector<FT> nx, ny, nz;  // summed as balanced trees: shallow lazy DAGs for any n
  nx.reserve(n);
  ny.reserve(n);
  nz.reserve(n);
  for (std::size_t a = 0; a < n; ++a) {
    const Point3& u = p[a];
    const Point3& v = p[(a + 1) % n];
    std::array<FT, 3> term = geometry::newell_term(u.x(), u.y(), u.z(), v.x(), v.y(), v.z());
    nx.push_back(std::move(term[0]));
    ny.push_back(std::move(term[1]));
    nz.push_back(std::move(term[2]));
  }
  return Vector3(balanced_sum(nx), balanced_sum(ny), balanced_sum(nz));
}

int dominant_axis(const Vector3& n) {
  const FT ax = CGAL::abs(n.x()), ay = CGAL::abs(n.y()), az = CGAL::abs(n.z());
  if (ax >= ay && ax >= az) return 0;
  if (ay >= az) return 1;
  return 2;
}

std::vector<Point3> exact_points(const std::vector<glm::dvec3>& vertices) {
  std::vector<Point3> points;
  points.reserve(vertices.size());
  for (const glm::dvec3& v : vertices) points.push_back(to_exact(v));
  return points;
}

/// Removes vertices exactly collinear with their neighbours, repeatedly, so that every
/// remaining vertex is a real turn (the faces are simple: validated before). A linked ring and
/// a work list: each removal re-examines only its two neighbours, so O(n) tests in all.
template <class Point>
std::vector<int> drop_collinear(const std::vector<int>& ring, const std::vector<Point>& chart) {
  const std::size_t n = ring.size();
  if (n < 3) return ring;
  std::vector<std::size_t> prev(n), next(n), work(n);
  std::vector<char> removed(n, 0);
  for (std::size_t a = 0; a < n; ++a) {
    prev[a] = (a + n - 1) % n;
    next[a] = (a + 1) % n;
    work[a] = n - 1 - a;  // popped in ring order
  }
  std::size_t left = n;
  while (!work.empty() && left >= 3) {
    const std::size_t a = work.back();
    work.pop_back();
    if (removed[a]) continue;
    // On a simple polygon a collinear vertex is "straight on": it adds no area.
    if (!CGAL::collinear(chart[ring[prev[a]]], chart[ring[a]], chart[ring[next[a]]])) continue;
    removed[a] = 1;
    --left;
    next[prev[a]] = next[a];
    prev[next[a]] = prev[a];
    work.push_back(next[a]);
    work.push_back(prev[a]);
  }
  std::vector<int> out;
  for (std::size_t a = 0; a < n; ++a)
    if (!removed[a]) out.push_back(ring[a]);
  return out;
}

/// Convex pieces of a simple polygon (indices into `chart`, counter-clockwise, no collinear
/// vertices) that tile it, by Hertel-Mehlhorn over a constrained Delaunay triangulation
/// (core::convex_pieces, shared with polygons with holes), not CGAL's approx_convex_partition_2,
/// whose non-Delaunay constrained triangulation is quadratic on combs (docs/benchmarks.md).
template <class K>
std::vector<std::vector<int>> convex_partition(const std::vector<int>& ring, const std::vector<typename K::Point_2>& chart) {
  const std::size_t n = ring.size();
  std::vector<std::array<double, 2>> points(n);
  std::vector<int> next(n), prev(n);
  for (std::size_t a = 0; a < n; ++a) {
    points[a] = {CGAL::to_double(chart[ring[a]].x()), CGAL::to_double(chart[ring[a]].y())};
    next[a] = static_cast<int>((a + 1) % n);
    prev[a] = static_cast<int>((a + n - 1) % n);
  }
  std::vector<std::vector<int>> pieces = core::convex_pieces(points, next, prev, true);
  for (std::vector<int>& piece : pieces)
    for (int& v : piece) v = ring[static_cast<std::size_t>(v)];
  return pieces;
}

template <class Point>
bool is_strictly_convex_ccw(const std::vector<int>& ring, const std::vector<Point>& chart) {
  const std::size_t n = ring.size();
  for (std::size_t a = 0; a < n; ++a) {
    if (CGAL::orientation(chart[ring[a]], chart[ring[(a + 1) % n]], chart[ring[(a + 2) % n]]) !=
        CGAL::LEFT_TURN)
      return false;
  }
  return true;
}

}  // namespace

core::FacePrep prepare_face(const std::vector<glm::dvec3>& vertices) {
  // Everything here is decided with Epick's exact predicates on the input doubles (static and
  // interval filters, then an exact fallback): far cheaper than Epeck's lazy constructions,
  // which would have to evaluate exactly every test that comes out zero (planarity tests do).
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  core::FacePrep prep;
  const std::size_t count = vertices.size();
  const glm::dvec3 newell = geometry::newell_normal(vertices, vertices[0]);
  // The dominant axis only needs to be a good chart direction, not exact: its component is at
  // least |n| / sqrt(3), far above rounding error for any face validation accepts.
  const glm::dvec3 an = glm::abs(newell);
  int k = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
  if (!(an[k] > 0) || !std::isfinite(an[k])) {
    // Under- or overflow (coordinates beyond 1e+-150): decide exactly.
    const Vector3 exact_normal = exact_newell_normal(exact_points(vertices));
    if (exact_normal == CGAL::NULL_VECTOR) {
      prep.degenerate = true;
      return prep;
    }
    k = dominant_axis(exact_normal);
  }
  prep.axis = k;
  const int i = core::chart_i(k), j = core::chart_j(k);
  std::vector<K::Point_2> chart;
  chart.reserve(count);
  for (const glm::dvec3& v : vertices) chart.emplace_back(v[i], v[j]);

  std::vector<int> ring(count);
  for (std::size_t a = 0; a < count; ++a) ring[a] = static_cast<int>(a);
  ring = drop_collinear(ring, chart);
  if (ring.size() < 3) {
    prep.degenerate = true;
    return prep;
  }
  // The lexicographically smallest vertex of a simple polygon is a strict convex corner: its
  // turn gives the polygon's orientation in the chart, i.e. the exact sign of n_k.
  std::size_t n = ring.size();
  std::size_t lowest = 0;
  for (std::size_t a = 1; a < n; ++a)
    if (CGAL::compare_xy(chart[ring[a]], chart[ring[lowest]]) == CGAL::SMALLER) lowest = a;
  const CGAL::Orientation turn =
      CGAL::orientation(chart[ring[(lowest + n - 1) % n]], chart[ring[lowest]], chart[ring[(lowest + 1) % n]]);
  prep.flipped = turn == CGAL::RIGHT_TURN;
  if (prep.flipped) {
    std::reverse(ring.begin(), ring.end());
    lowest = n - 1 - lowest;
  }
  prep.chart_ring = ring;
  prep.corner = {ring[(lowest + n - 1) % n], ring[lowest], ring[(lowest + 1) % n]};

  auto point3 = [&](int v) { return K::Point_3(vertices[v].x, vertices[v].y, vertices[v].z); };
  const K::Point_3 c0 = point3(prep.corner[1]), c1 = point3(prep.corner[2]), c2 = point3(prep.corner[0]);
  prep.exactly_planar = true;
  for (std::size_t v = 0; v < count && prep.exactly_planar; ++v)
    prep.exactly_planar = CGAL::orientation(c0, c1, c2, point3(static_cast<int>(v))) == CGAL::COPLANAR;

  // Chart bounding box: chart coordinates are input doubles, so this box is exact.
  prep.chart_min = {vertices[ring[0]][i], vertices[ring[0]][j]};
  prep.chart_max = prep.chart_min;
  for (int v : ring) {
    prep.chart_min[0] = std::min(prep.chart_min[0], vertices[v][i]);
    prep.chart_min[1] = std::min(prep.chart_min[1], vertices[v][j]);
    prep.chart_max[0] = std::max(prep.chart_max[0], vertices[v][i]);
    prep.chart_max[1] = std::max(prep.chart_max[1], vertices[v][j]);
  }
  if (n == 4) {
    prep.chart_is_box = std::all_of(ring.begin(), ring.end(), [&](int v) {
      const bool on_x = vertices[v][i] == prep.chart_min[0] || vertices[v][i] == prep.chart_max[0];
      const bool on_y = vertices[v][j] == prep.chart_min[1] || vertices[v][j] == prep.chart_max[1];
      return on_x && on_y;
    });
  }

  if (is_strictly_convex_ccw(ring, chart)) {
    prep.convex_pieces.push_back(ring);
  } else {
    // Hertel-Mehlhorn partition: diagonals only, so pieces reuse the face's own vertices.
    prep.convex_pieces = convex_partition<K>(ring, chart);
  }
  return prep;
}

ExactFace make_exact_face(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep) {
  ExactFace face;
  const int k = prep.axis;
  face.vertices = exact_points(vertices);
  if (prep.exactly_planar) {
    const auto [prev, corner, next] = prep.corner;
    // Counter-clockwise in the chart: this cross product has a positive k component.
    Vector3 n = CGAL::cross_product(face.vertices[next] - face.vertices[corner],
                                    face.vertices[prev] - face.vertices[corner]);
    face.normal = prep.flipped ? -n : n;
    face.offset = -(face.normal * (face.vertices[corner] - CGAL::ORIGIN));
  } else {
    // Within the planarity tolerance but not exact: use the plane through the centroid with
    // the Newell normal and lift every vertex onto it along the chart axis. The chart
    // coordinates stay the input doubles (docs/numeric-contract.md).
    face.normal = exact_newell_normal(face.vertices);
    std::vector<FT> xs, ys, zs;
    for (const Point3& p : face.vertices) {
      xs.push_back(p.x());
      ys.push_back(p.y());
      zs.push_back(p.z());
    }
    const FT sx = balanced_sum(xs), sy = balanced_sum(ys), sz = balanced_sum(zs);
    const FT count = static_cast<int>(face.vertices.size());
    face.offset = -(face.normal.x() * sx + face.normal.y() * sy + face.normal.z() * sz) / count;
    for (Point3& p : face.vertices) p = lift(to_chart(p, k), face, k);
  }
  for (int v : prep.chart_ring) face.chart.push_back(to_chart(face.vertices[v], k));
  if (prep.convex_pieces.size() > 1 && prep.convex_pieces.size() <= kMaxChartPiecesToClip) {
    for (const std::vector<int>& piece : prep.convex_pieces) {
      Polygon2& polygon = face.chart_pieces.emplace_back();
      for (int v : piece) polygon.push_back(to_chart(face.vertices[v], k));
      face.chart_piece_boxes.push_back(polygon.bbox());
    }
  }
  face.chart_area = polygon_area(face.chart);
  const FT nk = face.normal[k];
  face.area_scale_squared = face.normal.squared_length() / (nk * nk);
  return face;
}

Point3 lift(const Point2& c, const ExactFace& face, int k) {
  const int i = core::chart_i(k), j = core::chart_j(k);
  const FT xk = -(face.offset + face.normal[i] * c.x() + face.normal[j] * c.y()) / face.normal[k];
  FT xyz[3];
  xyz[i] = c.x();
  xyz[j] = c.y();
  xyz[k] = xk;
  return Point3(xyz[0], xyz[1], xyz[2]);
}

double area_3d(const FT& chart_area, const FT& area_scale_squared) {
  if (CGAL::is_zero(chart_area)) return 0.0;
  return sqrt_to_double(chart_area * chart_area * area_scale_squared);
}

double area_3d_exact(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
                     FT::Exact_type& scratch) {
  if (sgn(chart_area) == 0) return 0.0;
  if (mpq_cmp_ui(area_scale_squared.get_mpq_t(), 1, 1) == 0) {  // an axis-plane face: |A|, no root
    mpq_abs(scratch.get_mpq_t(), chart_area.get_mpq_t());
    return round_mpq_to_double(scratch.get_mpq_t());
  }
  scratch = chart_area * chart_area;
  scratch *= area_scale_squared;
  return sqrt_mpq_to_double(scratch.get_mpq_t());
}

void measure_lit_and_shadow(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
                            const FT::Exact_type& shadow_chart_area, FT::Exact_type& lit,
                            FT::Exact_type& scratch, FaceLighting& out) {
  lit = chart_area - shadow_chart_area;
  out.lit_area = area_3d_exact(lit, area_scale_squared, scratch);
  out.shadow_area = area_3d_exact(shadow_chart_area, area_scale_squared, scratch);
  scratch = lit / chart_area;
  out.lit_fraction = round_mpq_to_double(scratch.get_mpq_t());
}

EnclosedMeasure::EnclosedMeasure() {
  for (mpfr_ptr x : {s_lo_, s_hi_, l_lo_, l_hi_, t_lo_, t_hi_}) mpfr_init2(x, kBits);
}

EnclosedMeasure::~EnclosedMeasure() {
  for (mpfr_ptr x : {s_lo_, s_hi_, l_lo_, l_hi_, t_lo_, t_hi_}) mpfr_clear(x);
}

void EnclosedMeasure::swap(EnclosedMeasure& other) noexcept {
  mpfr_swap(s_lo_, other.s_lo_);
  mpfr_swap(s_hi_, other.s_hi_);
  mpfr_swap(l_lo_, other.l_lo_);
  mpfr_swap(l_hi_, other.l_hi_);
  mpfr_swap(t_lo_, other.t_lo_);
  mpfr_swap(t_hi_, other.t_hi_);
}

bool EnclosedMeasure::measure(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
                              const FT::Exact_type& twice_lo, std::size_t slack, int slack_bits,
                              const FT::Exact_type* scale, FaceLighting& out) {
  if (sgn(chart_area) <= 0 || sgn(area_scale_squared) <= 0 || (scale && sgn(*scale) <= 0)) return false;
  // The shadow's chart area in [s_lo, s_hi]: every step rounded outward (down for the lower
  // end, up for the upper; all values positive, so dividing keeps the directions).
  mpfr_set_q(s_lo_, twice_lo.get_mpq_t(), MPFR_RNDD);
  mpfr_set_q(s_hi_, twice_lo.get_mpq_t(), MPFR_RNDU);
  if (slack > 0) {
    mpfr_set_ui_2exp(t_hi_, static_cast<unsigned long>(slack), -slack_bits, MPFR_RNDU);
    mpfr_add(s_hi_, s_hi_, t_hi_, MPFR_RNDU);
  }
  mpfr_div_2ui(s_lo_, s_lo_, 1, MPFR_RNDD);  // (exact)
  mpfr_div_2ui(s_hi_, s_hi_, 1, MPFR_RNDU);
  if (mpfr_sgn(s_lo_) <= 0) return false;
  if (scale) {
    for (int twice = 0; twice < 2; ++twice) {
      mpfr_div_q(s_lo_, s_lo_, scale->get_mpq_t(), MPFR_RNDD);
      mpfr_div_q(s_hi_, s_hi_, scale->get_mpq_t(), MPFR_RNDU);
    }
  }
  return pin(chart_area, area_scale_squared, out);
}

bool EnclosedMeasure::measure_between(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
                                      const FT::Exact_type& shadow_lo, const FT::Exact_type& width,
                                      FaceLighting& out) {
  if (sgn(chart_area) <= 0 || sgn(area_scale_squared) <= 0 || sgn(width) < 0) return false;
  mpfr_set_q(s_lo_, shadow_lo.get_mpq_t(), MPFR_RNDD);
  mpfr_set_q(s_hi_, shadow_lo.get_mpq_t(), MPFR_RNDU);
  mpfr_set_q(t_hi_, width.get_mpq_t(), MPFR_RNDU);
  mpfr_add(s_hi_, s_hi_, t_hi_, MPFR_RNDU);
  if (mpfr_sgn(s_lo_) <= 0) return false;
  return pin(chart_area, area_scale_squared, out);
}

bool EnclosedMeasure::pin(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
                          FaceLighting& out) {
  // The lit part, chart - shadow, in [l_lo, l_hi]: (s_hi - chart) rounded up, negated, is
  // (chart - s_hi) rounded down.
  mpfr_sub_q(l_lo_, s_hi_, chart_area.get_mpq_t(), MPFR_RNDU);
  mpfr_neg(l_lo_, l_lo_, MPFR_RNDN);  // (exact)
  mpfr_sub_q(l_hi_, s_lo_, chart_area.get_mpq_t(), MPFR_RNDD);
  mpfr_neg(l_hi_, l_hi_, MPFR_RNDN);
  if (mpfr_sgn(l_lo_) <= 0) return false;
  double lit_area = 0, shadow_area = 0;
  if (!pinned_area(l_lo_, l_hi_, area_scale_squared, lit_area)) return false;
  if (!pinned_area(s_lo_, s_hi_, area_scale_squared, shadow_area)) return false;
  mpfr_div_q(t_lo_, l_lo_, chart_area.get_mpq_t(), MPFR_RNDD);
  mpfr_div_q(t_hi_, l_hi_, chart_area.get_mpq_t(), MPFR_RNDU);
  const double lit_fraction = mpfr_get_d(t_lo_, MPFR_RNDN);
  if (lit_fraction != mpfr_get_d(t_hi_, MPFR_RNDN)) return false;
  out.lit_area = lit_area;
  out.shadow_area = shadow_area;
  out.lit_fraction = lit_fraction;
  return true;
}

bool EnclosedMeasure::pinned_area(mpfr_srcptr lo, mpfr_srcptr hi, const FT::Exact_type& area_scale_squared,
                                  double& out) {
  // Rounding to nearest is monotone: where both ends of [lo, hi] round to one double, so does
  // every value between them.
  if (mpq_cmp_ui(area_scale_squared.get_mpq_t(), 1, 1) == 0) {  // |A|, no root (area_3d_exact)
    out = mpfr_get_d(lo, MPFR_RNDN);
    return out == mpfr_get_d(hi, MPFR_RNDN);
  }
  // sqrt(A^2 s), A > 0: increasing in A.
  mpfr_sqr(t_lo_, lo, MPFR_RNDD);
  mpfr_mul_q(t_lo_, t_lo_, area_scale_squared.get_mpq_t(), MPFR_RNDD);
  mpfr_sqrt(t_lo_, t_lo_, MPFR_RNDD);
  mpfr_sqr(t_hi_, hi, MPFR_RNDU);
  mpfr_mul_q(t_hi_, t_hi_, area_scale_squared.get_mpq_t(), MPFR_RNDU);
  mpfr_sqrt(t_hi_, t_hi_, MPFR_RNDU);
  out = mpfr_get_d(t_lo_, MPFR_RNDN);
  return out == mpfr_get_d(t_hi_, MPFR_RNDN);
}

namespace {

/// An exactly planar face in plain integers: with 2^e the least power of two of its nonzero
/// input coordinates, every coordinate is an integer multiple of 2^e, and so are their
/// differences. Twice the chart area is then twice_area 2^(2e) and the corner's normal
/// (nx, ny, nz) 2^(2e), all integers.
struct PlanarIntegers {
  mpz_class twice_area, n[3];
  long e = 0;
  bool zero = false;  ///< every coordinate zero, or a zero chart area
};

PlanarIntegers planar_integers(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep) {
  PlanarIntegers out;
  const int k = prep.axis, i = core::chart_i(k), j = core::chart_j(k);
  const auto [prev, corner, next] = prep.corner;
  core::BitSpan span;
  for (const glm::dvec3& v : vertices)
    for (int a = 0; a < 3; ++a) span.add(v[a]);
  const std::vector<int>& ring = prep.chart_ring;
  const std::size_t n = ring.size();
  if (span.empty() || n < 3) {  // every coordinate zero
    out.zero = true;
    return out;
  }
  const long e = span.least;
  out.e = e;
  // c / 2^e as an integer (no double overflow for any exponent).
  auto scaled = [&](double c, mpz_class& result) { integer_of(c, e, result.get_mpz_t()); };
  std::vector<mpz_class> x(n), y(n);
  for (std::size_t a = 0; a < n; ++a) {
    scaled(vertices[static_cast<std::size_t>(ring[a])][i], x[a]);
    scaled(vertices[static_cast<std::size_t>(ring[a])][j], y[a]);
  }
  mpz_class dx1, dy1, dx2, dy2;  // the shoelace about the first vertex
  for (std::size_t a = 1; a + 1 < n; ++a) {
    dx1 = x[a] - x[0];
    dy1 = y[a] - y[0];
    dx2 = x[a + 1] - x[0];
    dy2 = y[a + 1] - y[0];
    out.twice_area += dx1 * dy2 - dx2 * dy1;
  }
  if (out.twice_area == 0) {
    out.zero = true;
    return out;
  }
  mpz_class p[3], u[3], w[3];
  for (int a = 0; a < 3; ++a) {
    scaled(vertices[static_cast<std::size_t>(corner)][a], p[a]);
    scaled(vertices[static_cast<std::size_t>(next)][a], u[a]);
    scaled(vertices[static_cast<std::size_t>(prev)][a], w[a]);
    u[a] -= p[a];
    w[a] -= p[a];
  }
  out.n[0] = u[1] * w[2] - u[2] * w[1];
  out.n[1] = u[2] * w[0] - u[0] * w[2];
  out.n[2] = u[0] * w[1] - u[1] * w[0];
  return out;
}

/// PlanarIntegers in __int128, for a face whose coordinates span at most kFixedSpanBits bits (a
/// city in metres with millimetre doubles: about 60): every scaled coordinate is below 2^61,
/// every difference below 2^62 and every product below 2^124. False where a face spans more or
/// its shoelace sum would leave the type (then planar_integers, in GMP: the same integers).
struct PlanarFixed {
  fixed::i128 twice_area = 0, n[3] = {0, 0, 0};
  long e = 0;
  bool zero = false;
};
constexpr int kFixedSpanBits = 61;

bool planar_integers_fixed(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep, PlanarFixed& out) {
  using fixed::i128;
  const int k = prep.axis, i = core::chart_i(k), j = core::chart_j(k);
  core::BitSpan span;
  for (const glm::dvec3& v : vertices)
    for (int a = 0; a < 3; ++a) span.add(v[a]);
  const std::vector<int>& ring = prep.chart_ring;
  const std::size_t n = ring.size();
  if (span.empty() || n < 3) {
    out.zero = true;
    return true;
  }
  if (span.width() > kFixedSpanBits) return false;
  out.e = span.least;
  // c / 2^e, exact: c's mantissa shifted by at most kFixedSpanBits - 1 (c is a multiple of 2^e).
  auto scaled = [&](double c) -> i128 {
    if (c == 0.0) return 0;
    const core::Dyadic d = core::dyadic(c);
    return static_cast<i128>(d.mantissa) * (i128{1} << (d.exponent - out.e));
  };
  const glm::dvec3& first = vertices[static_cast<std::size_t>(ring[0])];
  const i128 x0 = scaled(first[i]), y0 = scaled(first[j]);
  i128 dx1 = scaled(vertices[static_cast<std::size_t>(ring[1])][i]) - x0;
  i128 dy1 = scaled(vertices[static_cast<std::size_t>(ring[1])][j]) - y0;
  for (std::size_t a = 1; a + 1 < n; ++a) {  // the shoelace about the first vertex
    const glm::dvec3& v = vertices[static_cast<std::size_t>(ring[a + 1])];
    const i128 dx2 = scaled(v[i]) - x0, dy2 = scaled(v[j]) - y0;
    if (__builtin_add_overflow(out.twice_area, dx1 * dy2 - dx2 * dy1, &out.twice_area)) return false;
    dx1 = dx2;
    dy1 = dy2;
  }
  if (out.twice_area == 0) {
    out.zero = true;
    return true;
  }
  const auto [prev, corner, next] = prep.corner;
  i128 u[3], w[3];
  for (int a = 0; a < 3; ++a) {
    const i128 p = scaled(vertices[static_cast<std::size_t>(corner)][a]);
    u[a] = scaled(vertices[static_cast<std::size_t>(next)][a]) - p;
    w[a] = scaled(vertices[static_cast<std::size_t>(prev)][a]) - p;
  }
  out.n[0] = u[1] * w[2] - u[2] * w[1];
  out.n[1] = u[2] * w[0] - u[0] * w[2];
  out.n[2] = u[0] * w[1] - u[1] * w[0];
  return true;
}

/// The face's plane integers in GMP: the __int128 route's converted where it applied (`fits`),
/// else planar_integers'. The same integers either way.
PlanarIntegers gmp_integers(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep,
                            const PlanarFixed& f, bool fits) {
  if (!fits) return planar_integers(vertices, prep);
  PlanarIntegers z;
  z.e = f.e;
  z.zero = f.zero;
  fixed::set_mpz(z.twice_area.get_mpz_t(), f.twice_area);
  for (int a = 0; a < 3; ++a) fixed::set_mpz(z.n[a].get_mpz_t(), f.n[a]);
  return z;
}

}  // namespace

std::optional<double> planar_face_area(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep) {
  const int k = prep.axis;
  PlanarFixed f;
  const bool fits = planar_integers_fixed(vertices, prep, f);
  if (fits && !f.zero && f.n[k] != 0 && f.n[core::chart_i(k)] == 0 && f.n[core::chart_j(k)] == 0) {
    // A face square to axis k (walls, roofs and grounds of most cities): the root below is |T|
    // 2^(2e-1) exactly, so its rounding is that of the integer |T| (the conversion rounds in the
    // current mode: to nearest, ties to even, as mpfr_get_d, outside CGAL's protected rounding
    // scopes, where this is never called), scaled exactly while the result stays normal; the
    // MPFR root of the same rational otherwise.
    const double m = static_cast<double>(fixed::magnitude(f.twice_area));
    int exponent = 0;
    std::frexp(m, &exponent);
    const long scale = 2 * f.e - 1;
    if (exponent + scale > -1021 && exponent + scale < 1024) return std::ldexp(m, static_cast<int>(scale));
  }
  //   (chart area)^2 |n|^2 / n_k^2 = T^2 |N|^2 2^(4e) / (4 N_k^2)
  // with T = twice_area and N = n of PlanarIntegers: the rational area_3d takes the root of (the
  // same value, so the same rounding).
  const PlanarIntegers z = gmp_integers(vertices, prep, f, fits);
  if (z.zero) return 0.0;
  const mpz_class& nk = z.n[k];
  if (nk == 0) return std::nullopt;  // (not for prepare_face's corner: a strict turn in the chart)
  mpq_class q(z.twice_area * z.twice_area * (z.n[0] * z.n[0] + z.n[1] * z.n[1] + z.n[2] * z.n[2]), 4 * nk * nk);
  q.canonicalize();
  scale_by_power_of_two(q, 4 * z.e);
  return sqrt_mpq_to_double(q.get_mpq_t());
}

bool planar_face_exact_areas(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep,
                             FT::Exact_type& chart_area, FT::Exact_type& area_scale_squared) {
  const int k = prep.axis;
  PlanarFixed f;
  const bool fits = planar_integers_fixed(vertices, prep, f);
  const PlanarIntegers z = gmp_integers(vertices, prep, f, fits);
  if (z.zero) return false;  // (prepare_face calls such a face degenerate)
  const mpz_class& nk = z.n[k];
  if (nk == 0) return false;
  chart_area = z.twice_area;
  scale_by_power_of_two(chart_area, 2 * z.e - 1);
  // n = N 2^(2e): the power cancels in |n|^2 / n_k^2, which is 1 for a face square to axis k.
  if (z.n[core::chart_i(k)] == 0 && z.n[core::chart_j(k)] == 0) {
    area_scale_squared = 1;
  } else {
    area_scale_squared = mpq_class(z.n[0] * z.n[0] + z.n[1] * z.n[1] + z.n[2] * z.n[2], nk * nk);
    area_scale_squared.canonicalize();
  }
  return true;
}

core::CellPlace place_cell(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep,
                           const std::array<double, 2>& lo, const std::array<double, 2>& hi) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const int i = core::chart_i(prep.axis), j = core::chart_j(prep.axis);
  const std::size_t n = prep.chart_ring.size();
  std::vector<K::Point_2> ring;
  ring.reserve(n);
  for (int v : prep.chart_ring) ring.emplace_back(vertices[v][i], vertices[v][j]);
  const K::Point_2 corners[4] = {K::Point_2(lo[0], lo[1]), K::Point_2(hi[0], lo[1]), K::Point_2(hi[0], hi[1]),
                                 K::Point_2(lo[0], hi[1])};
  for (std::size_t a = 0; a < n; ++a) {
    const K::Point_2& p = ring[a];
    const K::Point_2& q = ring[(a + 1) % n];
    // Two closed convex sets are disjoint exactly when the direction of one of their edges
    // separates them strictly: the cell's axes (comparisons of doubles) or the segment's line
    // (the cell's four corners strictly on one side: the exact orientation predicate).
    if (std::max(p.x(), q.x()) < lo[0] || std::min(p.x(), q.x()) > hi[0] || std::max(p.y(), q.y()) < lo[1] ||
        std::min(p.y(), q.y()) > hi[1])
      continue;
    int left = 0, right = 0;
    for (const K::Point_2& c : corners) {
      const CGAL::Orientation o = CGAL::orientation(p, q, c);
      left += o == CGAL::LEFT_TURN ? 1 : 0;
      right += o == CGAL::RIGHT_TURN ? 1 : 0;
    }
    if (left == 4 || right == 4) continue;
    return core::CellPlace::Crossing;
  }
  // No edge meets the closed cell: the whole cell lies on one side of the outline, as its corner.
  return CGAL::bounded_side_2(ring.begin(), ring.end(), corners[0], K()) == CGAL::ON_BOUNDED_SIDE
             ? core::CellPlace::Inside
             : core::CellPlace::Outside;
}

}  // namespace shadow::exact

namespace shadow::detail {

FaceShape classify_face_shape_exact(const std::vector<glm::dvec3>& vertices) {
  using namespace shadow::exact;
  std::vector<Point3> points;
  for (const glm::dvec3& v : vertices) points.push_back(to_exact(v));
  bool all_collinear = true;
  for (std::size_t a = 2; a < points.size() && all_collinear; ++a)
    all_collinear = CGAL::collinear(points[0], points[1], points[a]);
  if (all_collinear) return FaceShape::ZeroArea;
  const Vector3 normal = exact_newell_normal(points);
  if (normal == CGAL::NULL_VECTOR) return FaceShape::SelfIntersecting;  // e.g. a symmetric bow-tie
  const int k = dominant_axis(normal);
  Polygon2 chart;
  for (const Point3& p : points) chart.push_back(to_chart(p, k));
  return chart.is_simple() ? FaceShape::Simple : FaceShape::SelfIntersecting;
}

namespace {

/// The exact Newell normal's zero test and dominant axis (dominant_axis's tie rule) from an
/// interval enclosure: -1 for a zero normal, 0..2 for the axis, or -2 when the intervals cannot
/// decide. The normal of a closed polygon does not change when every vertex is translated, so
/// the vertices are taken relative to the first one (differences enclosed in intervals too):
/// the intervals stay tight for a small face far from the origin, and a face lying in a
/// coordinate plane gets exact zeros in the other two components.
int interval_normal_axis(const std::vector<glm::dvec3>& vertices) {
  using I = CGAL::Interval_nt<false>;  // needs the rounding mode set upward: the guard below
  I n[3] = {I(0), I(0), I(0)};
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const glm::dvec3& o = vertices[0];
    const std::size_t count = vertices.size();
    auto rel = [&](std::size_t a, int c) { return I(vertices[a][c]) - I(o[c]); };
    for (std::size_t a = 0; a < count; ++a) {
      const std::size_t b = (a + 1) % count;
      const std::array<I, 3> term = geometry::newell_term(rel(a, 0), rel(a, 1), rel(a, 2), rel(b, 0), rel(b, 1), rel(b, 2));
      n[0] += term[0];
      n[1] += term[1];
      n[2] += term[2];
    }
  }
  bool zero = true, nonzero = false;
  for (const I& c : n) {
    if (!std::isfinite(c.inf()) || !std::isfinite(c.sup())) return -2;  // overflow: decide exactly
    zero = zero && c.inf() == 0 && c.sup() == 0;
    nonzero = nonzero || c.inf() > 0 || c.sup() < 0;
  }
  if (zero) return -1;
  if (!nonzero) return -2;
  const I ax = CGAL::abs(n[0]), ay = CGAL::abs(n[1]), az = CGAL::abs(n[2]);
  // dominant_axis: ax >= ay && ax >= az -> 0; else ay >= az -> 1; else 2; each comparison used
  // must be certain.
  const CGAL::Uncertain<bool> x_over_y = ax >= ay;
  if (!CGAL::is_certain(x_over_y)) return -2;
  if (CGAL::get_certain(x_over_y)) {
    const CGAL::Uncertain<bool> x_over_z = ax >= az;
    if (!CGAL::is_certain(x_over_z)) return -2;
    if (CGAL::get_certain(x_over_z)) return 0;
  }
  const CGAL::Uncertain<bool> y_over_z = ay >= az;
  if (!CGAL::is_certain(y_over_z)) return -2;
  return CGAL::get_certain(y_over_z) ? 1 : 2;
}

}  // namespace

FaceShape classify_face_shape(const std::vector<glm::dvec3>& vertices) {
  // classify_face_shape_exact's decisions, made with Epick's exact predicates on the input
  // doubles (static and interval filters, exact fallback) and, for the Newell normal, an
  // interval enclosure that hands over to the lazy exact normal only when it cannot decide.
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const std::size_t count = vertices.size();
  auto point3 = [&](std::size_t a) { return K::Point_3(vertices[a].x, vertices[a].y, vertices[a].z); };
  bool all_collinear = true;
  for (std::size_t a = 2; a < count && all_collinear; ++a)
    all_collinear = CGAL::collinear(point3(0), point3(1), point3(a));
  if (all_collinear) return FaceShape::ZeroArea;
  int k = interval_normal_axis(vertices);
  if (k == -2) {
    const exact::Vector3 normal = exact::exact_newell_normal(exact::exact_points(vertices));
    k = normal == CGAL::NULL_VECTOR ? -1 : exact::dominant_axis(normal);
  }
  if (k == -1) return FaceShape::SelfIntersecting;  // e.g. a symmetric bow-tie
  // Chart coordinates are input doubles: Epick's exact predicates decide simplicity exactly.
  const int i = core::chart_i(k), j = core::chart_j(k);
  CGAL::Polygon_2<K> chart;
  for (const glm::dvec3& v : vertices) chart.push_back(K::Point_2(v[i], v[j]));
  return chart.is_simple() ? FaceShape::Simple : FaceShape::SelfIntersecting;
}

}  // namespace shadow::detail
