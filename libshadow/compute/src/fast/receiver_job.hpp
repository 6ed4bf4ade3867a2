// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path's receiver job (fast_receiver.cpp), shared by the files of its steps: the
// frame, facing and projection (fast_receiver.cpp), the casts (fast_receiver_casts.cpp), the
// union on the grid and the fragments (fast_receiver_union.cpp). Internal to fast/.
#pragma once

#include "fast/fast_receiver.hpp"

#include "fast/box_clip.hpp"
#include "fast/cluster_union.hpp"
#include "fast/error_bound.hpp"
#include "fast/window_clip.hpp"
#include "geometry/clip_convex.hpp"
#include "geometry/cyclic_index.hpp"
#include "geometry/default_init_allocator.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <polyclipping/clipper.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace shadow::fast::receiver_job {

using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
namespace CL = ClipperLib;
__extension__ typedef __int128 Int128;  // exact shoelace sums of int64 grid coordinates

constexpr double kEps = std::numeric_limits<double>::epsilon();  // 2^-52
// Grid half-range: Clipper 6.4 stays in its fast 64-bit mode for |coordinates| <= 2^30 - 1.
constexpr CL::cInt kHalf = (CL::cInt(1) << 30) - 2;

inline EK::Point_3 epick(const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); }

/// Twice the signed area of a grid polygon, exactly (fast/cluster_union.hpp).
inline Int128 area2(const CL::Path& path) { return twice_area(path); }

inline double perimeter(const ChartPoints& poly) {
  double length = 0;
  for (std::size_t a = 0; a < poly.size(); ++a) length += glm::length(poly[geometry::cyclic_next(a, poly.size())] - poly[a]);
  return length;
}

/// Homogeneous chart point (X, Z, w) of a central projection; the chart point is (X, Z) / w.
struct Hom {
  double x, z, w;
};

/// Clip of a convex homogeneous polygon to f(p) >= 0 for a linear f (geometry/clip_convex.hpp;
/// side +1 or -1 as in clip_axis).
template <class F>
void clip_hom(geometry::UnfilledVector<Hom>& poly, F f, geometry::UnfilledVector<Hom>& scratch) {
  geometry::clip_convex(poly, [&](std::size_t a) { return f(poly[a]) >= 0 ? 1 : -1; },
                        [&](std::size_t a, std::size_t b) {
                          const Hom& p = poly[a];
                          const Hom& q = poly[b];
                          const double fp = f(p), fq = f(q);
                          const double t = std::clamp(fp / (fp - fq), 0.0, 1.0);
                          return Hom{p.x + t * (q.x - p.x), p.z + t * (q.z - p.z), p.w + t * (q.w - p.w)};
                        }, scratch);
  poly.swap(scratch);
}


/// Everything about the receiver the casters need, in a frame centred on its corner vertex.
struct Receiver {
  int i = 0, j = 1, k = 2;
  glm::dvec3 corner{0.0};
  glm::dvec3 normal{0.0};  ///< unit, towards the front
  double normal_error = 0;  ///< bound on the direction error of `normal` plus rounding, relative
  std::array<double, 2> lo{}, hi{};
  double scene_reach = 0;  ///< bound on |Y - corner| for any scene point Y
  double magnitude = 0;    ///< bound on |chart coordinates| of any point involved
  // Directional light.
  glm::dvec2 shift{0.0};   ///< projection: chart(Y) - s(Y) * shift
  double inv_light_side = 0;
  // Point light.
  bool point = false;
  glm::dvec3 light_rel{0.0};  ///< light - corner
  double light_side = 0;      ///< s at the light (> 0)
  EK::Point_3 c0, c1, c2;     ///< corner points for the exact side predicate
  bool flipped = false;
  /// Exactly planar receiver: sides of input points by Epick's exact predicate. Otherwise the
  /// plane is the exact engine's lifted plane (Newell normal through the centroid) in doubles.
  bool exact_sides = true;
  double s_error = 0;  ///< bound on |s in doubles - exact s| for scene points

