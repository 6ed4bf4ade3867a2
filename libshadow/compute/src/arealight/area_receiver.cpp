// SPDX-License-Identifier: GPL-3.0-or-later
// The exact fully-lit, penumbra and umbra regions of a receiving face P under an extended light L
// (docs/area-lights.md has the geometry and the proofs). In P's chart, with exact rationals:
//
//   not fully lit = union over convex occluder pieces C of U(L, C),
//       U(L, C) = { p : some segment from a point of L to p meets C }   (convex for convex L, C)
//   umbra        >= union over C of  intersection over the vertices v of L of shadow(v, C)
//
// (equality for one piece). Each piece is first clipped to the front of P's plane and, for a
// finite light, to the front of the light's plane: nothing else can stand between them.
//
// U(L, C) is computed by one of two exact routes:
//  - projections: when every point of C is nearer to P's plane than every vertex of L (always
//    for a sun disk), U is the convex hull of C's shadows from L's vertices;
//  - separating planes, in general: p is outside U exactly when a plane separates C from L and
//    p, so U is the intersection of the half-planes that the planes separating L from C, through
//    an edge of one and a vertex of the other or through L's or C's own plane, cut from P's
//    plane. Points and directions alike are homogeneous (x, y, z, w).
// Everything is clipped to P's chart box; the Boolean operations are one aggregated union each.
#include "arealight/area_receiver.hpp"

#include "exact/exact_faces.hpp"
#include "exact/kernel.hpp"
#include "exact/lazy_geometry.hpp"
#include "exact/regions.hpp"
#include "geometry/clip_convex.hpp"
#include "geometry/unit_vector.hpp"

#include <shadow/error.hpp>

#include <CGAL/convex_hull_2.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <utility>

namespace shadow::arealight {

using exact::ExactFace;
using exact::FT;
using exact::Point2;
using exact::Point3;
using exact::Polygon2;
using exact::PolygonSet2;
using exact::PolygonWithHoles2;
using H4 = std::array<FT, 4>;  // a homogeneous point (w = 1) or direction (w = 0), or a plane

bool force_separating_planes = false;

struct AreaWorker::Exact {
  ExactFace light;  ///< the shape's polygon on its exact plane
};

namespace {

FT dot4(const H4& a, const H4& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]; }

H4 homogeneous(const Point3& p) { return {p.x(), p.y(), p.z(), FT(1)}; }
H4 homogeneous(const Point3& p, bool finite) { return {p.x(), p.y(), p.z(), FT(finite ? 1 : 0)}; }

FT det3(const H4& a, const H4& b, const H4& c, int c0, int c1, int c2) {
  return a[c0] * (b[c1] * c[c2] - b[c2] * c[c1]) - a[c1] * (b[c0] * c[c2] - b[c2] * c[c0]) +
         a[c2] * (b[c0] * c[c1] - b[c1] * c[c0]);
}

/// The plane through three homogeneous points: <H, X> = det(a, b, c, X). Zero when they do not
/// span a plane.
H4 plane_through(const H4& a, const H4& b, const H4& c) {
  return {-det3(a, b, c, 1, 2, 3), det3(a, b, c, 0, 2, 3), -det3(a, b, c, 0, 1, 3), det3(a, b, c, 0, 1, 2)};
}

bool is_zero(const H4& h) {
  return CGAL::is_zero(h[0]) && CGAL::is_zero(h[1]) && CGAL::is_zero(h[2]) && CGAL::is_zero(h[3]);
}

/// a u + b v + c >= 0 in a receiver's chart.
struct HalfPlane {
  FT a, b, c;
  [[nodiscard]] FT operator()(const Point2& p) const { return a * p.x() + b * p.y() + c; }
};

/// Clips a convex chart polygon to h >= 0 (vertices on the line kept, crossings only on strict
/// sign changes).
void clip(std::vector<Point2>& poly, const HalfPlane& h, std::vector<Point2>& scratch) {
  exact::clip_by_value(poly, h, [](const Point2& a, const Point2& b, const FT& t) { return a + t * (b - a); },
                       scratch);
}

/// The half-plane <h, lift(u, v)> >= 0 of the chart of P (axis k): P's plane solved for x_k
/// and put into h, cleared of the denominator n_k (whose sign it keeps).
HalfPlane chart_half_plane(const ExactFace& P, int k, const H4& h) {
  const int i = core::chart_i(k), j = core::chart_j(k);
  const FT& nk = P.normal[k];
  HalfPlane hp{h[i] * nk - h[k] * P.normal[i], h[j] * nk - h[k] * P.normal[j], h[3] * nk - h[k] * P.offset};
  if (CGAL::is_negative(nk)) hp = {-hp.a, -hp.b, -hp.c};
  return hp;
}

/// The chart box of a face as a counter-clockwise polygon.
std::vector<Point2> chart_box(const core::FacePrep& fp) {
  return {Point2(FT(fp.chart_min[0]), FT(fp.chart_min[1])), Point2(FT(fp.chart_max[0]), FT(fp.chart_min[1])),
          Point2(FT(fp.chart_max[0]), FT(fp.chart_max[1])), Point2(FT(fp.chart_min[0]), FT(fp.chart_max[1]))};
}

bool has_area(const std::vector<Point2>& poly) {
  return poly.size() >= 3 && !CGAL::is_zero(exact::polygon_area(poly.begin(), poly.end()));
}

class AreaReceiverJob {
 public:
  AreaReceiverJob(const core::PreparedScene& ctx, exact::ExactWorker& w, const ExactFace& light,
                  const AreaLightPrep& lp, std::size_t face_id, std::size_t light_id, bool polygons,
                  ShadowStats& stats)
      : ctx_(ctx), w_(w), light_(light), lp_(lp), face_id_(face_id), light_id_(light_id), polygons_(polygons),
        stats_(stats), fp_((*ctx.prep)[face_id]) {}

