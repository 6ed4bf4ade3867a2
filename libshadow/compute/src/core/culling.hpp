// SPDX-License-Identifier: GPL-3.0-or-later
// Culling in double precision: which faces can possibly shadow a receiver. Every test is
// conservative: it rejects a face only when it is certainly, by a margin far above rounding
// error, outside the receiver's slab, prism or pyramid. Whatever passes is decided exactly.
#pragma once

#include "geometry/box_sides.hpp"
#include "geometry/unit_vector.hpp"
#include "core/cull_scene.hpp"
#include "core/face_prep.hpp"
#include "core/light_space_grid.hpp"
#include "runtime/parallel.hpp"
#include "runtime/uninit_vector.hpp"

#include <shadow/scene.hpp>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow::core {

/// An affine function on local-frame points with the margin below which its sign is unsure.
struct DoubleAffine {
  glm::dvec3 a{0.0};
  double b = 0.0;
  double tolerance = 0.0;
  [[nodiscard]] double operator()(const glm::dvec3& p) const { return glm::dot(a, p) + b; }
};

/// The conservative double-precision tests of one receiver (front-facing) under one light: its
/// plane and, unless the light grazes it, the four sides of the prism or pyramid over its chart
/// box. Shared by the exact engine and the fast path, so that both see the same candidates.
class ReceiverCuller {
 public:
  ReceiverCuller(const CullScene& cull, const FacePrep& fp, std::size_t face_id, const Light& light)
      : cull_(&cull), receiver_(face_id) {
    const CullFace& cp = cull.faces[face_id];
    const double D = cull.diameter;
    glm::dvec3 lxyz;
    double lw;
    if (light.type == LightType::Point) {
      lamp_ = light.position;
      lxyz = light.position - cull.origin;
      lw = 1.0;
    } else {
      lxyz = geometry::unit(light.to_light);
      lw = 0.0;
      to_light_ = lxyz;
      if (light.type == LightType::Directional && !light.is_extended()) direction_ = light.to_light;
      if (!cull.closed_outward.empty() && light.type == LightType::Directional) {  // (never a lamp: it may be inside)
        closed_outward_ = cull.closed_outward.data();
        above_caps_ = lxyz.z > 16 * std::numeric_limits<double>::epsilon();  // the unit vector's rounding
      }
    }
    const double light_side = glm::dot(cp.normal, lxyz) + cp.offset * lw;
    const double scale = D + (lw != 0.0 ? glm::length(lxyz) : 0.0);
    // Rigorous error bounds (docs/numeric-contract.md, "Culling"). For a scene point p (|p - c|
    // <= D, c the receiver's centroid): |s(p) - s_exact(p)| <= e_n D + rounding, e_n the
    // normal's direction bound; the rounding of the centroid, the dot product and the local
    // frame is under (count + 16) eps D. The 1e-9 margin is only a safety factor on top.
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double e_n = cp.normal_error;
    const double s_error = e_n * D * (1 + 1e-9) + (static_cast<double>(cp.count) + 16) * eps * D;
    // The light's side: the light (or direction) is within |l - c| <= |l| + D of the centroid.
    const double light_side_error =
        lw != 0.0 ? (e_n + 8 * eps) * (glm::length(lxyz) + D) + s_error : e_n + 8 * eps;
    tests_[0] = {cp.normal, cp.offset, 1e-9 * scale + s_error};
    {
      // The same sides as the exact clip, in the local frame (chart box shifted by the origin).
      const int i = chart_i(fp.axis), j = chart_j(fp.axis);
      const double lo[2] = {fp.chart_min[0] - cull.origin[i], fp.chart_min[1] - cull.origin[j]};
      const double hi[2] = {fp.chart_max[0] - cull.origin[i], fp.chart_max[1] - cull.origin[j]};
      const std::array<double, 4> plane{cp.normal.x, cp.normal.y, cp.normal.z, cp.offset};
      const std::array<double, 4> light_h{lxyz.x, lxyz.y, lxyz.z, lw};
      const auto sides = geometry::box_sides(plane, light_h, light_side, i, j, lo, hi);
      for (int t = 0; t < 4; ++t) {
        const double coef = lxyz[t < 2 ? i : j] - (t % 2 ? hi : lo)[t / 2] * lw;
        // side = light_side (x_a - m) - coef s(x), |x_a - m| <= D: each factor's error times
        // the other's size.
        const double rigorous = light_side_error * D + std::abs(coef) * s_error;
        tests_[1 + t] = {glm::dvec3(sides[t][0], sides[t][1], sides[t][2]), sides[t][3],
                         2 * rigorous + 1e-9 * (std::abs(light_side) + std::abs(coef)) * scale +
                             1e-12 * scale * scale};
      }
    }
    // The side tests need the light's side of the receiver with the right sign: a grazing light
    // (light_side near zero, where rounding could flip it) keeps only the plane test.
    count_ = light_side > 1e-7 * (lw != 0.0 ? scale : 1.0) && light_side > 4 * light_side_error ? tests_.size() : 1;
    for (std::size_t t = 0; t < tests_.size(); ++t) length_[t] = glm::length(tests_[t].a);  // once, not per caster
    // may_cast_any's room for rounding, per test, once per receiver instead of a sum of
    // magnitudes per box: the scene's local coordinates lie within its diameter of 0 (the
    // vertices less the centre of their box), so no box's sum exceeds |b| + D |a|_1.
    for (std::size_t t = 0; t < tests_.size(); ++t) {
      const DoubleAffine& f = tests_[t];
      any_room_[t] = 32 * eps * (std::abs(f.b) + D * (std::abs(f.a.x) + std::abs(f.a.y) + std::abs(f.a.z)));
    }
  }