  [[nodiscard]] double s(const glm::dvec3& y) const { return glm::dot(normal, y - corner); }
  /// Exact sign of the receiver's plane at an input point (positive: in front); exactly planar
  /// receivers only.
  [[nodiscard]] CGAL::Sign side(const glm::dvec3& y) const {
    const CGAL::Sign sv = CGAL::orientation(c0, c1, c2, epick(y));
    return flipped ? CGAL::opposite(sv) : sv;
  }
  /// side(y) for a scene point y (|y - corner| within scene_reach) of an exactly planar
  /// receiver (exact_sides: s_error is then the frame's bound, not a lifted plane's): s in
  /// doubles where it is beyond twice its error bound, the exact predicate only where it is
  /// not. The same sign, without the predicate for most vertices. s_error already holds a
  /// factor of 2 over the normal's direction error and the roundings; the second factor is
  /// room for a direction bound derived by hand (set_up_frame), at the cost of sending a few
  /// more vertices near the plane to the predicate.
  [[nodiscard]] CGAL::Sign scene_side(const glm::dvec3& y) const { return scene_side(y, s(y)); }
  /// scene_side(y) where `value` is s(y), already computed.
  [[nodiscard]] CGAL::Sign scene_side(const glm::dvec3& y, double value) const {
    assert(exact_sides);
    if (value > 2 * s_error) return CGAL::POSITIVE;
    if (value < -2 * s_error) return CGAL::NEGATIVE;
    return side(y);
  }
  /// The side of a caster vertex that the exact engine would see, or `unsure` when doubles cannot
  /// tell (|s| within the error, plus `slack`: how far the exact engine lifts that vertex).
  [[nodiscard]] CGAL::Sign side(const glm::dvec3& y, bool caster_planar, double slack, bool& unsure) const {
    unsure = false;
    if (exact_sides && caster_planar) return scene_side(y);
    const double value = s(y), tolerance = s_error + slack;
    if (value > tolerance) return CGAL::POSITIVE;
    if (value < -tolerance) return CGAL::NEGATIVE;
    unsure = true;
    return CGAL::ZERO;  // taken as on the plane; the caller charges the difference
  }
};

/// One projected caster polygon in the chart with its estimated double error.
struct Cast {
  ChartPoints poly;
  double delta = 0;         ///< bound on each vertex's distance to the exact point
  double free_length = 0;   ///< perimeter before the box clip (directional), for the bound
};


/// FastReceiver's vectors (part of ReceiverScratch: kept by the worker).
struct FastReceiverScratch {
  ChartPoints box_clip;
  geometry::UnfilledVector<Hom> hom, hom_clip;  // (as ChartPoints: clip_convex sizes, writes, shrinks)
};

class FastReceiver {
 public:
  FastReceiver(const Receiver& rc, FastReceiverScratch& scratch)
      : rc_(rc), scratch_(scratch.box_clip), hom_(scratch.hom), scratch_hom_(scratch.hom_clip) {}

