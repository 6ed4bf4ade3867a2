// SPDX-License-Identifier: GPL-3.0-or-later
// The fast receiver job's casts (fast/receiver_job.hpp): each candidate caster, a convex
// solid's hull or a face's convex pieces, projected in doubles onto the receiver's chart and put
// on the grid, or charged to the bound when it collapses.
#include "fast/receiver_job.hpp"

#include "core/light_space_grid.hpp"
#include "core/solid_outlines.hpp"
#include "geometry/monotone_chain.hpp"
#include "geometry/unit_vector.hpp"
#include "geometry/winds_once.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace shadow::fast::receiver_job {
namespace {

/// Convex hull (counter-clockwise, Andrew's monotone chain) in doubles of pts[0, n) (reordered).
void convex_hull(ChartPoints& pts, std::size_t n, ChartPoints& hull) {
  const auto end = pts.begin() + static_cast<std::ptrdiff_t>(n);
  std::sort(pts.begin(), end, [](const glm::dvec2& a, const glm::dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  n = static_cast<std::size_t>(std::unique(pts.begin(), end) - pts.begin());
  hull.clear();
  if (n < 3) {
    hull.assign(pts.begin(), pts.begin() + static_cast<std::ptrdiff_t>(n));
    return;
  }
  hull.resize(2 * n);
  // (A turn that is not a number keeps its point: add_cast then sends the receiver to the exact engine.)
  hull.resize(geometry::monotone_chain(pts.data(), n, hull.data(), [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return !((a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x) <= 0);
  }));
}

/// The convex hull of pts[outline[0, m)], the corners of a convex solid's projected hull in
/// their order seen from the light (core/solid_outlines.hpp), into `hull` as convex_hull gives it:
/// counter-clockwise from the least point (x, then y). The projection onto a receiver's chart may
/// turn the order over; false where the corners, in doubles, do not make a convex polygon turning
/// strictly one way (a receiver nearly edge-on to the light, points not finite): convex_hull
/// decides those.
bool hull_from_outline(const ChartPoints& pts, const core::SolidOutlines::Outline& outline, ChartPoints& hull) {
  const std::size_t m = outline.size;
  if (m < 3) return false;
  auto at = [&](std::size_t c) -> const glm::dvec2& { return pts[outline.data[c]]; };
  bool left = true, right = true;
  std::size_t first = 0;  // the least point
  // Turning one way everywhere, a closed polygon may still wind twice (a pentagram).
  geometry::XSignChanges winding;
  for (std::size_t c = 0; c < m; ++c) {
    const glm::dvec2 &o = at(c), &a = at(c + 1 < m ? c + 1 : c + 1 - m), &b = at(c + 2 < m ? c + 2 : c + 2 - m);
    const double turn = (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    left = left && turn > 0;
    right = right && turn < 0;
    if (o.x < at(first).x || (o.x == at(first).x && o.y < at(first).y)) first = c;
    winding.add(geometry::sign_of_difference(o.x, a.x));
  }
  if ((!left && !right) || !winding.winds_once()) return false;
  hull.resize(m);
  for (std::size_t j = 0, c = first; j < m; ++j) {  // from the least point, counter-clockwise on the chart
    hull[j] = at(c);
    c = left ? (c + 1 < m ? c + 1 : 0) : (c > 0 ? c - 1 : m - 1);
  }
  return true;
}

}  // namespace

void ReceiverJob::add_cast(Cast& c) {
  if (c.poly.size() < 3) {
    bound_.clipped_away(c.free_length, c.delta + 4 * kEps * rc_.magnitude);
    not_finite_ |= !bound_.finite();
    return;
  }
  for (const glm::dvec2& p : c.poly) not_finite_ |= !std::isfinite(p.x) || !std::isfinite(p.y);
  not_finite_ |= !std::isfinite(c.delta);
  if (not_finite_) return;
  CL::Path path = s_.take_path();
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
      const glm::dvec2& q = c.poly[geometry::cyclic_next(a, c.poly.size())];
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
  // Likewise a convex outline that is not a box inside a convex cast (a terrain's triangle in a
  // building's shadow): the shadow is the whole outline.
  if (!polygons_ && !fp_.chart_is_box && convex_window() && is_convex_ccw(path) && convex_contains(path, window_))
    covered_ = true;
  casts_.push_back(std::move(path));
  cast_length_ += length + 2 * n_vertices * rho_;
}

bool ReceiverJob::cast_all(const std::vector<std::size_t>& candidates) {
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
    if (covered_) break;  // the whole receiver is in shadow: the other casters cannot add to it
  }
  return true;
}

// (Both helpers inlined into their two callers: as calls they added 27 M instructions, 1.4%, to
// cast_convex_solid on the fast sample; inlined, the sample is within 0.12% of one routine.)
template <bool kCertainSides>
[[gnu::always_inline]] inline bool ReceiverJob::solid_points(const core::ConvexSolid& cs, SolidPoints& out) {
  out = SolidPoints{};
  vsign_.resize(cs.vertices.size());
  // Written in place (at most one point per vertex and per edge), not pushed one call each; the
  // scratch is not shrunk here (resizing it to each solid's count zero-filled it every time).
  if (points_.size() < cs.vertices.size() + cs.edges.size()) points_.resize(cs.vertices.size() + cs.edges.size());
  // Each vertex's side and its projection from one s (scene_side's and project's, the same
  // double): one dot product a vertex, not two.
  for (std::size_t a = 0; a < cs.vertices.size(); ++a) {
    const glm::dvec3& y = cs.vertices[a];
    const double s = rc_.s(y);
    CGAL::Sign sign;
    if constexpr (kCertainSides) {  // scene_side's doubles, without its predicate
      if (s > 2 * rc_.s_error) sign = CGAL::POSITIVE;
      else if (s < -2 * rc_.s_error) sign = CGAL::NEGATIVE;
      else return false;
    } else {
      sign = rc_.scene_side(y, s);
    }
    vsign_[a] = sign;
    out.any_front |= sign == CGAL::POSITIVE;
    out.any_behind |= sign == CGAL::NEGATIVE;
    if (sign == CGAL::POSITIVE) points_[out.count++] = fr_.project(y, s);
    if (sign == CGAL::ZERO) points_[out.count++] = fr_.chart(y);
  }
  if (!out.any_front) return true;
  // Crossings only where some vertex is behind (a solid wholly in front of the receiver's plane,
  // as every building is of the ground, has none): its edges, a cache miss of their own, are
  // not read otherwise.
  for (std::size_t e = 0; out.any_behind && e < cs.edges.size(); ++e) {
    const auto& [a, b] = cs.edges[e];
    const CGAL::Sign sa = vsign_[a], sb = vsign_[b];
    if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE)) {
      glm::dvec3 x;
      if (!fr_.crossing(cs.vertices[a], cs.vertices[b], x, out.cross_delta)) return false;
      points_[out.count++] = fr_.chart(x);
    }
  }
  return true;
}

