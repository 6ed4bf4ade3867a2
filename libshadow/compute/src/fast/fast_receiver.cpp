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
#include "fast/receiver_job.hpp"

#include "fast/strip_union.hpp"
#include "geometry/exact_facing.hpp"
#include "geometry/newell_normal.hpp"
#include "geometry/unit_vector.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace shadow::fast {
namespace receiver_job {

bool ReceiverJob::run() {
  out_ = FaceLighting{};
  out_.face_id = face_id_;
  out_.light_id = light_id_;
  out_.area = (*ctx_.face_area)[face_id_];
  ++local_.receivers;
  if (fp_.degenerate) return commit();
  if (light_.type == LightType::Directional && !polygons_ && !tile_) {
    // Certainly turned away from the sun by the culling normal: the Newell normal of the face's
    // vertices, its direction known within normal_error. For an exactly planar face that is the
    // plane's normal with the face's orientation, whose sign at the light decide_facing and the
    // exact engine take from a corner's determinant (FacePrep::corner keeps the orientation);
    // for a lifted face it is the exact engine's plane itself. So the attached shadow, without
    // the receiver's frame. Half of a city's faces look away from each sun; where this cannot
    // tell, decide_facing does. (Such a face no longer counts as a fallback when its frame
    // would have been ill-conditioned: the exact engine gave the same attached shadow.)
    // The engine's rounds split these pairs off before they become work items
    // (engine_detail::split_turned_away, the same test), so this one is the reference it copies
    // and the guard for any other caller of the job.
    if (core::certainly_turned_away(cull_.faces[face_id_], geometry::unit(light_.to_light))) {
      ++local_.back_facing;
      out_.shadow_area = out_.area;
      return commit();
    }
  }
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
  // A receiver in one solid's shadow whole (a fifth of a city's walls and roofs with some
  // shadow under a year's suns, most of them under a low sun) needs neither the candidate
  // search nor the other casts: its exact lit area is 0. Tried on the few solids whose
  // light-space box contains the receiver's.
  const bool try_cover = may_be_covered_whole();
  if (try_cover) {
    if (!set_up_projection()) return false;
    if (one_solid_covers()) {
      ++local_.candidate_pairs;  // (the one pair that decided it)
      ++local_.casting_pairs;
      out_.shadow_area = out_.area;
      out_.lit_area = 0;
      out_.lit_fraction = 0;
      out_.lit_area_error_bound = 0;
      return commit();
    }
  }
  const std::vector<std::size_t>& candidates = gather_casters();
  if (split_above_ > 0 && !grid_index_ && candidates.size() > split_above_ && core::tileable(fp_)) {
    split_candidates = candidates.size();
    return true;
  }
  if (!try_cover && !set_up_projection()) return false;
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

bool ReceiverJob::set_up_frame() {
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

bool ReceiverJob::push_whole_face(bool lit) {
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
      Int128 cells2 = 0;
      return emit(lit_tree_, lit, cells2);
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

bool ReceiverJob::decide_facing(int& facing) {
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

bool ReceiverJob::set_up_projection() {
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

}  // namespace receiver_job

using receiver_job::ReceiverJob;

void ReceiverScratchDelete::operator()(receiver_job::ReceiverScratch* scratch) const noexcept { delete scratch; }

receiver_job::ReceiverScratch& FastWorker::receiver_scratch() {
  if (!receiver) receiver.reset(new receiver_job::ReceiverScratch);
  return *receiver;
}

EngineStripUnion& engine_strip_union() {
  static EngineStripUnion state;
  return state;
}

Outcome compute_receiver(const core::PreparedScene& ctx, FastWorker& w, std::size_t face_id, std::size_t light_id,
                         const Light& light, const core::LightSpaceGrid* grid_index, bool polygons,
                         FaceLighting& out, std::vector<Fragment>& fragments, ShadowStats& stats,
                         const core::TileRequest& tiles, std::size_t& split_candidates) {
  ReceiverJob job(ctx, w, face_id, light_id, light, grid_index, polygons, out, fragments, stats, tiles);
  const Outcome outcome = job.run_job();
  split_candidates = job.split_candidates;
  return outcome;
}

}  // namespace shadow::fast