  /// Directional light: the front part of a convex piece (exact signs), projected, clipped to
  /// the box. False: ill-conditioned (handed to the exact engine).
  bool project_parallel(const std::vector<glm::dvec3>& v, const std::vector<int>& piece,
                        const std::vector<CGAL::Sign>& sign, Cast& cast) {
    cast.poly.clear();
    cast.delta = base_delta_ + position_error_ * (1 + glm::length(rc_.shift));
    const std::size_t m = piece.size();
    for (std::size_t a = 0; a < m; ++a) {
      const glm::dvec3& va = v[piece[a]];
      const CGAL::Sign sa = sign[a], sb = sign[geometry::cyclic_next(a, m)];
      if (sa == CGAL::POSITIVE) cast.poly.push_back(project(va));
      if (sa == CGAL::ZERO) cast.poly.push_back(chart(va));
      if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE)) {
        glm::dvec3 x;
        if (!crossing(va, v[piece[geometry::cyclic_next(a, m)]], x, cast.delta)) return false;
        cast.poly.push_back(chart(x));
      }
    }
    cast.free_length = perimeter(cast.poly);
    return clip_to_box(cast);
  }

  /// Point light: the front part of a convex piece, clipped to the pyramid over the box in
  /// homogeneous chart coordinates, then divided out.
  bool project_central(const std::vector<glm::dvec3>& v, const std::vector<int>& piece,
                       const std::vector<CGAL::Sign>& sign, Cast& cast) {
    hom_.clear();
    double cross_delta = 0;
    const std::size_t m = piece.size();
    const double L = rc_.light_side;
    for (std::size_t a = 0; a < m; ++a) {
      const glm::dvec3& va = v[piece[a]];
      const CGAL::Sign sa = sign[a], sb = sign[geometry::cyclic_next(a, m)];
      if (sa == CGAL::POSITIVE) hom_.push_back(homogeneous(va - rc_.corner));
      if (sa == CGAL::ZERO) {
        const glm::dvec3 y = va - rc_.corner;
        hom_.push_back({L * y[rc_.i], L * y[rc_.j], L});
      }
      if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE)) {
        glm::dvec3 x;
        if (!crossing(va, v[piece[geometry::cyclic_next(a, m)]], x, cross_delta)) return false;
        const glm::dvec3 y = x - rc_.corner;
        hom_.push_back({L * y[rc_.i], L * y[rc_.j], L});
      }
    }
    const double lo_i = rc_.lo[0] - rc_.corner[rc_.i], hi_i = rc_.hi[0] - rc_.corner[rc_.i];
    const double lo_j = rc_.lo[1] - rc_.corner[rc_.j], hi_j = rc_.hi[1] - rc_.corner[rc_.j];
    // Smallest positive w before the clip: if the clip leaves nothing, the exact clip may still
    // hold a sliver along the box's edge, charged to the bound by the caller.
    double w_front = std::numeric_limits<double>::infinity();
    for (const Hom& p : hom_)
      if (p.w > 0) w_front = std::min(w_front, p.w);
    clip_hom(hom_, [&](const Hom& p) { return p.x - lo_i * p.w; }, scratch_hom_);
    clip_hom(hom_, [&](const Hom& p) { return hi_i * p.w - p.x; }, scratch_hom_);
    clip_hom(hom_, [&](const Hom& p) { return p.z - lo_j * p.w; }, scratch_hom_);
    clip_hom(hom_, [&](const Hom& p) { return hi_j * p.w - p.z; }, scratch_hom_);
    cast.poly.clear();
    // Errors of the homogeneous coordinates (products of s, the light and points, each with the
    // plane's error), divided by the smallest w; crossings move H by light_side times their error.
    const double e = rc_.normal_error, R = rc_.scene_reach, l = glm::length(rc_.light_rel);
    const double box = std::max({std::abs(lo_i), std::abs(hi_i), std::abs(lo_j), std::abs(hi_j)});
    const double dH = 4 * e * R * l + 4 * kEps * (l * R + l * box) + L * cross_delta +
                      2 * (L + l) * position_error_ + 2 * l * s_extra_;
    const double dw = 4 * e * (R + l);
    if (hom_.size() < 3) {  // nothing left in doubles: charge a sliver along the box's edges
      cast.free_length = std::isfinite(w_front) ? 2 * (hi_i - lo_i + hi_j - lo_j) : 0.0;
      cast.delta = std::isfinite(w_front) ? 2 * (dH + box * dw) / w_front + 4 * kEps * rc_.magnitude : 0.0;
      return cast.delta <= max_delta_;
    }
    double w_min = std::numeric_limits<double>::infinity();
    for (const Hom& p : hom_) w_min = std::min(w_min, p.w);
    if (!(w_min > 0)) return false;  // touches the light: leave it to the exact engine
    for (const Hom& p : hom_) {
      glm::dvec2 x(p.x / p.w + rc_.corner[rc_.i], p.z / p.w + rc_.corner[rc_.j]);
      cast.poly.push_back(glm::clamp(x, glm::dvec2(rc_.lo[0], rc_.lo[1]), glm::dvec2(rc_.hi[0], rc_.hi[1])));
    }
    cast.delta = 2 * (dH + box * dw) / w_min + 4 * kEps * rc_.magnitude;
    cast.free_length = perimeter(cast.poly);
    return cast.delta <= max_delta_;
  }

  void set_tolerances(double base_delta, double max_delta) {
    base_delta_ = base_delta;
    max_delta_ = max_delta;
  }
  /// For the next pieces: how far (3D) a vertex may be from the exact engine's (a lifted
  /// caster, or a vertex of unsure side taken as on the plane), and the extra error of s.
  void set_piece_error(double position, double s_extra) {
    position_error_ = position;
    s_extra_ = s_extra;
  }

  // Coordinates by index through value_ptr: glm's operator[] is a switch on the index, a
  // branch per coordinate of every caster vertex.
  glm::dvec2 chart(const glm::dvec3& y) const {
    const double* c = glm::value_ptr(y);
    return {c[rc_.i], c[rc_.j]};
  }

  glm::dvec2 project(const glm::dvec3& y) const { return project(y, rc_.s(y)); }
  /// project(y) where `s` is rc_.s(y), already computed.
  glm::dvec2 project(const glm::dvec3& y, double s) const {
    const double* c = glm::value_ptr(y);
    return {c[rc_.i] - s * rc_.shift.x, c[rc_.j] - s * rc_.shift.y};
  }

  /// Where segment a-b (exact signs strictly opposite) crosses the receiver's plane, with its
  /// error added to `delta`. False when the segment is nearly parallel to the plane.
  bool crossing(const glm::dvec3& a, const glm::dvec3& b, glm::dvec3& x, double& delta) const {
    const double sa = rc_.s(a), sb = rc_.s(b);
    const double ds = 2 * (rc_.normal_error + 4 * kEps) * rc_.scene_reach + rc_.s_error + s_extra_;
    const double gap = std::abs(sa - sb);
    if (!(gap > 64 * ds)) return false;
    const double t = std::clamp(sa / (sa - sb), 0.0, 1.0);
    x = a + t * (b - a);
    delta = std::max(delta, 3 * ds / gap * glm::length(b - a) + 4 * kEps * rc_.magnitude);
    return delta <= max_delta_;
  }

  Hom homogeneous(const glm::dvec3& y) const {
    const double s = glm::dot(rc_.normal, y);
    const double L = rc_.light_side;
    return {L * y[rc_.i] - s * rc_.light_rel[rc_.i], L * y[rc_.j] - s * rc_.light_rel[rc_.j], L - s};
  }

  bool clip_to_box(Cast& cast) {
    clip_to_box_sides(cast.poly, rc_.lo, rc_.hi, scratch_);
    for (glm::dvec2& p : cast.poly)
      p = glm::clamp(p, glm::dvec2(rc_.lo[0], rc_.lo[1]), glm::dvec2(rc_.hi[0], rc_.hi[1]));
    return cast.delta <= max_delta_;
  }

 private:
  const Receiver& rc_;
  double base_delta_ = 0, max_delta_ = 0, position_error_ = 0, s_extra_ = 0;
  ChartPoints& scratch_;
  geometry::UnfilledVector<Hom>&hom_, &scratch_hom_;
};