  /// False when may_cast is certainly false for every face whose vertices lie in `b` (with a
  /// slack of at most b.slack): for one of the tests, the box lies wholly outside it, with room
  /// for may_cast's own rounding. `b` bounds faces of this culler's scene (face_bounds(),
  /// LightSpaceGrid::item_bounds()). Its maximum over the box (at the corner each coefficient's
  /// sign picks) and may_cast's value at any vertex in it are each within 4 eps of their exact
  /// values relative to the same sum of magnitudes (three products and the constant), so a gap of
  /// 32 eps of a bound on that sum (any_room_) covers both.
  [[nodiscard]] bool may_cast_any(const LocalBounds& b) const {
    for (std::size_t t = 0; t < count_; ++t) {
      const DoubleAffine& f = tests_[t];
      double most = f.b;
      for (int c = 0; c < 3; ++c) most += f.a[c] * (f.a[c] >= 0 ? b.hi[c] : b.lo[c]);
      if (most + any_room_[t] < -(f.tolerance + length_[t] * b.slack)) return false;
    }
    return true;
  }

  /// The scene the culler tests faces of.
  [[nodiscard]] const CullScene& scene() const { return *cull_; }

  /// Lets caster_plane_rules_out() decide, with the scene's input faces (`scene` and `prep`, of
  /// the same faces as the CullScene): under a directional light or a lamp, for an exactly
  /// planar receiver.
  void use_caster_planes(const Scene& scene, const std::vector<FacePrep>& prep) {
    if ((direction_ || lamp_) && prep[receiver_].exactly_planar) {
      input_ = &scene;
      input_prep_ = &prep;
    }
  }