  exact::ReceiverResult run() {
    FaceLighting& out = item_.lighting;
    out.face_id = face_id_;
    out.light_id = light_id_;
    out.area = (*ctx_.face_area)[face_id_];
    if (fp_.degenerate) return std::move(item_);
    const ExactFace& P = w_.face(ctx_, face_id_);
    P_ = &P;
    const int k = fp_.axis;
    receiver_ = {P.normal.x(), P.normal.y(), P.normal.z(), P.offset};
    nk_sign_ = CGAL::sign(P.normal[k]);
    box_ = chart_box(fp_);

    // The light's vertices, and its convex pieces clipped to the front of P's plane.
    const bool finite = lp_.shape.finite;
    bool any_front = false, straddles = false;
    std::vector<H4> vertices;
    for (const Point3& v : light_.vertices) vertices.push_back(homogeneous(v, finite));
    for (const H4& v : vertices) {
      const CGAL::Sign s = CGAL::sign(dot4(receiver_, v));
      any_front |= s == CGAL::POSITIVE;
      straddles |= s == CGAL::NEGATIVE;
    }
    if (!any_front) return whole(LightRegion::Umbra);  // the face sees none of the light
    if (finite) {
      light_plane_ = H4{light_.normal.x(), light_.normal.y(), light_.normal.z(), light_.offset};
      bool face_in_front = false;
      for (const Point3& v : P.vertices) face_in_front |= CGAL::is_positive(dot4(*light_plane_, homogeneous(v)));
      if (!face_in_front) return whole(LightRegion::Umbra);  // behind the light, which shines forward
    }
    for (const std::vector<int>& piece : lp_.prep.convex_pieces) {
      std::vector<H4> poly;
      for (int v : piece) poly.push_back(vertices[v]);
      if (straddles) clip_homogeneous(poly, receiver_);
      if (poly.size() >= 3) light_pieces_.push_back(std::move(poly));
    }
    for (const std::vector<H4>& piece : light_pieces_)
      for (const H4& v : piece) light_points_.push_back(v);
    if (straddles) ++stats_.area_light_straddles;
    straddles_ = straddles;

    // The part of the face behind the light's plane sees none of it: umbra.
    if (light_plane_) {
      std::vector<Point2> back = box_;
      const H4 minus{-(*light_plane_)[0], -(*light_plane_)[1], -(*light_plane_)[2], -(*light_plane_)[3]};
      clip(back, chart_half_plane(minus), scratch2_);
      if (has_area(back)) {
        not_fully_lit_.push_back(back);
        umbra_.push_back(std::move(back));
      }
    }

    // Occluders: convex solids whole where the projection route takes them (an exact umbra for
    // the solid), other faces piece by piece. The receiver's own solid lies behind its plane.
    std::size_t casting = 0;
    const std::vector<std::size_t> faces = candidates();
    const std::vector<int>& solid_of = *ctx_.solid_of;
    const int own_solid = solid_of[face_id_];
    std::vector<int> solids_seen;
    for (std::size_t q : faces) {
      const int solid = solid_of[q];
      if (solid < 0) {
        casting += cast_face(q);
        continue;
      }
      if (solid == own_solid || std::find(solids_seen.begin(), solids_seen.end(), solid) != solids_seen.end())
        continue;
      solids_seen.push_back(solid);
      if (const std::optional<bool> cast = cast_solid(solid)) {
        casting += *cast ? 1 : 0;
        continue;
      }
      for (std::size_t q2 : faces)  // its faces one by one, as any other
        if (solid_of[q2] == solid) casting += cast_face(q2);
    }
    if (casting >= 2) ++stats_.area_umbra_bounded;
    ++stats_.area_receivers;
    measure(straddles);
    return std::move(item_);
  }