/// The integer grid over the receiver's chart box: its corners are grid points.
struct Grid {
  std::array<double, 2> lo{}, hi{}, scale{}, step{};
  Grid() = default;
  Grid(const std::array<double, 2>& lo_, const std::array<double, 2>& hi_) : lo(lo_), hi(hi_) {
    for (int c = 0; c < 2; ++c) {
      scale[c] = static_cast<double>(2 * kHalf) / (hi[c] - lo[c]);
      step[c] = (hi[c] - lo[c]) / static_cast<double>(2 * kHalf);
    }
  }
  CL::cInt to_int(double x, int c) const {
    const double g = std::clamp((x - lo[c]) * scale[c], 0.0, static_cast<double>(2 * kHalf));
    return round_half_up(g) - kHalf;
  }
  /// std::llround for 0 <= g <= 2^31 (halves away from zero, that is up), without its library
  /// call: g - trunc(g) is exact there. (Anything else, NaN included, goes to llround.)
  static CL::cInt round_half_up(double g) {
    if (!(g >= 0 && g <= 2147483648.0)) return static_cast<CL::cInt>(std::llround(g));
    const CL::cInt whole = static_cast<CL::cInt>(g);
    return whole + (g - static_cast<double>(whole) >= 0.5 ? 1 : 0);
  }
  CL::IntPoint point(const glm::dvec2& p) const { return {to_int(p.x, 0), to_int(p.y, 1)}; }
  glm::dvec2 chart(const CL::IntPoint& p) const {
    return {p.X == kHalf ? hi[0] : lo[0] + static_cast<double>(p.X + kHalf) * step[0],
            p.Y == kHalf ? hi[1] : lo[1] + static_cast<double>(p.Y + kHalf) * step[1]};
  }
  /// Bound on the distance between a chart point and its grid point (half a step per axis).
  double rounding() const { return 0.5 * std::hypot(step[0], step[1]) * (1 + 8 * kEps); }
};