  /// True when face q certainly casts nothing on the receiver because the whole receiver lies on
  /// the light's side of q's plane, or on it, and the light strictly on that side: a ray from a
  /// point there to the light only moves away from that plane, so it never meets q (a wall and
  /// the ground it stands on, a table top and the floor under a lamp). Exactly planar casters
  /// only (the exact engine's polygon is then the input's); false where use_caster_planes() was
  /// not called or did not apply. For a face cast on its own only: a convex solid is cast once,
  /// as one hull at its first listed face, so its faces are not left out one by one.
  ///
  /// A caster in a plane x_k = c (every input vertex with the same coordinate k: the ground, a
  /// floor) is decided exactly by comparing input doubles, also for receiver vertices on the
  /// plane (the foot of a wall). Any other plane, under a directional light only, in doubles by
  /// its rigorous error bound (as the receiver's own plane test above): certain where the
  /// receiver is clearly on the light's side.
  [[nodiscard]] bool caster_plane_rules_out(std::size_t q) const {
    if (input_ == nullptr || !(*input_prep_)[q].exactly_planar) return false;
    const std::vector<glm::dvec3>& receiver = input_->faces[receiver_].vertices;
    const std::vector<glm::dvec3>& caster = input_->faces[q].vertices;
    // A plane x_k = c has its normal along k: k is the face's dominant axis.
    const int k = (*input_prep_)[q].axis;
    const double c = caster[0][k];
    if (std::all_of(caster.begin(), caster.end(), [&](const glm::dvec3& v) { return v[k] == c; })) {
      // The light's side of x_k = c: the sign of d_k, or of the lamp's x_k - c.
      const int light = direction_ ? ((*direction_)[k] > 0) - ((*direction_)[k] < 0) : ((*lamp_)[k] > c) - ((*lamp_)[k] < c);
      if (light == 0) return false;  // edge-on to the light, or a lamp on the plane: left to the engines
      return std::all_of(receiver.begin(), receiver.end(), [&](const glm::dvec3& y) { return light > 0 ? y[k] >= c : y[k] <= c; });
    }
    if (!direction_) return false;
    const CullFace& cq = cull_->faces[q];
    const double light_side = certainly_turned_away(cq, to_light_, -1.0)  ? 1.0
                              : certainly_turned_away(cq, to_light_, 1.0) ? -1.0
                                                                           : 0.0;
    if (light_side == 0.0) return false;
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double D = cull_->diameter;
    const double error = 1e-9 * D + 2 * (cq.normal_error * D + (static_cast<double>(cq.count) + 16) * eps * D);
    const CullFace& cr = cull_->faces[receiver_];
    for (std::size_t a = cr.first; a < cr.first + cr.count; ++a)
      if (!(light_side * (glm::dot(cq.normal, cull_->vertices[a]) + cq.offset) > error)) return false;
    return true;
  }

  /// False when face q is certainly outside the receiver's slab, prism or pyramid, or, under a
  /// directional light, a face of a closed solid certainly turned away from the light: a ray
  /// that enters an embedded closed solid leaves it again nearer the light, through a face
  /// turned to it (docs/algorithm.md, "Closed solids cast through the faces facing the light"),
  /// so dropping such a caster changes no shadow.
  [[nodiscard]] bool may_cast(std::size_t q) const {
    const CullFace& cq = cull_->faces[q];
    for (std::size_t t = 0; t < count_; ++t) {
      const DoubleAffine& f = tests_[t];
      const double tolerance = f.tolerance + length_[t] * cq.slack;
      bool all_out = true;
      for (std::size_t a = cq.first; a < cq.first + cq.count && all_out; ++a)
        all_out = f(cull_->vertices[a]) < -tolerance;
      if (all_out) return false;
    }
    if (!closed_outward_) return true;
    const signed char outward = closed_outward_[q];
    return outward == 0 || ((outward == 2 || outward == -2) && !above_caps_) || !certainly_turned_away(cq, to_light_, outward > 0 ? 1.0 : -1.0);
  }

 private:

  const CullScene* cull_;
  std::size_t receiver_;
  std::optional<glm::dvec3> direction_;  ///< a directional light's to_light, as given
  std::optional<glm::dvec3> lamp_;       ///< a point light's position, as given
  const Scene* input_ = nullptr;         ///< use_caster_planes()
  const std::vector<FacePrep>* input_prep_ = nullptr;
  const signed char* closed_outward_ = nullptr;  ///< CullScene::closed_outward under a directional light
  glm::dvec3 to_light_{0.0};  ///< a directional light's unit direction to it
  bool above_caps_ = false;  ///< the light is certainly above every horizontal plane (to_light.z > 0)
  std::array<DoubleAffine, 5> tests_;
  std::array<double, 5> length_{};  ///< |tests_[t].a|
  std::array<double, 5> any_room_{};  ///< may_cast_any's room for rounding, per test
  std::size_t count_ = 1;
};