 private:
  // ---- the chart ----------------------------------------------------------------------------
  /// The half-plane <h, lift(u, v)> >= 0 of P's chart.
  HalfPlane chart_half_plane(const H4& h) const { return arealight::chart_half_plane(*P_, fp_.axis, h); }

  /// Sutherland-Hodgman on homogeneous vertices: keeps f >= 0.
  static void clip_homogeneous(std::vector<H4>& poly, const H4& f) {
    std::vector<H4> out;
    exact::clip_by_value(poly, [&](const H4& x) { return dot4(f, x); },
                         [](const H4& a, const H4& b, const FT& t) {
                           H4 x;
                           for (int c = 0; c < 4; ++c) x[c] = a[c] + t * (b[c] - a[c]);
                           return x;
                         }, out);
  }

  // ---- culling in doubles -------------------------------------------------------------------
  /// The faces whose bounding box meets the box of every segment from the light to the face
  /// (for a sun disk: of the face swept toward the sun across the scene), ascending.
  std::vector<std::size_t> candidates() const {
    const Face& face = ctx_.scene->faces[face_id_];
    std::array<double, 6> box{};
    bool first = true;
    auto grow = [&](const glm::dvec3& p) {
      for (int c = 0; c < 3; ++c) {
        box[c] = first ? p[c] : std::min(box[c], p[c]);
        box[3 + c] = first ? p[c] : std::max(box[3 + c], p[c]);
      }
      first = false;
    };
    for (const glm::dvec3& v : face.vertices) grow(v);
    if (!lp_.shape.finite) return sun_candidates();
    for (const glm::dvec3& v : lp_.shape.polygon) grow(v);
    double size = 0;
    for (int c = 0; c < 3; ++c) size = std::max({size, std::abs(box[c]), std::abs(box[3 + c]), box[3 + c] - box[c]});
    const double margin = 1e-9 * size + 1e-300;
    std::vector<std::size_t> result;
    for (std::size_t q = 0; q < ctx_.scene->faces.size(); ++q) {
      if (q == face_id_ || (*ctx_.prep)[q].degenerate) continue;
      const std::array<double, 6>& b = lp_.boxes[q];
      bool overlap = true;
      for (int c = 0; c < 3 && overlap; ++c) overlap = b[c] <= box[3 + c] + margin && box[c] <= b[3 + c] + margin;
      if (overlap) result.push_back(q);
    }
    stats_.candidate_pairs += result.size();
    return result;
  }

  /// A sun disk's candidates: in the frame (u, v, c) of the sun's central direction c, an
  /// occluder point x = p + t d (p on the face, d a direction of the cone with c . d = 1, t at
  /// most the scene's diagonal) has c . x >= c . p and lies within diagonal x spread of p across c.
  std::vector<std::size_t> sun_candidates() const {
    const Face& face = ctx_.scene->faces[face_id_];
    std::array<double, 6> box{};
    bool first = true;
    for (const glm::dvec3& x : face.vertices) {
      const double w[3] = {glm::dot(lp_.u, x), glm::dot(lp_.v, x), glm::dot(lp_.c, x)};
      for (int k = 0; k < 3; ++k) {
        box[k] = first ? w[k] : std::min(box[k], w[k]);
        box[3 + k] = first ? w[k] : std::max(box[3 + k], w[k]);
      }
      first = false;
    }
    double size = lp_.diagonal;
    for (int k = 0; k < 6; ++k) size = std::max(size, std::abs(box[k]));
    const double margin = 1e-9 * size + 1e-300;
    const double reach = lp_.diagonal * lp_.spread * (1 + 1e-6) + margin;
    std::vector<std::size_t> result;
    for (std::size_t q = 0; q < ctx_.scene->faces.size(); ++q) {
      if (q == face_id_ || (*ctx_.prep)[q].degenerate) continue;
      const std::array<double, 6>& b = lp_.sun_boxes[q];
      if (b[5] < box[2] - margin) continue;  // wholly on the far side from the sun
      bool overlap = true;
      for (int k = 0; k < 2 && overlap; ++k) overlap = b[k] <= box[3 + k] + reach && box[k] <= b[3 + k] + reach;
      if (overlap) result.push_back(q);
    }
    stats_.candidate_pairs += result.size();
    return result;
  }