/// The receiver job's vectors, kept by the worker (FastWorker::receiver) from one receiver to the
/// next: each job used to allocate its casts, hull points and clip buffers anew, and grow them
/// by copies, for a few casts a receiver. Their contents mean nothing between jobs: reset()
/// empties them, keeping their capacity. The casts' paths go to `spare`, from which add_cast
/// takes its next ones, so that `spare` never holds more paths than one job's casts; the window
/// clip's and the cells' paths are dropped instead (nothing takes them back).
struct ReceiverScratch {
  CL::Paths casts, maybe, windowed, cells;
  std::vector<CL::Path> spare;  ///< emptied paths with their capacity, for the next casts
  geometry::UnfilledVector<CGAL::Sign> vsign;  ///< resized to each caster's vertices, then written
  std::vector<CGAL::Sign> psign;
  std::vector<char> unsure;
  ChartPoints points, hull, outline;
  Cast cast;
  CL::Path receiver, window;
  CL::PolyTree shadow_tree, lit_tree;
  std::vector<CL::Paths> regions;
  FastReceiverScratch projection;

  /// Empties every vector for a new job (`spare` aside); the casts' paths go to `spare`.
  void reset() {
    recycle(casts);
    recycle(maybe);
    windowed.clear();
    cells.clear();
    vsign.clear();
    psign.clear();
    unsure.clear();
    points.clear();
    hull.clear();
    outline.clear();
    cast.poly.clear();
    cast.delta = 0;
    cast.free_length = 0;
    receiver.clear();
    window.clear();
    shadow_tree.Clear();
    lit_tree.Clear();
    regions.clear();
    projection.box_clip.clear();
    projection.hom.clear();
    projection.hom_clip.clear();
  }
  /// An empty path, with the capacity of one used before when there is one.
  CL::Path take_path() {
    if (spare.empty()) return {};
    CL::Path path = std::move(spare.back());
    spare.pop_back();
    path.clear();
    return path;
  }

 private:
  void recycle(CL::Paths& paths) {
    for (CL::Path& path : paths) spare.push_back(std::move(path));
    paths.clear();
  }
};

/// One receiver under one light on the fast path, in named steps (compute_receiver runs them in
/// order). Every step that returns false sends the receiver to the exact engine.
class ReceiverJob {
 public:
  ReceiverJob(const core::PreparedScene& ctx, FastWorker& w, std::size_t face_id, std::size_t light_id, const Light& light,
              const core::LightSpaceGrid* grid_index, bool polygons, FaceLighting& out,
              std::vector<Fragment>& fragments, ShadowStats& stats, const core::TileRequest& tiles)
      : ctx_(ctx), w_(w), scene_(*ctx.scene), prep_(*ctx.prep), cull_(*ctx.cull), face_id_(face_id),
        light_id_(light_id), light_(light), grid_index_(grid_index), polygons_(polygons), face_(scene_.faces[face_id]),
        fp_(tiles.tile ? *tiles.tile : prep_[face_id]), tile_(tiles.tile != nullptr),
        split_above_(tiles.tile ? 0 : tiles.split_above), out_(out), fragments_(fragments), stats_(stats),
        s_(w.receiver_scratch()), fr_(rc_, s_.projection), casts_(s_.casts), maybe_(s_.maybe), vsign_(s_.vsign),
        psign_(s_.psign), unsure_(s_.unsure), points_(s_.points), hull_(s_.hull), cast_(s_.cast),
        receiver_(s_.receiver), outline_(s_.outline), window_(s_.window), windowed_(s_.windowed),
        shadow_tree_(s_.shadow_tree), lit_tree_(s_.lit_tree), regions_(s_.regions), cells_(s_.cells) {
    s_.reset();
  }

  /// Set by run() when it returned Outcome::Split.
  std::size_t split_candidates = 0;

  Outcome run_job() {
    const bool done = run();
    if (split_candidates > 0) return Outcome::Split;
    return done ? Outcome::Done : Outcome::Exact;
  }

 private:
  bool run();

 private:
  /// Adds this receiver's counts to the caller's (only on success: a fallback leaves stats as
  /// they were, so local_.fast_exact_fallbacks is 0 here).
  bool commit() {
    stats_ += local_;
    return true;
  }

  // ---- receiver frame: plane, normal and their error bounds ---------------------------------
  bool set_up_frame();

  /// The face's outline as one fragment, wholly lit or wholly in shadow: its own vertices, or
  /// lifted onto the plane in doubles. False when that outline is not a simple polygon of
  /// certainly non-zero area in doubles (a sliver face): the exact engine writes it then.
  bool push_whole_face(bool lit);

  // ---- facing: exact where the double test could be wrong -----------------------------------
  bool decide_facing(int& facing);

