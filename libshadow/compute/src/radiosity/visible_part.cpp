// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/visible_part.hpp"

#include "arealight/light_visibility.hpp"
#include "radiosity/triangles.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace shadow::radiosity {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// `poly` split by the line through p0 along d: the part to its left (inside a counter-clockwise
/// convex polygon with that edge) into `inside`, the part to its right into `outside`.
void split_by_line(const std::vector<glm::dvec2>& poly, const glm::dvec2& p0, const glm::dvec2& d,
                   std::vector<glm::dvec2>& inside, std::vector<glm::dvec2>& outside) {
  inside.clear();
  outside.clear();
  const std::size_t m = poly.size();
  for (std::size_t k = 0; k < m; ++k) {
    const glm::dvec2& a = poly[k];
    const glm::dvec2& b = poly[(k + 1) % m];
    const double da = d.x * (a.y - p0.y) - d.y * (a.x - p0.x), db = d.x * (b.y - p0.y) - d.y * (b.x - p0.x);
    if (da >= 0) inside.push_back(a);
    if (da <= 0) outside.push_back(a);
    if ((da > 0 && db < 0) || (da < 0 && db > 0)) {
      const glm::dvec2 c = a + (b - a) * (da / (da - db));
      inside.push_back(c);
      outside.push_back(c);
    }
  }
}

/// Whether a counter-clockwise polygon is convex (no right turn).
bool convex(const std::vector<glm::dvec2>& p) {
  const std::size_t m = p.size();
  for (std::size_t i = 0; i < m; ++i) {
    const glm::dvec2 a = p[(i + 1) % m] - p[i], b = p[(i + 2) % m] - p[(i + 1) % m];
    if (a.x * b.y - a.y * b.x < 0.0) return false;
  }
  return true;
}

double twice_area(const std::vector<glm::dvec2>& p) {
  double s = 0.0;
  for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) s += p[j].x * p[i].y - p[i].x * p[j].y;
  return s;
}

}  // namespace