  // ---- one occluder ------------------------------------------------------------------------
  /// Casts face q's convex pieces; returns how many cast something on the chart box.
  std::size_t cast_face(std::size_t q) {
    const ExactFace& Q = w_.face(ctx_, q);
    const core::FacePrep& qp = (*ctx_.prep)[q];
    const exact::Affine3 front{P_->normal, P_->offset};
    std::optional<exact::Affine3> light_front;
    if (light_plane_) light_front = exact::Affine3{light_.normal, light_.offset};
    std::size_t cast = 0;
    for (const std::vector<int>& piece : qp.convex_pieces) {
      std::vector<Point3> C;
      for (int v : piece) C.push_back(Q.vertices[v]);
      exact::clip_convex(C, front, w_.scratch);
      if (light_front) exact::clip_convex(C, *light_front, w_.scratch);
      // A piece lying in P's plane (the back face of a double-sided wall, a decal) or in the
      // light's plane comes back from the clip whole: it casts nothing (docs/algorithm.md §2).
      if (C.size() < 3 || !strictly_in_front(C)) continue;
      const H4 own{Q.normal.x(), Q.normal.y(), Q.normal.z(), Q.offset};
      cast += cast_piece(C, own) ? 1 : 0;
    }
    if (cast > 0) ++stats_.casting_pairs;
    return cast;
  }

  /// True when some point of C lies strictly in front of P's plane and some strictly in front
  /// of the light's (finite lights): only then can C stand between P and the light. C is convex
  /// and already clipped to both closed half-spaces, so it then has area in front of both.
  bool strictly_in_front(const std::vector<Point3>& C) const {
    bool receiver = false, light = !light_plane_;
    for (const Point3& c : C) {
      const H4 h = homogeneous(c);
      receiver = receiver || CGAL::is_positive(dot4(receiver_, h));
      light = light || CGAL::is_positive(dot4(*light_plane_, h));
      if (receiver && light) return true;
    }
    return false;
  }

  /// The chart point where the line from light point or direction l through x meets P's plane:
  /// s(l) x - s(x) l, homogeneous, with weight s(l) - s(x) w(l) > 0 (x nearer than l).
  Point2 project(const H4& l, const Point3& x) const {
    const FT sl = dot4(receiver_, l), sx = dot4(receiver_, homogeneous(x));
    const FT w = sl - sx * l[3];
    const int i = core::chart_i(fp_.axis), j = core::chart_j(fp_.axis);
    const FT xi = x[i] * sl - sx * l[i], xj = x[j] * sl - sx * l[j];
    return Point2(xi / w, xj / w);
  }

  /// True when the projection route applies to the convex set of points C: the light wholly
  /// in front of P and every point of C strictly nearer to P's plane than every light vertex
  /// (always so for directions).
  bool projections_apply(const std::vector<Point3>& C) const {
    if (straddles_ || force_separating_planes) return false;
    // Every light point strictly in front of P: a direction of a sun disk parallel to P's plane
    // (s = 0) has no shadow on P (project() would divide by zero).
    for (const H4& v : light_points_)
      if (!CGAL::is_positive(dot4(receiver_, v))) return false;
    if (!lp_.shape.finite) return true;
    FT lowest_light = dot4(receiver_, light_points_.front());
    for (const H4& v : light_points_) lowest_light = CGAL::min(lowest_light, dot4(receiver_, v));
    for (const Point3& c : C)
      if (CGAL::compare(dot4(receiver_, homogeneous(c)), lowest_light) != CGAL::SMALLER) return false;
    return true;
  }