  // ---- culling: the exact engine's tests ----------------------------------------------------
  const std::vector<std::size_t>& gather_casters() {
    core::ReceiverCuller culler(cull_, fp_, face_id_, light_);
    culler.use_caster_planes(scene_, prep_);
    const std::vector<std::size_t>& candidates =
        w_.casters.gather(culler, prep_, face_id_, grid_index_, tile_ ? &cull_ : nullptr, tile_ ? &fp_ : nullptr,
                          ctx_.solid_of, /*one_face_per_solid=*/!rc_.point && rc_.exact_sides);  // as cast_all casts
    local_.candidate_pairs += candidates.size();
    return candidates;
  }

  // ---- one solid's shadow over the whole receiver ------------------------------------------
  /// Whether the receiver's outline is its chart box and the casts would be convex solids' hulls
  /// under a directional light, areas only: where one_solid_covers() may decide the receiver.
  [[nodiscard]] bool may_be_covered_whole() const;
  /// True when some convex solid, every vertex's side of the receiver's plane certain in
  /// doubles, certainly shades all of the receiver: the exact hull of its front part's projection
  /// contains the chart box (the hull of its projected front vertices and its edges' crossings
  /// with the plane, each point within its error of an exact one, contains the box by more than
  /// that error and the chart's rounding). Then the exact lit area is 0, whatever the other
  /// casters do. Only solids whose light-space box contains the receiver's
  /// (LightSpaceGrid::query_containing) are tried; nothing is changed but scratch. After
  /// set_up_projection().
  bool one_solid_covers();

  // ---- projection in doubles: tolerances and the grid ---------------------------------------
  bool set_up_projection();

  /// Puts a projected cast polygon on the grid and into the union (or the bound, when it
  /// collapsed). Sets not_finite_ on overflow.
  void add_cast(Cast& c);

  // ---- the casters, by route ----------------------------------------------------------------
  bool cast_all(const std::vector<std::size_t>& candidates);

  /// A convex solid casts the hull of its projection, as in the exact engine (directional
  /// light, exactly planar receiver).
  bool cast_convex_solid(int solid);

  /// What solid_points() found of a convex solid.
  struct SolidPoints {
    std::size_t count = 0;  ///< its points: points_[0, count)
    bool any_front = false, any_behind = false;
    double cross_delta = 0;  ///< the crossings' error (0 without crossings)
  };
  /// The points whose hull is convex solid `cs`'s shadow on the receiver's plane, into points_:
  /// its vertices in front projected and those on the plane as they are, in vertex order, then,
  /// where some vertex is in front and some behind, its edges' crossings with the plane. Each
  /// vertex's side in vsign_: scene_side's, or with kCertainSides its test in doubles alone, a
  /// vertex that test cannot tell making this return false. False also where a crossing is
  /// ill-conditioned (fr_.crossing).
  template <bool kCertainSides>
  bool solid_points(const core::ConvexSolid& cs, SolidPoints& out);
  /// The hull of solid_points()' points of convex solid `solid` into hull_, counter-clockwise:
  /// the corners of its outline seen from the light where it is wholly in front and those make a
  /// convex polygon on the chart, else their convex hull.
  void solid_hull(int solid, const SolidPoints& points);

