// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path: the exact engine's pipeline (cull, clip to the slab and the prism or pyramid,
// project onto the receiver's chart) in doubles, and the union with Clipper (int64) on a grid
// fitted to the receiver's chart box, then a bound on the lit-area error.
//
// What stays exact: which side of the receiver's plane every caster vertex is on when both
// faces are exactly planar (Epick's orientation predicate on the input doubles, as in the exact
// engine), whether the receiver faces the light (a double test with an error bound, else the
// exact engine), the grid polygons' areas (128-bit integers). Faces planar only within tolerance
// use the exact engine's lifted planes in doubles: sides that doubles cannot tell are taken as
// "on the plane" and charged to delta; nearly coplanar casters are bracketed between two unions. What is not: projected and clipped points (doubles, each within an
// estimated `delta` of the true point) and their rounding to the grid (within half a step per
// axis). A point that moves by at most r can change which polygons cover a point x only if x
// is within r of a polygon's boundary, so
//
//   |area(P ∩ union Q_i) - area(P' ∩ union Q'_i)|  <=  sum_i (2 r_i L_i + pi r_i^2) + tube(P),
//
// with L_i the perimeter of caster polygon i and tube(P) the same for the receiver (0 when it
// is its own chart box, whose corners are grid points), plus the same for Clipper's rounding of
// the intersection points it creates (under 2 rho, on a boundary no longer than sum L_i + L_P).
// That is `lit_area_error_bound`, times the chart-to-3D area factor, plus a few ulps of the
// final roundings.
#include "fast/fast_receiver.hpp"

#include "fast/error_bound.hpp"
#include "fast/cluster_union.hpp"
#include "fast/strip_union.hpp"
#include "geometry/clip_convex.hpp"
#include "geometry/exact_facing.hpp"
#include "geometry/newell_normal.hpp"
#include "geometry/unit_vector.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <polyclipping/clipper.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>