void clip_half_space(const std::vector<glm::dvec3>& polygon, const glm::dvec3& n, const glm::dvec3& o,
                     std::vector<glm::dvec3>& out) {
  out.clear();
  const std::size_t m = polygon.size();
  for (std::size_t i = 0; i < m; ++i) {
    const glm::dvec3& a = polygon[i];
    const glm::dvec3& b = polygon[(i + 1) % m];
    const double da = glm::dot(n, a - o), db = glm::dot(n, b - o);
    if (da > 0) out.push_back(a);
    if ((da > 0) != (db > 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
}

double signed_contour(const glm::dvec3& x, const glm::dvec3& nr, const std::vector<glm::dvec3>& polygon,
                      std::vector<glm::dvec3>& r) {
  r.resize(polygon.size());
  for (std::size_t i = 0; i < polygon.size(); ++i) r[i] = polygon[i] - x;
  return -0.5 * detail::lambert_contour(r, nr) / kPi;
}

SourceChart::SourceChart(const std::vector<glm::dvec3>& polygon) : polygon_(polygon) {
  const glm::dvec3 n = newell_normal(polygon);
  if (polygon.size() < 3 || !(glm::length(n) > 0.0)) return;
  normal_ = glm::normalize(n);
  origin_ = polygon[0];
  // u along the longest edge, v = n x u: counter-clockwise seen from the front stays so.
  glm::dvec3 edge(0.0);
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec3 e = polygon[(i + 1) % polygon.size()] - polygon[i];
    if (glm::length(e) > glm::length(edge)) edge = e;
  }
  u_ = glm::normalize(edge - glm::dot(edge, normal_) * normal_);
  v_ = glm::cross(normal_, u_);
  lo_ = hi_ = to_chart(polygon[0]);
  for (const glm::dvec3& p : polygon) lo_ = glm::min(lo_, to_chart(p)), hi_ = glm::max(hi_, to_chart(p));
  const double extent = std::max(hi_.x - lo_.x, hi_.y - lo_.y);
  if (!(extent > 0.0)) return;
  // The occluders' shadows are cut to the source's box widened by its extent each way: grid
  // coordinates then stay within 1e9, Clipper's fast 64-bit range.
  scale_ = 3.0e8 / extent;
  usable_ = true;
}

glm::dvec2 SourceChart::to_chart(const glm::dvec3& p) const {
  const glm::dvec3 d = p - origin_;
  return {glm::dot(d, u_), glm::dot(d, v_)};
}

glm::dvec3 SourceChart::from_grid(const ClipperLib::IntPoint& p) const {
  return origin_ + (static_cast<double>(p.X) / scale_) * u_ + (static_cast<double>(p.Y) / scale_) * v_;
}

double SourceChart::unoccluded(const glm::dvec3& x, const glm::dvec3& nr, VisibleScratch& s) const {
  if (!usable_ || !(glm::dot(normal_, x - origin_) > 0.0)) return 0.0;
  clip_half_space(polygon_, nr, x, s.front);
  if (s.front.size() < 3) return 0.0;
  return std::max(0.0, signed_contour(x, nr, s.front, s.r));
}

double SourceChart::form_factor(const glm::dvec3& x, const glm::dvec3& nr,
                                const std::vector<const std::vector<glm::dvec3>*>& occluders,
                                VisibleScratch& s) const {
  const double height = glm::dot(normal_, x - origin_);
  if (!usable_ || !(height > 0.0)) return 0.0;
  clip_half_space(polygon_, nr, x, s.front);
  if (s.front.size() < 3) return 0.0;
  glm::dvec2 front_lo = to_chart(s.front[0]), front_hi = front_lo;
  for (const glm::dvec3& p : s.front) front_lo = glm::min(front_lo, to_chart(p)), front_hi = glm::max(front_hi, to_chart(p));
  // The pyramid from x over the source's box widened by its size each way: what an occluder
  // holds outside it is cut off in 3D, so that every projected point stays in that box.
  const glm::dvec2 pad = hi_ - lo_;
  const glm::dvec2 c0 = lo_ - pad, c1 = hi_ + pad;
  const glm::dvec3 corners[4] = {origin_ + c0.x * u_ + c0.y * v_, origin_ + c1.x * u_ + c0.y * v_,
                                 origin_ + c1.x * u_ + c1.y * v_, origin_ + c0.x * u_ + c1.y * v_};
  // The half-spaces an occluder's part must lie in to hide anything: in front of x, in front of
  // the source's plane, nearer to it than x, and inside the pyramid's four sides.
  glm::dvec3 normals[7] = {nr, normal_, -normal_};
  glm::dvec3 points[7] = {x, origin_, x};
  for (int k = 0; k < 4; ++k) {
    // Counter-clockwise seen from the front (from x): the inward side is to the left.
    normals[3 + k] = glm::cross(corners[(k + 1) % 4] - x, corners[k] - x);
    points[3 + k] = x;
  }
  std::size_t shadows = 0;
  for (const std::vector<glm::dvec3>* occluder : occluders) {
    // Only that part can meet a segment from x to the source; it is projected from x onto the
    // source's plane. Most occluders are wholly in or wholly out of most half-spaces: those
    // are decided without clipping.
    const std::vector<glm::dvec3>* poly = occluder;
    bool gone = false;
    for (int k = 0; k < 7 && !gone; ++k) {
      bool any_in = false, any_out = false;
      for (const glm::dvec3& y : *poly) {
        const double d = glm::dot(normals[k], y - points[k]);
        any_in = any_in || d > 0;
        any_out = any_out || !(d > 0);
      }
      if (!any_in) gone = true;
      if (gone || !any_out) continue;
      std::vector<glm::dvec3>& out = poly == &s.clipped ? s.next : s.clipped;
      clip_half_space(*poly, normals[k], points[k], out);
      poly = &out;
      gone = out.size() < 3;
    }
    if (gone) continue;
    s.flat.clear();
    for (const glm::dvec3& y : *poly) {
      const double hy = glm::dot(normal_, y - origin_);
      if (!(height - hy > 0.0)) continue;
      s.flat.push_back(to_chart(x + (height / (height - hy)) * (y - x)));
    }
    if (s.flat.size() < 3) continue;
    for (glm::dvec2& p : s.flat) p = glm::clamp(p, c0, c1);  // rounding only
    glm::dvec2 a = s.flat[0], b = a;
    for (const glm::dvec2& p : s.flat) a = glm::min(a, p), b = glm::max(b, p);
    if (a.x >= front_hi.x || b.x <= front_lo.x || a.y >= front_hi.y || b.y <= front_lo.y) continue;
    // Counter-clockwise, so that non-zero filling unites the shadows.
    if (twice_area(s.flat) < 0) std::reverse(s.flat.begin(), s.flat.end());
    if (s.shadows.size() <= shadows) s.shadows.emplace_back();
    s.shadows[shadows].swap(s.flat);
    s.shadow_boxes.resize(shadows + 1);
    s.shadow_boxes[shadows] = {a.x, a.y, b.x, b.y};
    ++shadows;
  }
  if (shadows == 0) return std::max(0.0, signed_contour(x, nr, s.front, s.r));
  const Shadows kind = classify_shadows(s, shadows);
  double f = 0.0;
  if (kind == Shadows::Disjoint)
    f = subtract_each(x, nr, s, shadows);
  else if (kind != Shadows::Convex || !subtract_pieces(x, nr, s, shadows, f))
    f = subtract_union(x, nr, s, shadows);
  return std::max(0.0, f);
}

SourceChart::Shadows SourceChart::classify_shadows(VisibleScratch& s, std::size_t shadows) const {
  bool disjoint = true;
  for (std::size_t i = 0; i < shadows; ++i) {
    if (!convex(s.shadows[i])) return Shadows::General;
    const glm::dvec4& p = s.shadow_boxes[i];
    for (std::size_t j = 0; j < i && disjoint; ++j) {
      const glm::dvec4& q = s.shadow_boxes[j];
      if (p.x < q.z && q.x < p.z && p.y < q.w && q.y < p.w) disjoint = false;
    }
  }
  return disjoint ? Shadows::Disjoint : Shadows::Convex;
}

bool SourceChart::subtract_pieces(const glm::dvec3& x, const glm::dvec3& nr, VisibleScratch& s,
                                  std::size_t shadows, double& f) const {
  // What is left of the front part is kept as disjoint convex pieces; each convex shadow splits
  // a piece it overlaps along its edges' lines (the parts outside one edge and inside the ones
  // before it), and the part inside all of them, the shadowed part, is dropped.
  constexpr std::size_t kMaxPieces = 256;  // beyond: Clipper
  std::size_t count = 1;
  if (s.pieces.empty()) s.pieces.emplace_back();
  s.pieces[0].clear();
  for (const glm::dvec3& p : s.front) s.pieces[0].push_back(to_chart(p));
  for (std::size_t i = 0; i < shadows; ++i) {
    const std::vector<glm::dvec2>& q = s.shadows[i];
    const glm::dvec4& qb = s.shadow_boxes[i];
    std::size_t next = 0;
    auto take = [&]() -> std::vector<glm::dvec2>& {
      if (s.next_pieces.size() <= next) s.next_pieces.emplace_back();
      return s.next_pieces[next++];
    };
    for (std::size_t k = 0; k < count; ++k) {
      std::vector<glm::dvec2>& piece = s.pieces[k];
      glm::dvec2 a = piece[0], b = a;
      for (const glm::dvec2& p : piece) a = glm::min(a, p), b = glm::max(b, p);
      if (a.x >= qb.z || qb.x >= b.x || a.y >= qb.w || qb.y >= b.y) {
        take().swap(piece);
        continue;
      }
      s.flat.swap(piece);  // the rest, inside the edges so far
      for (std::size_t e = 0; e < q.size() && s.flat.size() >= 3; ++e) {
        const glm::dvec2 p0 = q[e], d = q[(e + 1) % q.size()] - p0;
        if (d.x == 0.0 && d.y == 0.0) continue;  // a repeated vertex: no line
        std::vector<glm::dvec2>& outside = take();
        split_by_line(s.flat, p0, d, s.flat_next, outside);
        if (outside.size() < 3) --next;
        s.flat.swap(s.flat_next);
      }
      if (next > kMaxPieces) return false;
    }
    s.pieces.swap(s.next_pieces);
    count = next;
    if (count == 0) break;
  }
  f = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    s.next.clear();
    for (const glm::dvec2& p : s.pieces[k]) s.next.push_back(origin_ + p.x * u_ + p.y * v_);
    f += signed_contour(x, nr, s.next, s.r);
  }
  return true;
}

double SourceChart::subtract_each(const glm::dvec3& x, const glm::dvec3& nr, VisibleScratch& s,
                                  std::size_t shadows) const {
  // Shadows that do not overlap: F(front) minus F(front cut to each), each cut a convex
  // clipping (Sutherland-Hodgman keeps the contour integral right for any subject polygon).
  double sum = signed_contour(x, nr, s.front, s.r);
  s.front_flat.clear();
  for (const glm::dvec3& p : s.front) s.front_flat.push_back(to_chart(p));
  for (std::size_t i = 0; i < shadows; ++i) {
    s.flat = s.front_flat;
    const std::vector<glm::dvec2>& q = s.shadows[i];
    for (std::size_t e = 0; e < q.size() && s.flat.size() >= 3; ++e) {
      const glm::dvec2 p0 = q[e], d = q[(e + 1) % q.size()] - p0;
      s.flat_next.clear();
      const std::size_t m = s.flat.size();
      for (std::size_t k = 0; k < m; ++k) {
        const glm::dvec2& a = s.flat[k];
        const glm::dvec2& b = s.flat[(k + 1) % m];
        const double da = d.x * (a.y - p0.y) - d.y * (a.x - p0.x), db = d.x * (b.y - p0.y) - d.y * (b.x - p0.x);
        if (da >= 0) s.flat_next.push_back(a);
        if ((da >= 0) != (db >= 0)) s.flat_next.push_back(a + (b - a) * (da / (da - db)));
      }
      s.flat.swap(s.flat_next);
    }
    if (s.flat.size() < 3) continue;
    s.next.clear();
    for (const glm::dvec2& p : s.flat) s.next.push_back(origin_ + p.x * u_ + p.y * v_);
    sum -= signed_contour(x, nr, s.next, s.r);
  }
  return sum;
}

double SourceChart::subtract_union(const glm::dvec3& x, const glm::dvec3& nr, VisibleScratch& s,
                                   std::size_t shadows) const {
  auto grid = [&](const glm::dvec2& c) {
    return ClipperLib::IntPoint(static_cast<ClipperLib::cInt>(std::llround((c.x - lo_.x) * scale_)),
                                static_cast<ClipperLib::cInt>(std::llround((c.y - lo_.y) * scale_)));
  };
  s.clips.resize(shadows);
  for (std::size_t i = 0; i < shadows; ++i) {
    s.clips[i].clear();
    for (const glm::dvec2& p : s.shadows[i]) s.clips[i].push_back(grid(p));
  }
  s.subject.clear();
  for (const glm::dvec3& p : s.front) s.subject.push_back(grid(to_chart(p)));
  s.clipper.Clear();
  s.clipper.AddPath(s.subject, ClipperLib::ptSubject, true);
  s.clipper.AddPaths(s.clips, ClipperLib::ptClip, true);
  s.visible.clear();
  s.clipper.Execute(ClipperLib::ctDifference, s.visible, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  // Outer boundaries come out counter-clockwise and holes clockwise: their contours add up.
  double sum = 0.0;
  for (const ClipperLib::Path& path : s.visible) {
    s.next.clear();
    for (const ClipperLib::IntPoint& p : path)
      s.next.push_back(from_grid({p.X, p.Y}) + lo_.x * u_ + lo_.y * v_);
    sum += signed_contour(x, nr, s.next, s.r);
  }
  return sum;
}

}  // namespace shadow::radiosity
