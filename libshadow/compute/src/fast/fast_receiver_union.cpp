// SPDX-License-Identifier: GPL-3.0-or-later
// The fast receiver job's union (fast/receiver_job.hpp): the casts united by Clipper on the
// grid, the lit area and its error bound, and the union's cells as fragments on the receiver's
// plane.
#include "fast/receiver_job.hpp"

#include "fast/strip_union.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace shadow::fast::receiver_job {
namespace {

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

}  // namespace

void ReceiverJob::set_up_receiver() {
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
    const glm::dvec2& q = outline_[geometry::cyclic_next(a, outline_.size())];
    receiver_length_ += std::hypot(q.x - p.x, q.y - p.y);
  }
}

bool ReceiverJob::convex_window() {
  if (window_convex_ >= 0) return window_convex_ != 0;
  set_up_receiver();
  window_.clear();
  for (const CL::IntPoint& p : receiver_)
    if (window_.empty() || !(window_.back() == p)) window_.push_back(p);
  while (window_.size() > 1 && window_.front() == window_.back()) window_.pop_back();
  if (window_.size() >= 3 && area2(window_) < 0) std::reverse(window_.begin(), window_.end());
  window_convex_ = window_.size() >= 3 && is_convex_ccw(window_) ? 1 : 0;
  return window_convex_ != 0;
}

bool ReceiverJob::clip_casts_to_window() {
  if (!convex_window()) return false;
  for (const CL::Path& c : casts_)
    if (!is_convex_ccw(c)) return false;
  set_window(window_, w_.window);
  windowed_.resize(casts_.size());
  std::size_t kept = 0;
  for (const CL::Path& c : casts_) {
    clip_to_window(c, w_.window, windowed_[kept]);
    if (!windowed_[kept].empty()) ++kept;
  }
  windowed_.resize(kept);
  return true;
}

double ReceiverJob::windowed_length() const {
  double length = 0;
  for (const CL::Path& path : windowed_)
    for (std::size_t a = 0; a < path.size(); ++a) {
      const CL::IntPoint& p = path[a];
      const CL::IntPoint& q = path[geometry::cyclic_next(a, path.size())];
      length += std::hypot(static_cast<double>(q.X - p.X) * grid_.step[0],
                           static_cast<double>(q.Y - p.Y) * grid_.step[1]) + 2 * rho_;
    }
  return length * (1 + 1e-9);
}