  /// The projection route for the convex hull of the points C (a convex piece, or the vertices
  /// of a convex solid): per convex light piece, the hull of C's shadows from its vertices (not
  /// fully lit); the intersection over the light's vertices of C's shadow from each (umbra).
  bool cast_by_projection(const std::vector<Point3>& C) {
    ++stats_.area_projection_pieces;
    bool any = false;
    for (const std::vector<H4>& L : light_pieces_) {
      std::vector<Point2> shadows;
      for (const H4& v : L)
        for (const Point3& c : C) shadows.push_back(project(v, c));
      std::vector<Point2> hull;
      CGAL::convex_hull_2(shadows.begin(), shadows.end(), std::back_inserter(hull), exact::Kernel());
      for (int c = 0; c < 2; ++c) {
        exact::clip_convex_2d(hull, c, fp_.chart_min[c], true, scratch2_);
        exact::clip_convex_2d(hull, c, fp_.chart_max[c], false, scratch2_);
      }
      if (has_area(hull)) {
        not_fully_lit_.push_back(std::move(hull));
        any = true;
      }
    }
    if (!any) return false;  // the umbra lies inside: nothing on the chart box either
    std::vector<Point2> umbra = box_;
    for (const H4& v : light_points_) {
      if (umbra.empty()) break;
      std::vector<Point2> projected, from_v;
      for (const Point3& c : C) projected.push_back(project(v, c));
      CGAL::convex_hull_2(projected.begin(), projected.end(), std::back_inserter(from_v), exact::Kernel());
      if (!has_area(from_v)) {  // edge-on from this vertex: no umbra
        umbra.clear();
        break;
      }
      for (std::size_t a = 0; a < from_v.size() && !umbra.empty(); ++a) {  // counter-clockwise
        const Point2& p = from_v[a];
        const Point2& r = from_v[(a + 1) % from_v.size()];
        // orientation(p, r, x) = (r - p) x (x - p) >= 0
        clip(umbra, HalfPlane{-(r.y() - p.y()), r.x() - p.x(), (r.y() - p.y()) * p.x() - (r.x() - p.x()) * p.y()},
             scratch2_);
      }
    }
    if (has_area(umbra)) umbra_.push_back(std::move(umbra));
    return true;
  }

  /// A convex solid as one occluder (its umbra is then exact, not the union of its faces'), when
  /// the projection route applies to it unclipped: every vertex on or in front of P's plane (and
  /// of the light's), nearer to P's plane than the light. Empty when it does not apply.
  std::optional<bool> cast_solid(int solid) {
    const core::ConvexSolid& cs = (*ctx_.solids)[static_cast<std::size_t>(solid)];
    std::vector<Point3> C;
    bool any_front = false;
    for (const glm::dvec3& v : cs.vertices) {
      C.push_back(exact::to_exact(v));
      const CGAL::Sign side = CGAL::sign(dot4(receiver_, homogeneous(C.back())));
      if (side == CGAL::NEGATIVE) return std::nullopt;
      any_front |= side == CGAL::POSITIVE;
      if (light_plane_ && CGAL::is_negative(dot4(*light_plane_, homogeneous(C.back())))) return std::nullopt;
    }
    if (!any_front || !projections_apply(C)) return std::nullopt;
    const bool cast = cast_by_projection(C);
    if (cast) ++stats_.casting_pairs;
    return cast;
  }

  bool cast_piece(const std::vector<Point3>& C, const H4& own_plane) {
    if (projections_apply(C)) return cast_by_projection(C);
    ++stats_.area_plane_pieces;
    std::vector<H4> Ch;
    for (const Point3& c : C) Ch.push_back(homogeneous(c));
    bool any = false;
    for (const std::vector<H4>& L : light_pieces_) {
      std::vector<Point2> region = box_;
      separate(L, Ch, own_plane, region);
      if (has_area(region)) {
        not_fully_lit_.push_back(std::move(region));
        any = true;
      }
    }
    std::vector<Point2> umbra = box_;
    for (const H4& v : light_points_) {
      if (umbra.empty()) break;
      separate({v}, Ch, own_plane, umbra);
    }
    if (has_area(umbra)) umbra_.push_back(std::move(umbra));
    return any;
  }