namespace shadow::fast {
namespace {

using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
namespace CL = ClipperLib;
__extension__ typedef __int128 Int128;  // exact shoelace sums of int64 grid coordinates

constexpr double kEps = std::numeric_limits<double>::epsilon();  // 2^-52
// Grid half-range: Clipper 6.4 stays in its fast 64-bit mode for |coordinates| <= 2^30 - 1.
constexpr CL::cInt kHalf = (CL::cInt(1) << 30) - 2;

EK::Point_3 epick(const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); }

/// Twice the signed area of a grid polygon, exactly (fast/cluster_union.hpp).
Int128 area2(const CL::Path& path) { return twice_area(path); }

double perimeter(const std::vector<glm::dvec2>& poly) {
  double length = 0;
  for (std::size_t a = 0; a < poly.size(); ++a) length += glm::length(poly[(a + 1) % poly.size()] - poly[a]);
  return length;
}

/// Sutherland-Hodgman clip of a convex polygon to x[c] >= bound (lower) or <= bound (upper)
/// (geometry/clip_convex.hpp). Crossing points get the bound exactly in coordinate c. In doubles a
/// vertex is inside or outside (side +1 or -1), never on the boundary: as before the one walk.
void clip_axis(std::vector<glm::dvec2>& poly, int c, double bound, bool lower, std::vector<glm::dvec2>& scratch) {
  auto side = [&](std::size_t a) {
    const glm::dvec2& p = poly[a];
    return (lower ? p[c] >= bound : p[c] <= bound) ? 1 : -1;
  };
  geometry::clip_convex(poly, side, [&](std::size_t a, std::size_t b) {
    const glm::dvec2& p = poly[a];
    const glm::dvec2& q = poly[b];
    const double t = std::clamp((bound - p[c]) / (q[c] - p[c]), 0.0, 1.0);
    glm::dvec2 x = p + t * (q - p);
    x[c] = bound;
    return x;
  }, scratch);
  poly.swap(scratch);
}

/// Homogeneous chart point (X, Z, w) of a central projection; the chart point is (X, Z) / w.
struct Hom {
  double x, z, w;
};

/// Clip of a convex homogeneous polygon to f(p) >= 0 for a linear f (geometry/clip_convex.hpp;
/// side +1 or -1 as in clip_axis).
template <class F>
void clip_hom(std::vector<Hom>& poly, F f, std::vector<Hom>& scratch) {
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

/// Convex hull (counter-clockwise, Andrew's monotone chain) in doubles.
void convex_hull(std::vector<glm::dvec2>& pts, std::vector<glm::dvec2>& hull) {
  std::sort(pts.begin(), pts.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  hull.clear();
  if (pts.size() < 3) {
    hull = pts;
    return;
  }
  auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  hull.resize(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  hull.resize(k - 1);
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
  /// The side of a caster vertex that the exact engine would see, or `unsure` when doubles cannot
  /// tell (|s| within the error, plus `slack`: how far the exact engine lifts that vertex).
  [[nodiscard]] CGAL::Sign side(const glm::dvec3& y, bool caster_planar, double slack, bool& unsure) const {
    unsure = false;
    if (exact_sides && caster_planar) return side(y);
    const double value = s(y), tolerance = s_error + slack;
    if (value > tolerance) return CGAL::POSITIVE;
    if (value < -tolerance) return CGAL::NEGATIVE;
    unsure = true;
    return CGAL::ZERO;  // taken as on the plane; the caller charges the difference
  }
};

/// One projected caster polygon in the chart with its estimated double error.
struct Cast {
  std::vector<glm::dvec2> poly;
  double delta = 0;         ///< bound on each vertex's distance to the exact point
  double free_length = 0;   ///< perimeter before the box clip (directional), for the bound
};


class FastReceiver {
 public:
  explicit FastReceiver(const Receiver& rc) : rc_(rc) {}

  /// Directional light: the front part of a convex piece (exact signs), projected, clipped to
  /// the box. False: ill-conditioned (handed to the exact engine).
  bool project_parallel(const std::vector<glm::dvec3>& v, const std::vector<int>& piece,
                        const std::vector<CGAL::Sign>& sign, Cast& cast) {
    cast.poly.clear();
    cast.delta = base_delta_ + position_error_ * (1 + glm::length(rc_.shift));
    const std::size_t m = piece.size();
    for (std::size_t a = 0; a < m; ++a) {
      const glm::dvec3& va = v[piece[a]];
      const CGAL::Sign sa = sign[a], sb = sign[(a + 1) % m];
      if (sa == CGAL::POSITIVE) cast.poly.push_back(project(va));
      if (sa == CGAL::ZERO) cast.poly.push_back(chart(va));
      if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE)) {
        glm::dvec3 x;
        if (!crossing(va, v[piece[(a + 1) % m]], x, cast.delta)) return false;
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
      const CGAL::Sign sa = sign[a], sb = sign[(a + 1) % m];
      if (sa == CGAL::POSITIVE) hom_.push_back(homogeneous(va - rc_.corner));
      if (sa == CGAL::ZERO) {
        const glm::dvec3 y = va - rc_.corner;
        hom_.push_back({L * y[rc_.i], L * y[rc_.j], L});
      }
      if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE)) {
        glm::dvec3 x;
        if (!crossing(va, v[piece[(a + 1) % m]], x, cross_delta)) return false;
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

  glm::dvec2 chart(const glm::dvec3& y) const { return {y[rc_.i], y[rc_.j]}; }

  glm::dvec2 project(const glm::dvec3& y) const {
    const double s = rc_.s(y);
    return {y[rc_.i] - s * rc_.shift.x, y[rc_.j] - s * rc_.shift.y};
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
    for (int c = 0; c < 2 && cast.poly.size() >= 3; ++c) {
      clip_axis(cast.poly, c, rc_.lo[c], true, scratch_);
      clip_axis(cast.poly, c, rc_.hi[c], false, scratch_);
    }
    for (glm::dvec2& p : cast.poly)
      p = glm::clamp(p, glm::dvec2(rc_.lo[0], rc_.lo[1]), glm::dvec2(rc_.hi[0], rc_.hi[1]));
    return cast.delta <= max_delta_;
  }

 private:
  const Receiver& rc_;
  double base_delta_ = 0, max_delta_ = 0, position_error_ = 0, s_extra_ = 0;
  std::vector<glm::dvec2> scratch_;
  std::vector<Hom> hom_, scratch_hom_;
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
    return static_cast<CL::cInt>(std::llround(g)) - kHalf;
  }
  CL::IntPoint point(const glm::dvec2& p) const { return {to_int(p.x, 0), to_int(p.y, 1)}; }
  glm::dvec2 chart(const CL::IntPoint& p) const {
    return {p.X == kHalf ? hi[0] : lo[0] + static_cast<double>(p.X + kHalf) * step[0],
            p.Y == kHalf ? hi[1] : lo[1] + static_cast<double>(p.Y + kHalf) * step[1]};
  }
  /// Bound on the distance between a chart point and its grid point (half a step per axis).
  double rounding() const { return 0.5 * std::hypot(step[0], step[1]) * (1 + 8 * kEps); }
};

/// Whether a boundary visits some grid point twice (touches itself).
bool has_repeated_vertex(CL::Path path) {
  std::sort(path.begin(), path.end(), [](const CL::IntPoint& a, const CL::IntPoint& b) {
    return a.X < b.X || (a.X == b.X && a.Y < b.Y);
  });
  return std::adjacent_find(path.begin(), path.end()) != path.end();
}

/// Regions (outer boundary with its holes) of a PolyTree, at every nesting level.
void regions_of(const CL::PolyNode& node, std::vector<CL::Paths>& regions) {
  for (const CL::PolyNode* outer : node.Childs) {
    CL::Paths region{outer->Contour};
    for (const CL::PolyNode* hole : outer->Childs) {
      region.push_back(hole->Contour);
      regions_of(*hole, regions);
    }
    regions.push_back(std::move(region));
  }
}

/// Splits a region (outer boundary and holes) into simple cells without holes: cut it with a
/// vertical line through the middle of its median hole (by x), then the two sides likewise.
/// Every hole is eventually cut by a line through its middle and opens onto the cut; halving
/// keeps the work at O(n log n) Boolean operations' worth for a ground face with n holes.
void simple_cells(const CL::Paths& region, CL::Paths& cells, int depth = 0, bool split_touching = true) {
  if (region.size() == 1 && split_touching && has_repeated_vertex(region[0])) {
    // A boundary that touches itself at a vertex: Clipper's strictly simple output splits it
    // there (done only here: on whole unions it costs quadratic point-in-polygon tests).
    CL::Clipper clipper;
    clipper.StrictlySimple(true);
    clipper.AddPaths(region, CL::ptSubject, true);
    CL::PolyTree tree;
    clipper.Execute(CL::ctUnion, tree, CL::pftNonZero, CL::pftNonZero);
    std::vector<CL::Paths> pieces;
    regions_of(tree, pieces);
    for (const CL::Paths& piece : pieces) simple_cells(piece, cells, depth + 1, false);
    return;
  }
  if (region.size() == 1 || depth > 64) {
    for (const CL::Path& p : region)
      if (area2(p) > 0) cells.push_back(p);
    return;
  }
  CL::cInt xmin = std::numeric_limits<CL::cInt>::max(), xmax = std::numeric_limits<CL::cInt>::min();
  CL::cInt ymin = xmin, ymax = xmax;
  std::vector<CL::cInt> middles;
  for (std::size_t h = 0; h < region.size(); ++h) {
    CL::cInt lo = std::numeric_limits<CL::cInt>::max(), hi = std::numeric_limits<CL::cInt>::min();
    for (const CL::IntPoint& p : region[h]) {
      lo = std::min(lo, p.X);
      hi = std::max(hi, p.X);
      ymin = std::min(ymin, p.Y);
      ymax = std::max(ymax, p.Y);
    }
    xmin = std::min(xmin, lo);
    xmax = std::max(xmax, hi);
    if (h > 0) middles.push_back(lo + (hi - lo) / 2);
  }
  std::nth_element(middles.begin(), middles.begin() + static_cast<std::ptrdiff_t>(middles.size() / 2), middles.end());
  const CL::cInt cut = std::clamp(middles[middles.size() / 2], xmin, xmax);
  for (int side = 0; side < 2; ++side) {
    const CL::cInt x0 = side == 0 ? xmin : cut, x1 = side == 0 ? cut : xmax;
    if (x1 <= x0) continue;
    const CL::Path half{{x0, ymin}, {x1, ymin}, {x1, ymax}, {x0, ymax}};
    CL::Clipper clipper;
    clipper.StrictlySimple(false);
    // (Not strictly simple here: cells that touch themselves are split when they come out.)
    clipper.AddPaths(region, CL::ptSubject, true);
    clipper.AddPath(half, CL::ptClip, true);
    CL::PolyTree tree;
    clipper.Execute(CL::ctIntersection, tree, CL::pftNonZero, CL::pftNonZero);
    std::vector<CL::Paths> pieces;
    regions_of(tree, pieces);
    for (const CL::Paths& piece : pieces) simple_cells(piece, cells, depth + 1);
  }
}

/// One receiver under one light on the fast path, in named steps (compute_receiver runs them in
/// order). Every step that returns false sends the receiver to the exact engine.
class ReceiverJob {
 public:
  ReceiverJob(const Context& ctx, Worker& w, std::size_t face_id, std::size_t light_id, const Light& light,
              const core::LightSpaceGrid* grid_index, bool polygons, FaceLighting& out,
              std::vector<Fragment>& fragments, ShadowStats& stats, const core::TileRequest& tiles)
      : ctx_(ctx), w_(w), scene_(*ctx.scene), prep_(*ctx.prep), cull_(*ctx.cull), face_id_(face_id),
        light_id_(light_id), light_(light), grid_index_(grid_index), polygons_(polygons), face_(scene_.faces[face_id]),
        fp_(tiles.tile ? *tiles.tile : prep_[face_id]), tile_(tiles.tile != nullptr),
        split_above_(tiles.tile ? 0 : tiles.split_above), out_(out), fragments_(fragments), stats_(stats), fr_(rc_) {}

  /// Set by run() when it returned Outcome::Split.
  std::size_t split_candidates = 0;

  Outcome run_job() {
    const bool done = run();
    if (split_candidates > 0) return Outcome::Split;
    return done ? Outcome::Done : Outcome::Exact;
  }

 private:
  bool run() {
    out_ = FaceLighting{};
    out_.face_id = face_id_;
    out_.light_id = light_id_;
    out_.area = (*ctx_.face_area)[face_id_];
    ++local_.receivers;
    if (fp_.degenerate) return commit();
    if (!set_up_frame()) return false;
    int facing = 0;
    if (!decide_facing(facing)) return false;
    if (facing <= 0) {  // attached shadow, as in the exact engine
      ++local_.back_facing;
      out_.shadow_area = out_.area;
      if (polygons_ && !push_whole_face(false)) return false;
      return commit();
    }
    out_.faces_light = true;
    if (split_above_ > 0 && grid_index_ && core::tileable(fp_)) {
      // A directional light: decided from the light-space grid's count (an upper bound on the
      // candidates, without culling each of them: for a ground, culling is most of an item).
      const std::size_t potential = grid_index_->count(face_id_);
      if (potential > split_above_) {
        split_candidates = potential;  // the engine splits it into tiles; nothing counted
        return true;
      }
    }
    const std::vector<std::size_t>& candidates = gather_casters();
    if (split_above_ > 0 && !grid_index_ && candidates.size() > split_above_ && core::tileable(fp_)) {
      split_candidates = candidates.size();
      return true;
    }
    if (!set_up_projection()) return false;
    if (!cast_all(candidates)) return false;
    scale_ = 1.0 / std::abs(rc_.normal[rc_.k]);  // chart area -> 3D area
    if (casts_.empty() && maybe_.empty()) {
      ++local_.unshadowed;
      out_.lit_area = out_.area;
      out_.lit_fraction = 1.0;
      if (polygons_ && tile_ && !fp_.chart_is_box) {
        // A tile's part of a face that is not a box is made on the grid (its fragment): its
        // outline's rounding in the bound, as for a shadowed one. Areas only, the tile's
        // shadow is exactly nothing and the outline is not made.
        set_up_receiver();
        bound_.receiver_outline(receiver_length_, receiver_rho_);
      }
      out_.lit_area_error_bound = bound_.unshadowed(scale_);
      if (!std::isfinite(out_.lit_area_error_bound)) return false;
      if (polygons_ && !push_whole_face(true)) return false;
      return commit();
    }
    if (!unite()) return false;
    if (!polygons_) return commit();
    if (!emit_fragments()) return false;  // the caller drops what was appended
    return commit();
  }

 private:
  /// Adds this receiver's counts to the caller's (only on success: a fallback leaves stats as
  /// they were, so local_.fast_exact_fallbacks is 0 here).
  bool commit() {
    stats_ += local_;
    return true;
  }

  // ---- receiver frame: plane, normal and their error bounds ---------------------------------
  bool set_up_frame() {
    rc_.k = fp_.axis;
    rc_.i = core::chart_i(fp_.axis);
    rc_.j = core::chart_j(fp_.axis);
    rc_.flipped = fp_.flipped;
    rc_.lo = fp_.chart_min;
    rc_.hi = fp_.chart_max;
    rc_.magnitude = std::max({std::abs(rc_.lo[0]), std::abs(rc_.lo[1]), std::abs(rc_.hi[0]), std::abs(rc_.hi[1])}) +
                    glm::length(cull_.origin) + cull_.diameter;
    if (fp_.exactly_planar) {
      const glm::dvec3& corner = face_.vertices[fp_.corner[1]];
      const glm::dvec3& next = face_.vertices[fp_.corner[2]];
      const glm::dvec3& prev = face_.vertices[fp_.corner[0]];
      rc_.c0 = epick(corner);
      rc_.c1 = epick(next);
      rc_.c2 = epick(prev);
      rc_.corner = corner;
      const glm::dvec3 u = next - corner, v = prev - corner;
      glm::dvec3 n = glm::cross(u, v);
      if (fp_.flipped) n = -n;
      const double nlen = glm::length(n);
      if (!(nlen > 0) || !std::isfinite(nlen)) return false;
      rc_.normal = n / nlen;
      // Rounded differences and products: the direction error grows with 1/sin(corner angle).
      rc_.normal_error = 8 * kEps * glm::length(u) * glm::length(v) / nlen + 4 * kEps;
      rc_.scene_reach = (glm::length(corner - cull_.origin) + cull_.diameter) * (1 + 1e-9);
      rc_.s_error = 2 * (rc_.normal_error + 4 * kEps) * rc_.scene_reach;
    } else {
      // Planar only within tolerance: the exact engine lifts the face onto the plane through its
      // centroid with its Newell normal (docs/numeric-contract.md); the same plane in doubles.
      rc_.exact_sides = false;
      const std::vector<glm::dvec3>& p = face_.vertices;
      const std::size_t m = p.size();
      glm::dvec3 n(0.0), centroid(0.0);
      double rounding = 0, largest = 0;
      for (std::size_t a = 0; a < m; ++a) {
        const glm::dvec3 u = p[a] - p[0], v = p[(a + 1) % m] - p[0];
        n += geometry::newell_term(u, v);
        rounding += glm::length(u - v) * (glm::length(u) + glm::length(v));
        centroid += p[a];
        largest = std::max({largest, std::abs(p[a].x), std::abs(p[a].y), std::abs(p[a].z)});
      }
      const double nlen = glm::length(n);
      if (!(nlen > 0) || !std::isfinite(nlen)) return false;
      rc_.normal = n / nlen;
      rc_.corner = centroid / static_cast<double>(m);
      rc_.normal_error = 8 * kEps * rounding / nlen + 8 * kEps;
      rc_.scene_reach = (glm::length(rc_.corner - cull_.origin) + cull_.diameter) * (1 + 1e-9);
      rc_.s_error = 2 * (rc_.normal_error + 4 * kEps) * rc_.scene_reach + 4 * kEps * static_cast<double>(m + 2) * largest;
    }
    return true;
  }

  /// The face's outline as one fragment, wholly lit or wholly in shadow: its own vertices, or
  /// lifted onto the plane in doubles. False when that outline is not a simple polygon of
  /// certainly non-zero area in doubles (a sliver face): the exact engine writes it then.
  bool push_whole_face(bool lit) {
    const glm::dvec3 corner = rc_.corner;
    if (tile_ && !fp_.chart_is_box) {
      // A tile's part of a face that is not a box: the face's outline cut to the tile, on the
      // grid (set up in run() before this is called), in cells like any region.
      if (!(grid_.step[0] > 0) || !(grid_.step[1] > 0)) return false;  // (not set up: exact engine)
      set_up_receiver();
      cell_ = grid_.step[0] * grid_.step[1] * scale_;
      try {
        CL::Clipper clipper;
        clipper.StrictlySimple(false);
        clipper.AddPath(receiver_, CL::ptSubject, true);
        clipper.Execute(CL::ctUnion, lit_tree_, CL::pftNonZero, CL::pftNonZero);
        return emit(lit_tree_, lit);
      } catch (const CL::clipperException&) {
        return false;
      }
    }
    if (tile_) {  // the tile's rectangle (in the face: chart_is_box) lifted onto the plane
      Fragment f;
      f.face_id = face_id_;
      f.light_id = light_id_;
      f.lit = lit;
      const double x[4] = {fp_.chart_min[0], fp_.chart_max[0], fp_.chart_max[0], fp_.chart_min[0]};
      const double y[4] = {fp_.chart_min[1], fp_.chart_min[1], fp_.chart_max[1], fp_.chart_max[1]};
      for (int a = 0; a < 4; ++a) {
        glm::dvec3 v;
        v[rc_.i] = x[a];
        v[rc_.j] = y[a];
        v[rc_.k] = corner[rc_.k] - (rc_.normal[rc_.i] * (x[a] - corner[rc_.i]) +
                                    rc_.normal[rc_.j] * (y[a] - corner[rc_.j])) / rc_.normal[rc_.k];
        f.polygon.push_back(v);
      }
      f.area = (fp_.chart_max[0] - fp_.chart_min[0]) * (fp_.chart_max[1] - fp_.chart_min[1]) / std::abs(rc_.normal[rc_.k]);
      if (fp_.flipped) std::reverse(f.polygon.begin(), f.polygon.end());
      if (!core::clean_double_polygon(f.polygon, fp_.axis)) return false;
      fragments_.push_back(std::move(f));
      return true;
    }
    Fragment f;
    f.face_id = face_id_;
    f.light_id = light_id_;
    f.lit = lit;
    f.area = out_.area;
    f.polygon = face_.vertices;
    if (!fp_.exactly_planar)
      for (glm::dvec3& y : f.polygon)
        y[rc_.k] = corner[rc_.k] - (rc_.normal[rc_.i] * (y[rc_.i] - corner[rc_.i]) +
                                    rc_.normal[rc_.j] * (y[rc_.j] - corner[rc_.j])) / rc_.normal[rc_.k];
    if (!core::clean_double_polygon(f.polygon, fp_.axis)) return false;
    fragments_.push_back(std::move(f));
    return true;
  }

  // ---- facing: exact where the double test could be wrong -----------------------------------
  bool decide_facing(int& facing) {
    const glm::dvec3 corner = rc_.corner;
    if (light_.type == LightType::Point) {
      rc_.point = true;
      rc_.light_rel = light_.position - corner;
      rc_.light_side = glm::dot(rc_.normal, rc_.light_rel);
      if (fp_.exactly_planar) {
        facing = rc_.side(light_.position);
      } else {
        const double error = 2 * (rc_.normal_error + 4 * kEps) * glm::length(rc_.light_rel) + rc_.s_error;
        if (std::abs(rc_.light_side) <= error) return false;
        facing = rc_.light_side > 0 ? 1 : -1;
      }
      // The light so close to the receiver's plane that s at the light is unsure: exact engine.
      if (facing > 0 && !(rc_.light_side > 64 * rc_.normal_error * glm::length(rc_.light_rel))) return false;
    } else {
      const glm::dvec3 d = geometry::unit(light_.to_light);
      const double nd = glm::dot(rc_.normal, d);
      if (std::abs(nd) <= 64 * rc_.normal_error) {
        // Grazing: the exact engine decides, unless the sun is exactly in the receiver's plane
        // (an east or west wall at solar noon): then the face is edge-on, an attached shadow in
        // the exact engine too, and one exact determinant says so.
        if (!fp_.exactly_planar || geometry::exact_facing_sign(face_.vertices[fp_.corner[1]], face_.vertices[fp_.corner[2]],
                                                                 face_.vertices[fp_.corner[0]], light_.to_light) != 0) return false;
        facing = 0;
        return true;
      }
      facing = nd > 0 ? 1 : -1;
      rc_.inv_light_side = 1.0 / nd;
      rc_.shift = glm::dvec2(d[rc_.i], d[rc_.j]) * rc_.inv_light_side;
    }
    return true;
  }

  // ---- culling: the exact engine's tests ----------------------------------------------------
  const std::vector<std::size_t>& gather_casters() {
    const core::ReceiverCuller culler(cull_, fp_, face_id_, light_);
    const std::vector<std::size_t>& candidates =
        w_.casters.gather(culler, prep_, face_id_, grid_index_, tile_ ? &cull_ : nullptr, tile_ ? &fp_ : nullptr,
                          ctx_.solid_of);
    local_.candidate_pairs += candidates.size();
    return candidates;
  }

  // ---- projection in doubles: tolerances and the grid ---------------------------------------
  bool set_up_projection() {
    max_delta_ = std::ldexp(std::max(rc_.hi[0] - rc_.lo[0], rc_.hi[1] - rc_.lo[1]), -20);
    if (!rc_.point) {
      // |error| of a projected point: s's error times |shift|, shift's error times |s|, roundings.
      const double e = rc_.normal_error + 8 * kEps, g = std::abs(rc_.inv_light_side), R = rc_.scene_reach;
      const double shift = glm::length(rc_.shift);
      parallel_delta_ = 2 * (shift * e * R + R * e * g * g + 2 * kEps * (rc_.magnitude + R * shift));
      if (parallel_delta_ > max_delta_) return false;  // grazing light: the exact engine is better
    }
    fr_.set_tolerances(parallel_delta_, max_delta_);
    grid_ = Grid(rc_.lo, rc_.hi);
    rho_ = grid_.rounding();
    return true;
  }

  /// Puts a projected cast polygon on the grid and into the union (or the bound, when it
  /// collapsed). Sets not_finite_ on overflow.
  void add_cast(Cast& c) {
    if (c.poly.size() < 3) {
      bound_.clipped_away(c.free_length, c.delta + 4 * kEps * rc_.magnitude);
      not_finite_ |= !bound_.finite();
      return;
    }
    for (const glm::dvec2& p : c.poly) not_finite_ |= !std::isfinite(p.x) || !std::isfinite(p.y);
    not_finite_ |= !std::isfinite(c.delta);
    if (not_finite_) return;
    CL::Path path;
    path.reserve(c.poly.size());
    for (const glm::dvec2& p : c.poly) {
      const CL::IntPoint ip = grid_.point(p);
      if (path.empty() || !(path.back() == ip)) path.push_back(ip);
    }
    while (path.size() > 1 && path.front() == path.back()) path.pop_back();
    const double r = rho_ + c.delta + 4 * kEps * rc_.magnitude;
    const double n_vertices = static_cast<double>(c.poly.size());
    const double length = perimeter(c.poly);
    bound_.cast_polygon(c.free_length, length, n_vertices, c.delta, r);
    const Int128 a2 = path.size() >= 3 ? area2(path) : 0;
    if (a2 == 0) {  // collapsed on the grid: its true area is within the bound just added
      double twice_area = 0;  // edge-on casters have no area in doubles either: not counted
      for (std::size_t a = 0; a < c.poly.size(); ++a) {
        const glm::dvec2& p = c.poly[a];
        const glm::dvec2& q = c.poly[(a + 1) % c.poly.size()];
        twice_area += p.x * q.y - q.x * p.y;
      }
      if (twice_area != 0) ++local_.fast_collapsed;
      return;
    }
    if (a2 < 0) std::reverse(path.begin(), path.end());
    // Areas only on a box receiver: a convex cast that fills the whole chart box (on the grid,
    // the box is [-kHalf, kHalf]^2) is the shadow; no later caster can change that, and its own
    // rounding is in the bound already (a low sun shadows many walls wholly).
    const Int128 box2 = 2 * static_cast<Int128>(2 * kHalf) * (2 * kHalf);
    if (!polygons_ && fp_.chart_is_box && (a2 == box2 || a2 == -box2) && is_convex_ccw(path)) covered_ = true;
    casts_.push_back(std::move(path));
    cast_length_ += length + 2 * n_vertices * rho_;
  }

  // ---- the casters, by route ----------------------------------------------------------------
  bool cast_all(const std::vector<std::size_t>& candidates) {
    const int own_solid = (*ctx_.solid_of)[face_id_];
    for (std::size_t q : candidates) {
      const int solid = (*ctx_.solid_of)[q];
      if (solid >= 0 && (solid == own_solid || w_.casters.solid_done(solid))) continue;
      if (solid >= 0 && !rc_.point && rc_.exact_sides) {
        if (!cast_convex_solid(solid)) return false;
        if (covered_) break;
        continue;
      }
      if (!cast_face(q)) return false;
      if (covered_) break;  // the whole box is in shadow: the other casters cannot add to it
    }
    return true;
  }

  /// A convex solid casts the hull of its projection, as in the exact engine (directional
  /// light, exactly planar receiver).
  bool cast_convex_solid(int solid) {
    w_.casters.mark_solid_done(solid);
    const core::ConvexSolid& cs = (*ctx_.solids)[solid];
    vsign_.resize(cs.vertices.size());
    bool any_front = false;
    for (std::size_t a = 0; a < cs.vertices.size(); ++a) {
      vsign_[a] = rc_.side(cs.vertices[a]);
      any_front |= vsign_[a] == CGAL::POSITIVE;
    }
    if (!any_front) return true;
    points_.clear();
    for (std::size_t a = 0; a < cs.vertices.size(); ++a) {
      if (vsign_[a] == CGAL::POSITIVE) points_.push_back(fr_.project(cs.vertices[a]));
      if (vsign_[a] == CGAL::ZERO) points_.push_back(fr_.chart(cs.vertices[a]));
    }
    double cross_delta = 0;
    for (const auto& [a, b] : cs.edges) {
      const CGAL::Sign sa = vsign_[a], sb = vsign_[b];
      if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE)) {
        glm::dvec3 x;
        if (!fr_.crossing(cs.vertices[a], cs.vertices[b], x, cross_delta)) return false;
        points_.push_back(fr_.chart(x));
      }
    }
    convex_hull(points_, hull_);
    cast_.poly = hull_;
    // The hull of points each within delta of the exact ones is within delta of the exact hull.
    cast_.delta = std::max(parallel_delta_, cross_delta);
    if (cast_.poly.size() < 3) {  // flat in doubles: the exact hull is at most a sliver
      bound_.flat_solid(perimeter(cast_.poly), cast_.delta + 4 * kEps * rc_.magnitude);
      return true;
    }
    cast_.free_length = perimeter(cast_.poly);
    if (!fr_.clip_to_box(cast_)) return false;
    const std::size_t before = casts_.size();
    add_cast(cast_);
    if (not_finite_) return false;
    if (casts_.size() > before) ++local_.casting_pairs;
    return true;
  }

  /// A caster face, convex piece by convex piece: projected in front of the receiver (parallel
  /// or central projection), or, for pieces nowhere clearly in front, a sliver in the bound or a
  /// nearly coplanar footprint.
  bool cast_face(std::size_t q) {
    const core::FacePrep& qp = prep_[q];
    const Face& qface = scene_.faces[q];
    const core::CullFace& cq = cull_.faces[q];
    if (rc_.point) {
      if (qp.exactly_planar) {
        if (CGAL::orientation(epick(qface.vertices[qp.corner[1]]), epick(qface.vertices[qp.corner[2]]),
                              epick(qface.vertices[qp.corner[0]]), epick(light_.position)) == CGAL::COPLANAR)
          return true;  // edge-on to the light: casts nothing
      } else {
        // A lifted caster nearly edge-on to the light: leave the receiver to the exact engine.
        const glm::dvec3 l = light_.position - cull_.origin;
        if (std::abs(glm::dot(cq.normal, l) + cq.offset) <=
            (1e-9 + cq.normal_error) * (glm::length(l) + cull_.diameter) + cq.slack)
          return false;
      }
    }
    // A lifted caster's vertices are up to `slack` from where the exact engine puts them.
    const double slack = qp.exactly_planar ? 0.0 : cq.slack;
    vsign_.resize(qface.vertices.size());
    unsure_.resize(qface.vertices.size());
    bool any_front = false, any_unsure = false;
    for (std::size_t a = 0; a < qface.vertices.size(); ++a) {
      bool u = false;
      vsign_[a] = rc_.side(qface.vertices[a], qp.exactly_planar, slack, u);
      unsure_[a] = u;
      any_front |= vsign_[a] == CGAL::POSITIVE;
      any_unsure |= u;
    }
    if (!any_front && !any_unsure) return true;
    // A vertex of unsure side, taken as on the plane, is within (its s error) / sin(angle between
    // the planes) of where the exact clip puts the boundary.
    double unsure_shift = 0;
    if (any_unsure) {
      const double sine = glm::length(glm::cross(rc_.normal, cq.normal));
      unsure_shift = 2 * (rc_.s_error + slack) / sine;
      if (!(unsure_shift <= max_delta_)) unsure_shift = std::numeric_limits<double>::infinity();
    }
    bool cast_any = false;
    for (const std::vector<int>& piece : qp.convex_pieces) {
      psign_.clear();
      bool piece_front = false, piece_unsure = false;
      for (int a : piece) {
        psign_.push_back(vsign_[a]);
        piece_front |= vsign_[a] == CGAL::POSITIVE;
        piece_unsure |= unsure_[a] != 0;
      }
      const double position = slack + (piece_unsure ? unsure_shift : 0.0);
      // Points within s_error + slack of the plane project to within this of their chart points.
      const double grow = rc_.point ? 2 * (1 + glm::length(rc_.light_rel) / rc_.light_side) : 1 + glm::length(rc_.shift);
      if (!piece_front) {
        if (!piece_unsure) continue;
        if (!cast_nearly_coplanar(qface, piece, position, grow, slack)) return false;
        continue;
      }
      if (!std::isfinite(position)) return false;  // nearly coplanar and partly in front: exact
      fr_.set_piece_error(position, rc_.s_error + slack);
      const bool ok = rc_.point ? fr_.project_central(qface.vertices, piece, psign_, cast_)
                                : fr_.project_parallel(qface.vertices, piece, psign_, cast_);
      fr_.set_piece_error(0, 0);
      if (!ok) return false;
      const std::size_t before = casts_.size();
      add_cast(cast_);
      if (not_finite_) return false;
      cast_any |= casts_.size() > before;
    }
    if (cast_any) ++local_.casting_pairs;
    return true;
  }

  /// A piece nowhere clearly in front, some vertex of unsure side: a sliver along the plane in
  /// the bound when its position is known, else (nearly coplanar with the receiver) its chart
  /// footprint, united separately: the shadow lies between the union without and with these.
  bool cast_nearly_coplanar(const Face& qface, const std::vector<int>& piece, double position, double grow,
                            double slack) {
    points_.clear();
    for (int a : piece) points_.push_back(fr_.chart(qface.vertices[a]));
    if (std::isfinite(position)) {  // the exact front part is at most a sliver along the plane
      bound_.unsure_sliver(perimeter(points_), (position + rc_.s_error) * grow + 4 * kEps * rc_.magnitude);
      return true;
    }
    // Its exact shadow lies somewhere inside its own chart footprint.
    cast_.poly = points_;
    cast_.delta = (rc_.s_error + slack) * grow;
    cast_.free_length = perimeter(cast_.poly);
    for (int c = 0; c < 2 && cast_.poly.size() >= 3; ++c) {
      clip_axis(cast_.poly, c, rc_.lo[c], true, hull_);
      clip_axis(cast_.poly, c, rc_.hi[c], false, hull_);
    }
    const std::size_t before = casts_.size();
    // A footprint may cast anything from nothing to itself: it never counts as filling the box.
    const bool covered_before = covered_;
    add_cast(cast_);
    covered_ = covered_before;
    if (not_finite_) return false;
    if (casts_.size() > before) {
      maybe_.push_back(std::move(casts_.back()));
      casts_.pop_back();
    }
    return true;
  }

  // ---- the union on the grid ----------------------------------------------------------------
  /// The receiver's outline on the grid (receiver_), counter-clockwise, with its length in the
  /// chart (receiver_length_) and a bound on the distance from its grid points to the exact
  /// outline (receiver_rho_). A tile of a box (chart_is_box): its rectangle. A tile of another
  /// face: the face's outline clipped to the tile's box in doubles (Sutherland-Hodgman, which
  /// may leave zero-width bridges along the box: no area under the non-zero rule), whose new
  /// vertices are a few ulps from the exact crossings. Once per job.
  void set_up_receiver() {
    if (receiver_ready_) return;
    receiver_ready_ = true;
    receiver_.clear();
    receiver_rho_ = rho_;
    receiver_length_ = 0;
    if (tile_ && fp_.chart_is_box) {
      const double x[4] = {fp_.chart_min[0], fp_.chart_max[0], fp_.chart_max[0], fp_.chart_min[0]};
      const double y[4] = {fp_.chart_min[1], fp_.chart_min[1], fp_.chart_max[1], fp_.chart_max[1]};
      for (int a = 0; a < 4; ++a) receiver_.push_back(grid_.point({x[a], y[a]}));
      return;  // (a box's outline adds nothing to the bound: its length is not used)
    }
    outline_.clear();
    for (int a : fp_.chart_ring) outline_.emplace_back(face_.vertices[a][rc_.i], face_.vertices[a][rc_.j]);
    if (tile_) {
      for (int c = 0; c < 2 && outline_.size() >= 3; ++c) {
        clip_axis(outline_, c, rc_.lo[c], true, hull_);
        if (outline_.size() >= 3) clip_axis(outline_, c, rc_.hi[c], false, hull_);
      }
      if (outline_.size() < 3) outline_.clear();  // only touches the tile: no area
      // A crossing's other coordinate: t = (m - p) / (q - p), p + t (q - p), each rounded (about
      // 6 eps of the magnitude), and up to four clips in a row each start from the last's
      // rounded crossings: 64 eps covers the chain with room.
      receiver_rho_ = rho_ + 64 * kEps * rc_.magnitude;
    }
    for (const glm::dvec2& p : outline_) receiver_.push_back(grid_.point(p));
    for (std::size_t a = 0; a < outline_.size(); ++a) {
      const glm::dvec2& p = outline_[a];
      const glm::dvec2& q = outline_[(a + 1) % outline_.size()];
      receiver_length_ += std::hypot(q.x - p.x, q.y - p.y);
    }
  }

  bool unite() {
    set_up_receiver();
    const double receiver_length = receiver_length_;
    if (!fp_.chart_is_box) bound_.receiver_outline(receiver_length, receiver_rho_);
    Int128 shadow2 = 0, gap2 = 0;
    double boundary2 = 0;  // twice the area of the clusters measured by their boundary (grid units)
    if (covered_) {
      shadow2 = 2 * static_cast<Int128>(2 * kHalf) * (2 * kHalf);
    } else try {
      // Many casts (a ground under a low sun): united in strips first (fast/strip_union.hpp),
      // and that union stands for the casts below (one more level of rounding), or, when it is
      // all that is asked for (areas only, a box receiver, no nearly coplanar footprints), its
      // area is the shadow's.
      const CL::Paths* casts = &casts_;
      CL::Paths united;
      double levels = 1;
      bool strips_only = false;
      EngineStripUnion& strips = engine_strip_union();
      if (casts_.size() > strips.options.threshold) {
        strips.used.fetch_add(1, std::memory_order_relaxed);
        const glm::dvec2 along = rc_.point ? glm::dvec2(0, 1) : rc_.shift;
        const int strip_levels =
            strip_union(casts_, along.x * grid_.scale[0], along.y * grid_.scale[1], united, strips.options);
        casts = &united;
        strips_only = fp_.chart_is_box && !polygons_ && maybe_.empty();
        levels = strip_levels + (strips_only ? 0 : 1);
      }
      const bool clustered = !strips_only && fp_.chart_is_box && !polygons_ && maybe_.empty();
      if (clustered) {
        // Areas only: the union's area cluster by cluster (fast/cluster_union.hpp). Clusters of
        // convex casts are measured by their boundary, without rounding intersection points:
        // their arithmetic bound replaces the union's rounding term.
        const glm::dvec2 along = rc_.point ? glm::dvec2(0, 1) : rc_.shift;
        const ClusteredArea area = clustered_union_area(*casts, along.x * grid_.scale[0], along.y * grid_.scale[1]);
        if (area.clipper) bound_.union_rounding(cast_length_, rho_);
        bound_.boundary_arithmetic(0.5 * area.boundary.error * grid_.step[0] * grid_.step[1]);
        shadow2 = area.exact2;
        boundary2 = area.boundary.twice_area;
      }
      // (A box receiver's edges meet the casts only at their vertices, already grid points.)
      if (!clustered)
        bound_.union_rounding(cast_length_ + (fp_.chart_is_box ? 0.0 : receiver_length * (1 + 1e-9)), levels * rho_);
      CL::Clipper clipper;
      clipper.StrictlySimple(false);
      if (!strips_only && !clustered) clipper.AddPaths(*casts, CL::ptSubject, true);
      // Casters are clipped to the chart box already: a rectangular receiver needs no intersection.
      const CL::ClipType op = fp_.chart_is_box ? CL::ctUnion : CL::ctIntersection;
      if (!fp_.chart_is_box && !strips_only) clipper.AddPath(receiver_, CL::ptClip, true);
      if (strips_only) {
        for (const CL::Path& p : united) shadow2 += area2(p);  // holes come out negative
      } else if (clustered) {
        // (measured above)
      } else if (polygons_) {
        clipper.Execute(op, shadow_tree_, CL::pftNonZero, CL::pftNonZero);
        CL::Paths all;
        CL::PolyTreeToPaths(shadow_tree_, all);
        for (const CL::Path& p : all) shadow2 += area2(p);
        CL::Clipper lit;
        lit.StrictlySimple(false);
        lit.AddPath(receiver_, CL::ptSubject, true);
        lit.AddPaths(*casts, CL::ptClip, true);
        lit.Execute(CL::ctDifference, lit_tree_, CL::pftNonZero, CL::pftNonZero);
      } else {
        CL::Paths shadow_paths;
        clipper.Execute(op, shadow_paths, CL::pftNonZero, CL::pftNonZero);
        for (const CL::Path& p : shadow_paths) shadow2 += area2(p);  // holes come out negative
      }
      if (!maybe_.empty()) {
        // The exact shadow lies between the union without and with the nearly coplanar casters'
        // footprints: report the middle, and half the gap in the bound (0 when they are covered,
        // as a box's bottom is by its walls' shadows).
        CL::Clipper with;
        with.AddPaths(*casts, CL::ptSubject, true);
        with.AddPaths(maybe_, CL::ptSubject, true);
        if (!fp_.chart_is_box) with.AddPath(receiver_, CL::ptClip, true);
        CL::Paths paths;
        with.Execute(op, paths, CL::pftNonZero, CL::pftNonZero);
        Int128 most = 0;
        for (const CL::Path& p : paths) most += area2(p);
        if (most > shadow2) {
          gap2 = most - shadow2;
          shadow2 += gap2 / 2;
        }
      }
    } catch (const CL::clipperException&) {
      return false;  // coordinates out of range cannot happen on the grid; be safe anyway
    }
    cell_ = grid_.step[0] * grid_.step[1] * scale_;  // 3D area of one grid unit
    const double shadow_3d = 0.5 * (static_cast<double>(shadow2) + boundary2) * cell_;
    out_.shadow_area = std::clamp(shadow_3d, 0.0, out_.area);
    out_.lit_area = out_.area - out_.shadow_area;
    out_.lit_fraction = out_.area > 0 ? out_.lit_area / out_.area : 0.0;
    out_.lit_area_error_bound =
        bound_.after_union(scale_, static_cast<double>(gap2 > 0 ? gap2 + 1 : 0), cell_, out_.area);
    return std::isfinite(out_.lit_area_error_bound);
  }

  // ---- fragments: the union's cells on the receiver's plane ---------------------------------
  bool emit_fragments() {
    try {
      return emit(lit_tree_, true) && emit(shadow_tree_, false);
    } catch (const CL::clipperException&) {
      return false;
    }
  }

  bool emit(const CL::PolyTree& tree, bool lit) {
    const glm::dvec3 corner = rc_.corner;
    const double ni = rc_.normal[rc_.i], nj = rc_.normal[rc_.j], nk = rc_.normal[rc_.k];
    regions_.clear();
    regions_of(tree, regions_);
    for (const CL::Paths& region : regions_) {
      cells_.clear();
      simple_cells(region, cells_);
      if (cells_.empty()) continue;
      for (const CL::Path& c : cells_) {
        Fragment f;
        f.face_id = face_id_;
        f.light_id = light_id_;
        f.fragment_id = fragment_id_;
        f.lit = lit;
        f.area = 0.5 * static_cast<double>(area2(c)) * cell_;
        for (const CL::IntPoint& p : c) {
          const glm::dvec2 x = grid_.chart(p);
          const double di = x.x - corner[rc_.i], dj = x.y - corner[rc_.j];
          glm::dvec3 y;
          y[rc_.i] = x.x;
          y[rc_.j] = x.y;
          y[rc_.k] = corner[rc_.k] - (ni * di + nj * dj) / nk;  // on the receiver's plane
          f.polygon.push_back(y);
        }
        // Cells are counter-clockwise in the chart; the chart sees a flipped face clockwise.
        if (fp_.flipped) std::reverse(f.polygon.begin(), f.polygon.end());
        // The output contract (one simple double polygon of non-zero area a cell): a cell that
        // breaks it (a sliver rounding collapsed, a boundary touching itself) sends the
        // receiver to the exact engine, which triangulates such cells (dropped_area).
        if (!core::clean_double_polygon(f.polygon, rc_.k)) return false;
        fragments_.push_back(std::move(f));
      }
      ++fragment_id_;
    }
    return true;
  }

  // Inputs.
  const Context& ctx_;
  Worker& w_;
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
  // The receiver's frame and the projection.
  Receiver rc_;
  FastReceiver fr_;  // holds a reference to rc_
  double max_delta_ = 0, parallel_delta_ = 0;
  Grid grid_;
  double rho_ = 0;
  // The casts and the bound.
  CL::Paths casts_, maybe_;  // maybe_: footprints of nearly coplanar casters
  bool covered_ = false;      // a cast fills the whole box (areas only): the shadow is the box
  LitAreaBound bound_;
  double cast_length_ = 0;  // total perimeter of the grid polygons given to Clipper
  bool not_finite_ = false;  // overflow in doubles (coordinates near 1e150): exact engine
  double scale_ = 0, cell_ = 0;
  // Scratch.
  std::vector<CGAL::Sign> vsign_, psign_;
  std::vector<char> unsure_;
  std::vector<glm::dvec2> points_, hull_;
  Cast cast_;
  CL::Path receiver_;
  bool receiver_ready_ = false;                    // receiver_ and the two below set up
  double receiver_length_ = 0, receiver_rho_ = 0;  // see set_up_receiver
  std::vector<glm::dvec2> outline_;
  CL::PolyTree shadow_tree_, lit_tree_;
  std::vector<CL::Paths> regions_;
  CL::Paths cells_;
  std::size_t fragment_id_ = 0;
};

}  // namespace

EngineStripUnion& engine_strip_union() {
  static EngineStripUnion state;
  return state;
}

bool compute_receiver(const Context& ctx, Worker& w, std::size_t face_id, std::size_t light_id,
                      const Light& light, const core::LightSpaceGrid* grid_index, bool polygons,
                      FaceLighting& out, std::vector<Fragment>& fragments, ShadowStats& stats) {
  return ReceiverJob(ctx, w, face_id, light_id, light, grid_index, polygons, out, fragments, stats, {}).run_job() ==
         Outcome::Done;
}

Outcome compute_receiver(const Context& ctx, Worker& w, std::size_t face_id, std::size_t light_id,
                         const Light& light, const core::LightSpaceGrid* grid_index, bool polygons,
                         FaceLighting& out, std::vector<Fragment>& fragments, ShadowStats& stats,
                         const core::TileRequest& tiles, std::size_t& split_candidates) {
  ReceiverJob job(ctx, w, face_id, light_id, light, grid_index, polygons, out, fragments, stats, tiles);
  const Outcome outcome = job.run_job();
  split_candidates = job.split_candidates;
  return outcome;
}

}  // namespace shadow::fast
