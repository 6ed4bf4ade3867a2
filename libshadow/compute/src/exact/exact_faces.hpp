// SPDX-License-Identifier: GPL-3.0-or-later
// Exact per-face data: each face's exact plane, its 2D chart and its convex pieces.
//
// A face is prepared once (core::FacePrep: plain numbers and indices, shareable between threads);
// each worker thread then builds its own Epeck objects from it (ExactFace), because Epeck's
// lazy values must not be shared between threads.
#pragma once

#include "core/dyadic.hpp"
#include "core/face_prep.hpp"
#include "core/tiles.hpp"
#include "exact/kernel.hpp"

#include <mpfr.h>

#include <cstddef>

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <gmpxx.h>

#include <array>
#include <optional>
#include <stdexcept>
#include <vector>

namespace shadow::exact {

/// Prepares a face. Faces must be finite and free of consecutive duplicate vertices.
core::FacePrep prepare_face(const std::vector<glm::dvec3>& vertices);

/// Areas only, a receiver whose chart is not convex: with at most this many convex pieces its
/// casts are clipped to each piece and the pieces' unions measured (measure_in_convex_pieces,
/// measure_in_scaled_pieces); with more, CGAL's join and an intersection with the chart. A
/// 2,000-tooth comb (4,000 pieces) under 400 boxes' shadows took 1.4 s in the pieces (each cast
/// clipped to the dozens of narrow pieces it spans) against the join's fraction of that; a real
/// model's L-, U- and courtyard-shaped faces have a few pieces.
constexpr std::size_t kMaxChartPiecesToClip = 64;

/// One thread's exact view of a face.
struct ExactFace {
  Vector3 normal;                ///< exact normal pointing to the face's front (any length)
  FT offset;                     ///< plane: normal . p + offset = 0
  std::vector<Point3> vertices;  ///< on the plane (lifted along the chart axis if not planar)
  Polygon2 chart;                ///< counter-clockwise chart polygon (chart_ring)
  /// The chart's convex pieces (prep.convex_pieces, counter-clockwise) with their bounding
  /// boxes, when the chart is not convex and has at most kMaxChartPiecesToClip of them; empty
  /// otherwise (a convex chart is its one piece).
  std::vector<Polygon2> chart_pieces;
  std::vector<CGAL::Bbox_2> chart_piece_boxes;
  FT chart_area;                 ///< exact area of `chart`
  FT area_scale_squared;         ///< (3D area / chart area)^2 = |n|^2 / n_k^2
};

ExactFace make_exact_face(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep);

/// Lifts a chart point onto the face's plane.
Point3 lift(const Point2& chart_point, const ExactFace& face, int axis);

/// Converts an input vertex to an exact point.
inline Point3 to_exact(const glm::dvec3& v) { return Point3(v.x, v.y, v.z); }

/// The chart coordinates of a 3D point for dropped axis k.
inline Point2 to_chart(const Point3& p, int k) {
  return Point2(p[core::chart_i(k)], p[core::chart_j(k)]);
}

/// 3D area of a chart area on a face, rounded once.
double area_3d(const FT& chart_area, const FT& area_scale_squared);

/// area_3d on plain exact rationals (no lazy DAG): sqrt(A^2 s) rounded once, and |A| rounded
/// once where s is exactly 1 (a face in an axis plane; docs/numeric-contract.md). `scratch` is
/// the caller's, to reuse its limbs.
double area_3d_exact(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
                     FT::Exact_type& scratch);

/// A receiver's lit_area, shadow_area and lit_fraction from its exact chart area and area scale
/// (ExactWorker::exact_areas) and its shadow's exact chart area, each rounded once: the one
/// measure of whole receivers (exact_receiver.cpp) and of tiled ones summed (the engine's merge).
/// `lit` receives chart - shadow; `scratch` is reused.
void measure_lit_and_shadow(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
                            const FT::Exact_type& shadow_chart_area, FT::Exact_type& lit,
                            FT::Exact_type& scratch, FaceLighting& out);

/// measure_lit_and_shadow for a shadow whose chart area is known to lie in an enclosure: from
/// twice_lo / 2 to (twice_lo + slack 2^-slack_bits) / 2, each divided by scale^2 where `scale`
/// is given (a scaled chart's K). Each of the three doubles is taken where the enclosure pins
/// it: the value rounded once from both ends (every step rounded outward, at kBits bits) is the
/// same double, so the exact value rounds to it too. True then, with the doubles
/// measure_lit_and_shadow gives for the exact shadow (bit for bit, but for values closer than
/// 2^-200 to a rounding boundary, which sqrt_mpq_to_double may round either way and these round
/// correctly). False, `out` unchanged, where some double is not pinned, or the shadow or the lit
/// part is not positive throughout: the caller then measures the exact shadow. Holds its MPFR
/// numbers (one per worker).
class EnclosedMeasure {
 public:
  static constexpr long kBits = 192;
  EnclosedMeasure();
  ~EnclosedMeasure();
  EnclosedMeasure(const EnclosedMeasure&) = delete;
  EnclosedMeasure& operator=(const EnclosedMeasure&) = delete;
  EnclosedMeasure(EnclosedMeasure&& other) noexcept : EnclosedMeasure() { swap(other); }
  EnclosedMeasure& operator=(EnclosedMeasure&& other) noexcept {
    swap(other);
    return *this;
  }
  void swap(EnclosedMeasure& other) noexcept;