  /// Clips `region` to every half-plane <H, p> >= 0 of P's plane for the planes H that separate
  /// the convex light piece L (<H, l> <= 0) from the convex occluder C (<H, c> >= 0): through an
  /// edge of one and a vertex of the other, L's plane (finite lights) and C's plane. A point p of
  /// P's plane sees all of L past C exactly when some such plane has it strictly on L's side.
  void separate(const std::vector<H4>& L, const std::vector<H4>& C, const H4& own_plane,
                std::vector<Point2>& region) {
    auto consider = [&](const H4& h) {
      if (region.empty() || is_zero(h)) return;
      bool plus = true, minus = true;  // H or -H separates
      for (const H4& l : L) {
        const CGAL::Sign s = CGAL::sign(dot4(h, l));
        plus &= s != CGAL::POSITIVE;
        minus &= s != CGAL::NEGATIVE;
        if (!plus && !minus) return;
      }
      for (const H4& c : C) {
        const CGAL::Sign s = CGAL::sign(dot4(h, c));
        plus &= s != CGAL::NEGATIVE;
        minus &= s != CGAL::POSITIVE;
        if (!plus && !minus) return;
      }
      if (plus) clip(region, chart_half_plane(h), scratch2_);
      if (minus) clip(region, chart_half_plane(H4{-h[0], -h[1], -h[2], -h[3]}), scratch2_);
    };
    const std::size_t nl = L.size(), nc = C.size();
    consider(own_plane);
    if (light_plane_ && nl >= 3) consider(*light_plane_);
    for (std::size_t a = 0; a < nl && nl >= 2; ++a)
      for (const H4& c : C) consider(plane_through(L[a], L[(a + 1) % nl], c));
    for (std::size_t a = 0; a < nc; ++a)
      for (const H4& l : L) consider(plane_through(C[a], C[(a + 1) % nc], l));
  }

  // ---- regions, areas, fragments ------------------------------------------------------------
  exact::ReceiverResult whole(LightRegion region) {
    FaceLighting& out = item_.lighting;
    ++stats_.area_receivers;
    out.umbra_area = region == LightRegion::Umbra ? out.area : 0.0;
    out.fully_lit_area = region == LightRegion::FullyLit ? out.area : 0.0;
    if (polygons_) {
      const ExactFace& P = w_.face(ctx_, face_id_);
      P_ = &P;
      emit({PolygonWithHoles2(P.chart)}, region);
      finish_dropped();
    }
    return std::move(item_);
  }

  static FT set_area(const PolygonSet2& set, std::vector<PolygonWithHoles2>& regions) {
    set.polygons_with_holes(std::back_inserter(regions));
    std::vector<FT> areas;
    for (const PolygonWithHoles2& r : regions) areas.push_back(exact::region_area(r));
    return exact::balanced_sum(areas);
  }

  /// The union of convex chart polygons (either orientation), in one aggregated join.
  static PolygonSet2 joined(const std::vector<std::vector<Point2>>& regions) {
    PolygonSet2 set;
    std::vector<Polygon2> polys;
    for (const std::vector<Point2>& r : regions) {
      Polygon2 poly(r.begin(), r.end());
      if (CGAL::is_negative(exact::polygon_area(poly))) poly.reverse_orientation();
      polys.push_back(std::move(poly));
    }
    if (!polys.empty()) set.join(polys.begin(), polys.end());
    return set;
  }

  void measure(bool straddles) {
    const ExactFace& P = *P_;
    FaceLighting& out = item_.lighting;
    PolygonSet2 nfl(P.chart);  // not fully lit
    // a face that cannot see all of the light is nowhere fully lit
    if (!straddles) nfl.intersection(joined(not_fully_lit_));
    PolygonSet2 um(P.chart);
    um.intersection(joined(umbra_));
    std::vector<PolygonWithHoles2> nfl_regions, um_regions;
    const FT nfl_area = set_area(nfl, nfl_regions);
    const FT um_area = set_area(um, um_regions);
    out.fully_lit_area = exact::area_3d(P.chart_area - nfl_area, P.area_scale_squared);
    out.penumbra_area = exact::area_3d(nfl_area - um_area, P.area_scale_squared);
    out.umbra_area = exact::area_3d(um_area, P.area_scale_squared);
    if (!polygons_) return;
    std::vector<PolygonWithHoles2> lit, penumbra;
    PolygonSet2 lit_set(P.chart);
    lit_set.difference(nfl);
    lit_set.polygons_with_holes(std::back_inserter(lit));
    PolygonSet2 penumbra_set(nfl);
    penumbra_set.difference(um);
    penumbra_set.polygons_with_holes(std::back_inserter(penumbra));
    emit(lit, LightRegion::FullyLit);
    emit(penumbra, LightRegion::Penumbra);
    emit(um_regions, LightRegion::Umbra);
    finish_dropped();
  }

  void finish_dropped() {
    if (!dropped_.empty()) item_.lighting.dropped_area = exact::area_3d(exact::balanced_sum(dropped_), P_->area_scale_squared);
  }