  /// Whether every point of points[0, n) lies beyond one side of the receiver's chart box by
  /// more than `margin`. False where a point is not finite: the cast then goes on as before this
  /// test, and add_cast's finiteness check sends the receiver to the exact engine.
  [[nodiscard]] bool beyond_chart_box(const ChartPoints& points, std::size_t n, double margin) const {
    if (n == 0) return false;
    glm::dvec2 lo = points[0], hi = points[0];
    for (std::size_t a = 0; a < n; ++a) {
      const glm::dvec2& p = points[a];
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    return hi.x + margin < rc_.lo[0] || rc_.hi[0] < lo.x - margin || hi.y + margin < rc_.lo[1] ||
           rc_.hi[1] < lo.y - margin;
  }

  /// A caster face, convex piece by convex piece: projected in front of the receiver (parallel
  /// or central projection), or, for pieces nowhere clearly in front, a sliver in the bound or a
  /// nearly coplanar footprint.
  bool cast_face(std::size_t q);

  /// A piece nowhere clearly in front, some vertex of unsure side: a sliver along the plane in
  /// the bound when its position is known, else (nearly coplanar with the receiver) its chart
  /// footprint, united separately: the shadow lies between the union without and with these.
  bool cast_nearly_coplanar(const Face& qface, const std::vector<int>& piece, double position, double grow,
                            double slack);

  // ---- the union on the grid ----------------------------------------------------------------
  /// The receiver's outline on the grid (receiver_), counter-clockwise, with its length in the
  /// chart (receiver_length_) and a bound on the distance from its grid points to the exact
  /// outline (receiver_rho_). A tile of a box (chart_is_box): its rectangle. A tile of another
  /// face: the face's outline clipped to the tile's box in doubles (Sutherland-Hodgman, which
  /// may leave zero-width bridges along the box: no area under the non-zero rule), whose new
  /// vertices are a few ulps from the exact crossings. Once per job.
  void set_up_receiver();

  bool unite();
  /// Areas only on a convex receiver that is not its chart box: every cast (each convex) clipped
  /// exactly to the receiver's grid outline (fast/window_clip.hpp) into windowed_. False, with
  /// nothing done, when the outline or some cast is not convex on the grid.
  bool clip_casts_to_window();
  /// The clipped casts' total length in the chart (perimeters plus 2 rho per vertex), for the
  /// bound when a cluster of them goes through Clipper.
  [[nodiscard]] double windowed_length() const;
  /// Whether the receiver's grid outline is convex (window_, counter-clockwise; set up once).
  bool convex_window();

  // ---- fragments: the union's cells on the receiver's plane ---------------------------------
  /// The lit and shadow cells, or false (the exact engine) when they do not partition the
  /// receiver as the union measured it, within the bound.
  bool emit_fragments();

  /// The tree's regions as cells; their twice areas (grid units) added to `cells2`.
  bool emit(const CL::PolyTree& tree, bool lit, Int128& cells2);

  // Inputs.
  const core::PreparedScene& ctx_;
  FastWorker& w_;
  const Scene& scene_;
  const std::vector<core::FacePrep>& prep_;
  const core::CullScene& cull_;
  std::size_t face_id_, light_id_;
  const Light& light_;
  const core::LightSpaceGrid* grid_index_;
  bool polygons_;
  const Face& face_;
  const core::FacePrep& fp_;  // the tile's (its chart box) when computing a tile
  const bool tile_;
  const std::size_t split_above_;
  // Outputs.
  FaceLighting& out_;
  std::vector<Fragment>& fragments_;
  ShadowStats& stats_;
  ShadowStats local_;
  // The worker's vectors (ReceiverScratch), emptied for this job; the members below that are
  // references name parts of it.
  ReceiverScratch& s_;
  // The receiver's frame and the projection.
  Receiver rc_;
  FastReceiver fr_;  // holds a reference to rc_
  double max_delta_ = 0, parallel_delta_ = 0;
  Grid grid_;
  double rho_ = 0;
  // The casts and the bound.
  CL::Paths&casts_, &maybe_;  // maybe_: footprints of nearly coplanar casters
  bool covered_ = false;      // a cast covers the whole box or convex outline (areas only): the shadow is it
  std::size_t face_casts_ = 0;  // casts added by cast_face: those share edges (solids' hulls rarely do)
  LitAreaBound bound_;
  double cast_length_ = 0;  // total perimeter of the grid polygons given to Clipper
  bool not_finite_ = false;  // overflow in doubles (coordinates near 1e150): exact engine
  double scale_ = 0, cell_ = 0;
  // Scratch.
  geometry::UnfilledVector<CGAL::Sign>& vsign_;
  std::vector<CGAL::Sign>& psign_;
  std::vector<char>& unsure_;
  ChartPoints&points_, &hull_;
  Cast& cast_;
  CL::Path& receiver_;
  bool receiver_ready_ = false;                    // receiver_ and the two below set up
  double receiver_length_ = 0, receiver_rho_ = 0;  // see set_up_receiver
  ChartPoints& outline_;
  CL::Path& window_;           // receiver_ counter-clockwise, for clip_casts_to_window
  int window_convex_ = -1;     // convex_window(): -1 not known yet
  CL::Paths& windowed_;        // the casts clipped to it
  CL::PolyTree&shadow_tree_, &lit_tree_;
  Int128 shadow_tree2_ = 0;  // twice shadow_tree_'s area (holes negative), grid units
  std::vector<CL::Paths>& regions_;
  CL::Paths& cells_;
  std::size_t fragment_id_ = 0;
};

}  // namespace shadow::fast::receiver_job