/// The casters one receiver has to consider, as found by its ReceiverCuller. One per thread,
/// reused for every receiver: a stamp per convex solid (cast once per receiver) instead of
/// clearing per-solid flags. Shared by the exact
/// engine and the fast path, so that both consider the same casters in the same order.
class CasterCandidates {
 public:
  /// Sizes the stamps for a scene of `solids` convex solids.
  void reset(std::size_t solids) {
    solid_seen_.assign(solids, 0);
    stamp_ = 0;
  }

  /// The faces that `culler` cannot rule out as casters on `receiver` (itself and degenerate
  /// faces excluded), from `grid`'s cells when there is one, else from every face. Sorted: the
  /// same order whatever order the grid visits them in.
  ///
  /// With `solid_of` (the convex solid of each face, -1 for none), the other faces of the
  /// receiver's own convex solid are left out too: a face of a closed convex solid that faces the
  /// light is never shadowed by its own solid, and both engines skip those casters anyway.
  ///
  /// With `one_face_per_solid` (the caller casts every convex solid as one hull, at its first
  /// face in the list, and skips its other faces) and a grid whose items are the solids of this
  /// `solid_of`, a solid's faces after the first that passes are neither tested nor listed: that
  /// first one is its lowest that passes (the grid visits an item's faces one after another, in
  /// increasing order), so the hull is cast at the same place in the list and every result is
  /// the same. Without such a grid the list is the full one (its size may decide a split).
  const std::vector<std::size_t>& gather(const ReceiverCuller& culler, const std::vector<FacePrep>& prep,
                                         std::size_t receiver, const LightSpaceGrid* grid,
                                         const CullScene* tile_scene = nullptr, const FacePrep* tile = nullptr,
                                         const std::vector<int>* solid_of = nullptr, bool one_face_per_solid = false) {
    faces_.clear();
    if (++stamp_ == 0) {  // stamps wrapped: reset
      std::fill(solid_seen_.begin(), solid_seen_.end(), 0);
      stamp_ = 1;
    }
    const bool one_face = one_face_per_solid && solid_of != nullptr && grid != nullptr && grid->solid_items() == solid_of;
    // The grid holds no degenerate face: its visits skip the look-up in `prep` (a cache miss per
    // visit on a large struct, a sizeable share of the query).
    const int own_solid = solid_of ? (*solid_of)[receiver] : -1;
    // The grid reports each face once (LightSpaceGrid.QueriesReportEveryOverlappingFaceOnce), as
    // does the loop over every face: no stamp per face.
    // Returns true when the rest of q's grid item needs no visit: in one_face mode, once a
    // solid is listed. The grid takes each item in one cell only, so a solid's later faces are
    // then neither tested nor listed.
    auto consider = [&](std::size_t q) -> bool {
      if (q == receiver) return false;
      const int solid = one_face || own_solid >= 0 ? (*solid_of)[q] : -1;
      if (solid >= 0 && solid == own_solid) return false;
      if (!culler.may_cast(q)) return false;
      if ((solid_of == nullptr || (*solid_of)[q] < 0) && culler.caster_plane_rules_out(q)) return false;
      faces_.push_back(q);
      return one_face && solid >= 0;
    };
    // The receiver's own convex solid, when it is one of the grid's items: none of its faces is
    // taken (above), so the query skips it whole.
    const std::uint32_t own_item = grid && own_solid >= 0 && grid->solid_items() == solid_of
                                       ? grid->item_of(receiver)
                                       : LightSpaceGrid::kNoItem;
    // An item of the grid (a convex solid, or a face alone) that the culler rules out whole.
    auto keep_item = [&](const LocalBounds& b) { return culler.may_cast_any(b); };
    if (grid) {
      const CullScene& scene = tile && tile_scene ? *tile_scene : culler.scene();
      const CullFace& cf = scene.faces[receiver];
      // How near the light a point whose shadow counts lies at the least (the query's min_depth):
      // a caster shades a point only through points on its ray to the light, each nearer the
      // light than it, so an item that reaches less near casts nothing that counts.
      if (tile && tile_scene) {
        // A tile: the light-space box of its corners on the receiver's plane (local frame).
        const int k = tile->axis, i = chart_i(k), j = chart_j(k);
        corners_.clear();
        for (int c = 0; c < 4; ++c) {
          glm::dvec3 p;
          p[i] = (c == 1 || c == 2 ? tile->chart_max[0] : tile->chart_min[0]) - tile_scene->origin[i];
          p[j] = (c >= 2 ? tile->chart_max[1] : tile->chart_min[1]) - tile_scene->origin[j];
          p[k] = -(cf.offset + cf.normal[i] * p[i] + cf.normal[j] * p[j]) / cf.normal[k];
          corners_.push_back(p);
        }
        // The culling plane is within the normal's error (over the scene's diameter) and the
        // slack of the exact one.
        const double slack = (cf.normal_error + 1e-9) * tile_scene->diameter * 4 + 4 * cf.slack;
        // The tile's corners bound its points' depth (more tightly than the receiver's vertices,
        // and in four steps however many vertices it has) where the plane's height over the chart
        // is well conditioned: a corner's error is about (sqrt(3) e_n D + slack) / (|n_k| - e_n),
        // within `slack` from |n_k| - e_n >= 0.45. Elsewhere the receiver's vertices do.
        double nearest = std::numeric_limits<double>::max();
        bool corners_bound = std::abs(cf.normal[k]) - cf.normal_error >= 0.45 && std::isfinite(slack);
        for (const glm::dvec3& p : corners_) {
          const double depth = grid->depth(p);
          corners_bound = corners_bound && std::isfinite(depth);
          nearest = std::min(nearest, depth);
        }
        const double min_depth = corners_bound ? nearest - slack : depth_floor(*grid, scene, cf);
        grid->query_part(receiver, corners_, std::isfinite(slack) ? slack : 0.0, consider, keep_item, own_item, min_depth);
      } else {
        grid->query(receiver, consider, keep_item, own_item, depth_floor(*grid, scene, cf));
      }
    } else {
      for (std::size_t q = 0; q < prep.size(); ++q)
        if (!prep[q].degenerate) consider(q);
    }
    std::sort(faces_.begin(), faces_.end());
    return faces_;
  }