  /// One cell as a fragment if its vertices rounded to doubles still make a simple polygon of
  /// non-zero area (as the point-light engine writes them).
  bool write(const Polygon2& cell, const FT& cell_area, LightRegion region) {
    Fragment fragment;
    fragment.face_id = face_id_;
    fragment.light_id = light_id_;
    fragment.fragment_id = fragment_id_;
    fragment.lit = region != LightRegion::Umbra;
    fragment.region = region;
    fragment.area = exact::area_3d(CGAL::abs(cell_area), P_->area_scale_squared);
    for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
      fragment.polygon.push_back(exact::nearest_doubles(exact::lift(*v, *P_, fp_.axis)));
    }
    if (fp_.flipped == CGAL::is_positive(cell_area)) std::reverse(fragment.polygon.begin(), fragment.polygon.end());
    if (!core::clean_double_polygon(fragment.polygon, fp_.axis)) return false;
    item_.fragments.push_back(std::move(fragment));
    return true;
  }

  void emit(const std::vector<PolygonWithHoles2>& regions, LightRegion region) {
    std::vector<Polygon2> cells, triangles;
    for (const PolygonWithHoles2& r : regions) {
      cells.clear();
      exact::append_simple_cells(r, cells);
      const std::size_t written = item_.fragments.size();
      for (Polygon2& cell : cells) {
        const FT cell_area = exact::polygon_area(cell);
        if (write(cell, cell_area, region)) continue;
        if (CGAL::is_negative(cell_area)) cell.reverse_orientation();
        triangles.clear();
        exact::triangulate_region(PolygonWithHoles2(cell), triangles);
        for (const Polygon2& t : triangles) {
          const FT t_area = exact::polygon_area(t);
          if (!write(t, t_area, region)) {
            dropped_.push_back(CGAL::abs(t_area));
            ++stats_.dropped_cells;
          }
        }
      }
      if (item_.fragments.size() > written) ++fragment_id_;
    }
  }

  const core::PreparedScene& ctx_;
  exact::ExactWorker& w_;
  const ExactFace& light_;
  const AreaLightPrep& lp_;
  std::size_t face_id_, light_id_;
  bool polygons_;
  ShadowStats& stats_;
  const core::FacePrep& fp_;
  const ExactFace* P_ = nullptr;
  H4 receiver_;
  CGAL::Sign nk_sign_ = CGAL::POSITIVE;
  std::optional<H4> light_plane_;
  bool straddles_ = false;
  std::vector<Point2> box_, scratch2_;
  std::vector<std::vector<H4>> light_pieces_;
  std::vector<H4> light_points_;
  std::vector<std::vector<Point2>> not_fully_lit_, umbra_;
  exact::ReceiverResult item_;
  std::size_t fragment_id_ = 0;
  std::vector<FT> dropped_;
};

}  // namespace