  bool measure(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
               const FT::Exact_type& twice_lo, std::size_t slack, int slack_bits, const FT::Exact_type* scale,
               FaceLighting& out);

  /// The same for a shadow chart area from shadow_lo to shadow_lo + width (width >= 0): a tiled
  /// face's tiles' enclosures (or exact areas) added.
  bool measure_between(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared,
                       const FT::Exact_type& shadow_lo, const FT::Exact_type& width, FaceLighting& out);

 private:
  /// The doubles from the shadow's enclosure [s_lo_, s_hi_] (set by the callers).
  bool pin(const FT::Exact_type& chart_area, const FT::Exact_type& area_scale_squared, FaceLighting& out);
  /// area_3d_exact of a value in [lo, hi] (lo > 0), when both ends give the same double.
  bool pinned_area(mpfr_srcptr lo, mpfr_srcptr hi, const FT::Exact_type& area_scale_squared, double& out);
  mpfr_t s_lo_, s_hi_, l_lo_, l_hi_, t_lo_, t_hi_;
};

/// The 3D area of an exactly planar face (prep.exactly_planar), rounded once: the same double as
/// area_3d(make_exact_face(...).chart_area, ...area_scale_squared), computed in plain integers
/// from the input doubles (all scaled by one power of two) instead of lazy exact numbers; nullopt
/// when the corner's normal has a zero k component (then use area_3d).
std::optional<double> planar_face_area(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep);

/// ExactFace::chart_area and ::area_scale_squared of an exactly planar face (prep.exactly_planar),
/// the same rationals, from plain integers as planar_face_area: no lazy exact face (each node of
/// its DAG evaluated through std::call_once, a futex system call). False, and nothing set, where
/// the corner's normal has a zero k component or the chart area is zero (use make_exact_face).
bool planar_face_exact_areas(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep,
                             FT::Exact_type& chart_area, FT::Exact_type& area_scale_squared);

/// Where the closed axis-aligned cell [lo, hi] of the chart lies with respect to the face's
/// outline (its chart ring, in the input doubles), decided with exact predicates: Crossing when
/// some edge of the outline meets the closed cell, else Inside or Outside as its corner `lo` is
/// (docs/tiles.md). O(outline vertices).
core::CellPlace place_cell(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep,
                           const std::array<double, 2>& lo, const std::array<double, 2>& hi);

/// v 2^-e as an integer into `out`, for v a multiple of 2^e (every coordinate of a set is, for e
/// the least set bit of them all: core::BitSpan::least); std::logic_error for one that is not.
/// The integer views of planar_face_area and of the areas route's scaled charts.
inline void integer_of(double v, long e, mpz_ptr out) {
  static_assert(sizeof(long) >= 8, "GMP's si functions here take the 53-bit mantissas of doubles");
  if (v == 0.0) {
    mpz_set_ui(out, 0);
    return;
  }
  const core::Dyadic q = core::dyadic(v);
  if (q.exponent < e) throw std::logic_error("libshadow: a coordinate below the least bit of its set (scene changed after ShadowEngine was made?)");
  mpz_set_si(out, static_cast<long>(q.mantissa));
  mpz_mul_2exp(out, out, static_cast<mp_bitcnt_t>(q.exponent - e));
}

/// q times 2^shift (either sign).
inline void scale_by_power_of_two(mpq_class& q, long shift) {
  if (shift >= 0)
    mpq_mul_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(shift));
  else
    mpq_div_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(-shift));
}

}  // namespace shadow::exact