  /// Convex solid `s` has already cast (as one hull) on the current receiver.
  [[nodiscard]] bool solid_done(int s) const { return solid_seen_[static_cast<std::size_t>(s)] == stamp_; }
  /// Marks convex solid `s` as cast on the current receiver.
  void mark_solid_done(int s) { solid_seen_[static_cast<std::size_t>(s)] = stamp_; }

  /// The least depth (LightSpaceGrid::depth) of the receiver's points as the exact engine sees
  /// them, less room for rounding, from its own vertices: depth is linear, so its least over the
  /// face is at a vertex; the exact engine moves a vertex by at most the face's slack; 1e-9 D
  /// covers the dot products' rounding. It needs no normal (a face whose area rounds to zero in
  /// doubles has none). The lowest double, so no cut, where a depth is not finite.
  static double depth_floor(const LightSpaceGrid& grid, const CullScene& scene, const CullFace& cf) {
    constexpr double kNoCut = std::numeric_limits<double>::lowest();
    if (cf.count == 0) return kNoCut;
    double nearest = std::numeric_limits<double>::max();
    for (std::size_t a = cf.first; a < cf.first + cf.count; ++a) {
      const double depth = grid.depth(scene.vertices[a]);
      if (!std::isfinite(depth)) return kNoCut;
      nearest = std::min(nearest, depth);
    }
    const double floor = nearest - cf.slack - 1e-9 * scene.diameter;
    return std::isfinite(floor) ? floor : kNoCut;
  }

 private:
  std::vector<std::uint32_t> solid_seen_;
  std::uint32_t stamp_ = 0;
  std::vector<std::size_t> faces_;
  std::vector<glm::dvec3> corners_;
};

}  // namespace shadow::core