AreaLightPrep prepare_area_light(const core::PreparedScene& ctx, const Light& light, std::size_t light_id) {
  AreaLightPrep lp;
  lp.shape = light_shape(light);
  lp.prep = exact::prepare_face(lp.shape.polygon);
  if (lp.prep.degenerate || lp.prep.convex_pieces.empty())
    throw InputError({ctx.scene->source.string(), "lights[" + std::to_string(light_id) + "]"},
                     "the light's polygon has zero area in exact arithmetic (too small for its coordinates)");
  const Scene& scene = *ctx.scene;
  lp.boxes.resize(scene.faces.size());
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    std::array<double, 6>& b = lp.boxes[f];
    b = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
         std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest(),
         std::numeric_limits<double>::lowest()};
    for (const glm::dvec3& v : scene.faces[f].vertices)
      for (int c = 0; c < 3; ++c) {
        b[c] = std::min(b[c], v[c]);
        b[3 + c] = std::max(b[3 + c], v[c]);
        lo[c] = std::min(lo[c], v[c]);
        hi[c] = std::max(hi[c], v[c]);
      }
  }
  lp.diagonal = scene.faces.empty() ? 1.0 : glm::length(hi - lo) + 1e-300;
  if (!lp.shape.finite) {
    // The sun's frame: c the central direction, u and v across it; the cone's spread across c
    // per unit along it (its directions have c . d = 1 up to rounding).
    lp.c = geometry::unit(light.to_light);  // any finite scale: |to_light|^2 may overflow
    lp.u = glm::normalize(glm::cross(lp.c, std::abs(lp.c.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    lp.v = glm::cross(lp.c, lp.u);
    for (const glm::dvec3& d : lp.shape.polygon) {
      const double along = glm::dot(lp.c, d);
      lp.spread = std::max(lp.spread, std::hypot(glm::dot(lp.u, d), glm::dot(lp.v, d)) / along);
    }
    lp.spread = lp.spread * (1 + 1e-9) + 1e-12;
    lp.sun_boxes.resize(scene.faces.size());
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      std::array<double, 6>& b = lp.sun_boxes[f];
      b = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
           std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
           std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
      for (const glm::dvec3& x : scene.faces[f].vertices) {
        const double w[3] = {glm::dot(lp.u, x), glm::dot(lp.v, x), glm::dot(lp.c, x)};
        for (int k = 0; k < 3; ++k) {
          b[k] = std::min(b[k], w[k]);
          b[3 + k] = std::max(b[3 + k], w[k]);
        }
      }
    }
  }
  return lp;
}

exact::ReceiverResult compute_area_receiver(const core::PreparedScene& ctx, exact::ExactWorker& w, AreaWorker& aw,
                                            const AreaLightPrep& light, std::size_t face_id, std::size_t light_id,
                                            bool polygons, ShadowStats& stats) {
  if (!aw.exact) {
    aw.exact = std::make_shared<AreaWorker::Exact>();
    aw.exact->light = exact::make_exact_face(light.shape.polygon, light.prep);
  }
  return AreaReceiverJob(ctx, w, aw.exact->light, light, face_id, light_id, polygons, stats).run();
}

void restrict_centre_to_emitting_side(const core::PreparedScene& ctx, exact::ExactWorker& w, AreaWorker& aw,
                                      const AreaLightPrep& light, std::size_t face_id, std::size_t light_id,
                                      const Light& centre, ShadowStats& stats, FaceLighting& out) {
  const core::FacePrep& fp = (*ctx.prep)[face_id];
  if (!light.shape.finite || fp.degenerate) return;
  if (!aw.exact) {
    aw.exact = std::make_shared<AreaWorker::Exact>();
    aw.exact->light = exact::make_exact_face(light.shape.polygon, light.prep);
  }
  // The plane the regions use (AreaReceiverJob's light_plane_): positive on the emitting side.
  const ExactFace& L = aw.exact->light;
  const H4 plane{L.normal.x(), L.normal.y(), L.normal.z(), L.offset};
  const ExactFace& P = w.face(ctx, face_id);
  bool front = false, back = false;
  for (const Point3& v : P.vertices) {
    const CGAL::Sign s = CGAL::sign(dot4(plane, homogeneous(v)));
    front |= s == CGAL::POSITIVE;
    back |= s == CGAL::NEGATIVE;
  }
  if (!back) return;  // nothing of the face behind the light: the centre's result stands
  ++stats.area_centre_behind;
  if (!front || (out.lit_area == 0.0 && out.lit_area_error_bound == 0.0)) {  // wholly behind, or dark anyway
    out.lit_area = 0.0;
    out.shadow_area = out.area;
    out.lit_fraction = 0.0;
    out.lit_area_error_bound = 0.0;
    return;
  }
  // Straddling: the centre's exact lit region cut to the front of the light's plane.
  const exact::ExactLight el = exact::to_exact_light(centre);
  const int facing = CGAL::sign(exact::plane_at_light(P, el));
  ShadowStats not_counted;  // the receiver was counted by the centre's own computation
  exact::LitRegion region = exact::exact_lit_region(ctx, w, face_id, light_id, el, facing, centre, nullptr, not_counted);
  FT lit_chart(0);
  if (region.kind != exact::LitRegion::Kind::Dark) {
    PolygonSet2 lit = region.kind == exact::LitRegion::Kind::Whole ? PolygonSet2(P.chart) : std::move(region.lit);
    std::vector<Point2> in_front = chart_box(fp), scratch;
    clip(in_front, chart_half_plane(P, fp.axis, plane), scratch);
    if (has_area(in_front)) {
      Polygon2 cut(in_front.begin(), in_front.end());
      if (cut.is_clockwise_oriented()) cut.reverse_orientation();
      lit.intersection(cut);
      std::vector<PolygonWithHoles2> regions;
      lit.polygons_with_holes(std::back_inserter(regions));
      std::vector<FT> areas;
      for (const PolygonWithHoles2& r : regions) areas.push_back(exact::region_area(r));
      lit_chart = exact::balanced_sum(areas);
    }
  }
  const auto [chart, scale] = w.exact_areas(ctx, face_id);
  FT::Exact_type shadow = *chart - CGAL::exact(lit_chart), lit, scratch;
  exact::measure_lit_and_shadow(*chart, *scale, shadow, lit, scratch, out);
  out.lit_area_error_bound = 0.0;
}

}  // namespace shadow::arealight