bool ReceiverJob::unite() {
  // A box receiver's outline on the grid is its box, which nothing below reads when only areas
  // are asked for (the casts are clipped to it already): its grid points and length (four
  // roundings and four hypot calls a receiver) only for polygons and for other outlines.
  if (!fp_.chart_is_box || polygons_) set_up_receiver();
  const double receiver_length = receiver_length_;
  if (!fp_.chart_is_box) bound_.receiver_outline(receiver_length, receiver_rho_);
  Int128 shadow2 = 0, gap2 = 0;
  double boundary2 = 0;  // twice the area of the clusters measured by their boundary (grid units)
  if (covered_) {
    // The box, or a convex outline inside one cast (add_cast): the receiver's outline rounding
    // and the cast's are in the bound already.
    shadow2 = fp_.chart_is_box ? 2 * static_cast<Int128>(2 * kHalf) * (2 * kHalf) : area2(window_);
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
    // A convex receiver that is not its box (a terrain's triangle), areas only: the casts
    // clipped to it one by one, exactly, and then measured as a box's. The clip rounds each
    // crossing of a cast's edge with the outline once: its clipped casts, each inside its own
    // cast, move by under rho (the union's rounding term over the casts' length).
    const bool windowed = !clustered && !strips_only && casts == &casts_ && !fp_.chart_is_box && !polygons_ &&
                          maybe_.empty() && clip_casts_to_window();
    if (clustered || windowed) {
      // Areas only: the union's area cluster by cluster (fast/cluster_union.hpp). Clusters of
      // convex casts are measured by their boundary, without rounding intersection points:
      // their arithmetic bound replaces the union's rounding term.
      const glm::dvec2 along = rc_.point ? glm::dvec2(0, 1) : rc_.shift;
      const ClusteredArea area = clustered_union_area(windowed ? windowed_ : *casts, along.x * grid_.scale[0],
                                                      along.y * grid_.scale[1], nullptr, &w_.cluster,
                                                      /*merge_shared=*/face_casts_ >= 2);
      if (windowed) bound_.union_rounding(cast_length_, rho_);
      if (area.clipper) bound_.union_rounding(windowed ? windowed_length() : cast_length_, rho_);
      bound_.boundary_arithmetic(0.5 * area.boundary.error * grid_.step[0] * grid_.step[1]);
      shadow2 = area.exact2;
      boundary2 = area.boundary.twice_area;
    }
    // (A box receiver's edges meet the casts only at their vertices, already grid points.)
    if (!clustered && !windowed)
      bound_.union_rounding(cast_length_ + (fp_.chart_is_box ? 0.0 : receiver_length * (1 + 1e-9)), levels * rho_);
    // Casters are clipped to the chart box already: a rectangular receiver needs no intersection.
    const CL::ClipType op = fp_.chart_is_box ? CL::ctUnion : CL::ctIntersection;
    // Clipper's union only where it measures the shadow (not after the strips or the clusters).
    auto make_clipper = [&](CL::Clipper& clipper) {
      clipper.StrictlySimple(false);
      clipper.AddPaths(*casts, CL::ptSubject, true);
      if (!fp_.chart_is_box) clipper.AddPath(receiver_, CL::ptClip, true);
    };
    if (strips_only) {
      for (const CL::Path& p : united) shadow2 += area2(p);  // holes come out negative
    } else if (clustered || windowed) {
      // (measured above)
    } else if (polygons_) {
      CL::Clipper clipper;
      make_clipper(clipper);
      clipper.Execute(op, shadow_tree_, CL::pftNonZero, CL::pftNonZero);
      CL::Paths all;
      CL::PolyTreeToPaths(shadow_tree_, all);
      for (const CL::Path& p : all) shadow2 += area2(p);
      shadow_tree2_ = shadow2;
      CL::Clipper lit;
      lit.StrictlySimple(false);
      lit.AddPath(receiver_, CL::ptSubject, true);
      lit.AddPaths(*casts, CL::ptClip, true);
      lit.Execute(CL::ctDifference, lit_tree_, CL::pftNonZero, CL::pftNonZero);
    } else {
      CL::Clipper clipper;
      make_clipper(clipper);
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

bool ReceiverJob::emit_fragments() {
  Int128 lit2 = 0, shadow2 = 0;
  try {
    if (!emit(lit_tree_, true, lit2) || !emit(shadow_tree_, false, shadow2)) return false;
  } catch (const CL::clipperException&) {
    return false;
  }
  // The cells must partition the receiver as the union measured it: the shadow cells the
  // union's area, the lit ones the rest of the receiver's outline on the grid, within the
  // bound. The union and the difference are two Clipper runs; where rounding gave them
  // different topologies (a cast's vertex on another cast's edge, on the grid), a region was
  // both lit and shadow and the fragments covered more than the face (fuzz_engine): the exact
  // engine then.
  // The relative slack is of this receiver's own outline (a tile's, not its face's).
  const Int128 outline2 = area2(receiver_);
  const Int128 receiver2 = outline2 < 0 ? -outline2 : outline2;
  const double tolerance2 = 1e-9 * static_cast<double>(receiver2) + out_.lit_area_error_bound / (0.5 * cell_);
  const auto off = [](Int128 a, Int128 b) { return std::abs(static_cast<double>(a - b)); };
  return off(shadow2, shadow_tree2_) <= tolerance2 && off(lit2, receiver2 - shadow_tree2_) <= tolerance2;
}

bool ReceiverJob::emit(const CL::PolyTree& tree, bool lit, Int128& cells2) {
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
      cells2 += area2(c);
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

}  // namespace shadow::fast::receiver_job