[[gnu::always_inline]] inline void ReceiverJob::solid_hull(int solid, const SolidPoints& points) {
  // Wholly in front (no vertex behind): points_ holds every vertex's point, in vertex order, and
  // the hull's corners are those of the solid's outline seen from the light, in its order or
  // the reverse: no sort. The outline is certain for the exact projection, so the corners are
  // the exact hull's, each within delta of its exact point, as convex_hull's would be.
  const core::SolidOutlines* outlines = grid_index_ ? grid_index_->outlines() : nullptr;
  if (points.any_behind || !outlines || !outlines->of(ctx_.solids) ||
      !hull_from_outline(points_, outlines->outline(static_cast<std::size_t>(solid)), hull_))
    convex_hull(points_, points.count, hull_);
}

bool ReceiverJob::cast_convex_solid(int solid) {
  w_.casters.mark_solid_done(solid);
  SolidPoints points;
  if (!solid_points<false>((*ctx_.solids)[solid], points)) return false;
  if (!points.any_front) return true;
  // The hull of points each within delta of the exact ones is within delta of the exact hull.
  const double delta = std::max(parallel_delta_, points.cross_delta);
  // Front parts that land wholly beyond a side of the chart box, farther than their points'
  // error, cast nothing on the receiver and leave nothing to charge: the exact hull misses the
  // box too. The culler passed them on the whole solid, whose part behind the receiver's plane
  // may lie in the prism over the box (a fifth of the solids cast on a fast instant). No hull and
  // no clip for them.
  if (beyond_chart_box(points_, points.count, delta + 4 * kEps * rc_.magnitude)) return true;
  solid_hull(solid, points);
  cast_.poly.swap(hull_);  // (hull_ is scratch: convex_hull empties it first)
  cast_.delta = delta;
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

bool ReceiverJob::may_be_covered_whole() const {
  if (polygons_ || tile_ || !fp_.chart_is_box || rc_.point || !rc_.exact_sides || !grid_index_) return false;
  if (light_.type != LightType::Directional || light_.is_extended()) return false;
  // (A grid whose items are the solids: query_containing then meets each solid once.)
  return ctx_.solids && ctx_.solid_of && grid_index_->solid_items() == ctx_.solid_of;
}

bool ReceiverJob::one_solid_covers() {
  const int own_solid = (*ctx_.solid_of)[face_id_];
  // Each corner of the box is certainly inside the exact hull when it is inside every edge of
  // the hull in doubles by more than the corners' error (delta: theirs, and the chart's rounding
  // as for any cast): the exact hull contains the doubles' hull shrunk by that much.
  const std::array<glm::dvec2, 4> box{glm::dvec2(rc_.lo[0], rc_.lo[1]), glm::dvec2(rc_.hi[0], rc_.lo[1]),
                                      glm::dvec2(rc_.hi[0], rc_.hi[1]), glm::dvec2(rc_.lo[0], rc_.hi[1])};
  auto covers = [&](const ChartPoints& hull, double delta) {
    const std::size_t m = hull.size();
    for (std::size_t a = 0; a < m; ++a) {
      const glm::dvec2 p = hull[a], d = hull[a + 1 < m ? a + 1 : 0] - p;
      // The distance's rounding: the differences, the products and the sum, each within a few
      // eps of the terms' magnitudes; the length's within a few eps of itself.
      const double reach = delta * glm::length(d) * (1 + 1e-9);
      for (const glm::dvec2& c : box) {
        const glm::dvec2 e = c - p;
        const double tx = d.x * e.y, ty = d.y * e.x;
        if (!(tx - ty - 8 * kEps * (std::abs(tx) + std::abs(ty)) > reach)) return false;
      }
    }
    return true;
  };
  bool found = false;
  const double min_depth = core::CasterCandidates::depth_floor(*grid_index_, cull_, cull_.faces[face_id_]);
  grid_index_->query_containing(face_id_, min_depth, [&](std::size_t q) {
    const int solid = (*ctx_.solid_of)[q];
    if (solid < 0 || solid == own_solid) return false;
    // Every vertex's side certain in doubles (a vertex too near the plane for them rules the
    // solid out): the shadow as cast_convex_solid makes it.
    SolidPoints points;
    if (!solid_points<true>((*ctx_.solids)[static_cast<std::size_t>(solid)], points) || !points.any_front) return false;
    solid_hull(solid, points);
    found = hull_.size() >= 3 && covers(hull_, std::max(parallel_delta_, points.cross_delta) + 4 * kEps * rc_.magnitude);
    return found;
  });
  return found;
}

bool ReceiverJob::cast_face(std::size_t q) {
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
    face_casts_ += casts_.size() - before;
  }
  if (cast_any) ++local_.casting_pairs;
  return true;
}

bool ReceiverJob::cast_nearly_coplanar(const Face& qface, const std::vector<int>& piece, double position, double grow,
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
  clip_to_box_sides(cast_.poly, rc_.lo, rc_.hi, hull_);
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

}  // namespace shadow::fast::receiver_job
