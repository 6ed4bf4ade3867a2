// SPDX-License-Identifier: GPL-3.0-or-later
// The union of a plane's images by tiles (planes/plane_steps.hpp): the tile grid, each tile's
// images clipped to it and united exactly (CGAL), and the tiles' regions joined back along their
// shared borders (see plane_shadows.cpp).
#include "planes/plane_steps.hpp"

#include "geometry/box_sides.hpp"
#include "geometry/clip_convex.hpp"
#include "core/culling.hpp"
#include "exact/convex_solids.hpp"
#include "exact/exact_faces.hpp"
#include "runtime/parallel.hpp"
#include "exact/regions.hpp"
#include "core/input_checks.hpp"
#include "core/lights.hpp"

#include <shadow/validation.hpp>
#include <shadow/shadows.hpp>

#include <CGAL/Interval_nt.h>
#include <CGAL/version.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow::planes::steps {
namespace {

constexpr std::size_t kMaxTilesPerAxis = 16;

}  // namespace

Grid make_grid(const std::vector<Image>& images, const Tiling& tiling) {
  Grid grid;
  if (images.size() < tiling.tile_from || tiling.per_tile == 0) return grid;
  const double wanted = static_cast<double>(images.size()) / static_cast<double>(tiling.per_tile);
  std::array<std::vector<double>, 2> centre;
  std::size_t fit[2];
  std::vector<double> extent(images.size());
  for (int axis = 0; axis < 2; ++axis) {
    for (std::size_t a = 0; a < images.size(); ++a) extent[a] = images[a].box[axis + 2] - images[a].box[axis];
    std::nth_element(extent.begin(), extent.begin() + static_cast<std::ptrdiff_t>(extent.size() / 2), extent.end());
    const double median_extent = extent[extent.size() / 2];
    centre[axis].resize(images.size());
    for (std::size_t a = 0; a < images.size(); ++a) centre[axis][a] = 0.5 * images[a].box[axis] + 0.5 * images[a].box[axis + 2];
    std::sort(centre[axis].begin(), centre[axis].end());
    const double spread = centre[axis].back() - centre[axis].front();
    const double wide = tiling.tile_over_image > 0 ? spread / (tiling.tile_over_image * median_extent) : 1e6;
    fit[axis] = wide >= 1 && std::isfinite(wide) ? static_cast<std::size_t>(std::min(wide, 1e6)) : 1;
  }
  // The square grid's share per axis; what one axis cannot take (fit) goes to the other. Every
  // count is in [1, kMaxTilesPerAxis] (share's range, fit >= 1).
  const auto share = [](double of) {
    return static_cast<std::size_t>(std::clamp(std::round(of), 1.0, static_cast<double>(kMaxTilesPerAxis)));
  };
  std::size_t count[2];
  count[0] = std::min(share(std::sqrt(wanted)), fit[0]);
  count[1] = std::min(share(wanted / static_cast<double>(count[0])), fit[1]);
  count[0] = std::min(std::max(count[0], share(wanted / static_cast<double>(count[1]))), fit[0]);
  for (int axis = 0; axis < 2; ++axis) {
    const std::vector<double>& sorted = centre[axis];
    const std::size_t g = count[axis];
    for (std::size_t c = 1; c < g; ++c) {
      const double cut = sorted[c * sorted.size() / g];
      if (std::isfinite(cut) && (grid.cuts[axis].empty() || cut > grid.cuts[axis].back())) grid.cuts[axis].push_back(cut);
    }
  }
  return grid;
}

namespace {

/// Spreads the low 16 bits of v to the even bits (Morton code).
std::uint32_t spread(std::uint32_t v) {
  v &= 0xffff;
  v = (v | (v << 8)) & 0x00ff00ff;
  v = (v | (v << 4)) & 0x0f0f0f0f;
  v = (v | (v << 2)) & 0x33333333;
  v = (v | (v << 1)) & 0x55555555;
  return v;
}

/// `members` in Z order of their boxes' centres (ties by index). CGAL's aggregated join merges
/// its inputs by divide and conquer in the order given: in space order each partial union
/// swallows the edges inside it before the next merge, instead of carrying every edge (and
/// every crossing of the long shadows of a low sun) up to the last merge.
std::vector<std::size_t> spatial_order(const std::vector<Image>& images, std::vector<std::size_t> members) {
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-lo[0], -lo[1]};
  std::vector<std::array<double, 2>> centre(members.size());
  for (std::size_t a = 0; a < members.size(); ++a)
    for (int axis = 0; axis < 2; ++axis) {
      const std::array<double, 4>& box = images[members[a]].box;
      centre[a][axis] = 0.5 * box[axis] + 0.5 * box[axis + 2];
      lo[axis] = std::min(lo[axis], centre[a][axis]);
      hi[axis] = std::max(hi[axis], centre[a][axis]);
    }
  std::vector<std::pair<std::uint32_t, std::size_t>> keyed(members.size());
  for (std::size_t a = 0; a < members.size(); ++a) {
    std::uint32_t cell[2];
    for (int axis = 0; axis < 2; ++axis) {
      const double span = hi[axis] - lo[axis];
      const double t = span > 0 && std::isfinite(span) ? (centre[a][axis] - lo[axis]) / span : 0.0;
      cell[axis] = static_cast<std::uint32_t>(std::clamp(t, 0.0, 1.0) * 65535.0);
    }
    keyed[a] = {spread(cell[0]) | (spread(cell[1]) << 1), members[a]};
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t a = 0; a < members.size(); ++a) members[a] = keyed[a].second;
  return members;
}

using ApproxKernel = exact::Kernel::Approximate_kernel;
using ExactKernel = exact::Kernel::Exact_kernel;

// lazy_point and exact_of reach into CGAL 5.5's lazy representations (Lazy_rep_0 built with
// both values, Lazy_rep::is_lazy and exact_unsafe): checked there; any other CGAL takes the
// public, slower route (the same values).
#if CGAL_VERSION_NR >= 1050500000 && CGAL_VERSION_NR < 1050600000
#define SHADOW_PLANES_LAZY_INTERNALS 1
#else
#define SHADOW_PLANES_LAZY_INTERNALS 0
#endif

#if SHADOW_PLANES_LAZY_INTERNALS
/// The tightest interval of doubles around a rational: a point when it is a double, else the
/// double below and the double above (mpq_get_d truncates toward zero). What CGAL's conversion
/// gives, without its MPFR division.
CGAL::Interval_nt<false> enclosure(const mpq_class& q) {
  const double d = q.get_d();
  const int sign = sgn(q);
  if (mpz_popcount(q.get_den_mpz_t()) == 1 && cmp(q, d) == 0) return {d, d};  // a dyadic rational may be a double
  const double away = std::nextafter(d, sign > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity());
  return sign > 0 ? CGAL::Interval_nt<false>(d, away) : CGAL::Interval_nt<false>(away, d);
}
#endif

/// An exact chart point as a lazy point whose exact value is known from the start (one node,
/// no lazy coordinates): CGAL evaluates it without a DAG, and exact_of reads it back directly.
exact::Point2 lazy_point(const Q2& q) {
#if SHADOW_PLANES_LAZY_INTERNALS
  using PointRep = CGAL::Lazy_rep_0<ApproxKernel::Point_2, ExactKernel::Point_2, exact::Kernel::E2A>;
  return exact::Point2(new PointRep(ApproxKernel::Point_2(enclosure(q[0]), enclosure(q[1])), ExactKernel::Point_2(q[0], q[1])));
#else
  return exact::Point2(exact::FT(q[0]), exact::FT(q[1]));
#endif
}

/// CGAL::exact(p), without std::call_once when the exact value is already known (glibc's
/// pthread_once makes a futex system call every time it runs an initialisation, even an
/// empty one). Only for lazy points that no other thread touches. CGAL 5.5's Lazy keeps its
/// representation private; Handle::for_compact_container is the public way to it.
const ExactKernel::Point_2& exact_of(const exact::Point2& p) {
#if SHADOW_PLANES_LAZY_INTERNALS
  using Rep = CGAL::Lazy_rep<ApproxKernel::Point_2, ExactKernel::Point_2, exact::Kernel::E2A>;
  const auto* rep = static_cast<const Rep*>(static_cast<CGAL::Rep*>(static_cast<const CGAL::Handle&>(p).for_compact_container()));
  return rep->is_lazy() ? CGAL::exact(p) : rep->exact_unsafe();
#else
  return CGAL::exact(p);
#endif
}

/// Twice the signed area of a polygon, exactly, from its vertices' exact rational coordinates
/// (the shoelace; the same value as exact::polygon_area's, without a lazy node per term).
mpq_class exact_twice_area(const exact::Polygon2& polygon) {
  static_assert(std::is_same_v<std::decay_t<decltype(CGAL::exact(std::declval<exact::FT>()))>, mpq_class>,
                "the exact kernel's numbers are GMP rationals");
  const std::size_t n = polygon.size();
  mpq_class twice(0), term;
  for (std::size_t a = 0; a < n; ++a) {
    const auto& p = exact_of(polygon[a]);
    const auto& q = exact_of(polygon[(a + 1) % n]);
    term = p.x() * q.y();
    twice += term;
    term = q.x() * p.y();
    twice -= term;
  }
  return twice;
}

/// exact::area_3d for twice an exact chart area: sqrt(area^2 x scale), the rational rounded to
/// 256 bits before the root (exact::sqrt_to_double), so bit for bit the same double.
double area_3d(const mpq_class& twice_chart_area, const mpq_class& scale_squared) {
  if (sgn(twice_chart_area) == 0) return 0.0;
  const mpq_class squared = twice_chart_area * twice_chart_area * scale_squared / 4;
  return exact::sqrt_mpq_to_double(squared.get_mpq_t());
}

}  // namespace

void unite_tile(const Scene& scene, const Pair& P, const std::vector<Image>& images, const Grid& grid,
                const std::vector<std::size_t>& members, std::size_t tile, TileResult& out) {
  const std::size_t column = tile % grid.columns(), row = tile / grid.columns();
  const std::size_t cell_of[2] = {column, row};
  // The tile's finite bounds: lower[axis] is cut[cell - 1], upper[axis] is cut[cell].
  bool has_lower[2], has_upper[2];
  mpq_class lower[2], upper[2];
  double lower_d[2], upper_d[2];
  for (int axis = 0; axis < 2; ++axis) {
    const std::vector<double>& cuts = grid.cuts[axis];
    const std::size_t cell = cell_of[axis];
    has_lower[axis] = cell > 0;
    has_upper[axis] = cell < cuts.size();
    lower_d[axis] = has_lower[axis] ? cuts[cell - 1] : -std::numeric_limits<double>::infinity();
    upper_d[axis] = has_upper[axis] ? cuts[cell] : std::numeric_limits<double>::infinity();
    if (has_lower[axis]) lower[axis] = cuts[cell - 1];
    if (has_upper[axis]) upper[axis] = cuts[cell];
  }
  std::vector<exact::Polygon2> pieces;
  std::vector<Q2> poly;
  for (std::size_t m : spatial_order(images, members)) {
    const Image& image = images[m];
    poly = image.vertices;
    bool cut = false;
    for (int axis = 0; axis < 2; ++axis) {
      if (image.box[axis] <= lower_d[axis]) cut |= clip_axis(poly, axis, lower[axis], false);
      if (image.box[axis + 2] >= upper_d[axis]) cut |= clip_axis(poly, axis, upper[axis], true);
    }
    if (poly.size() < 3) continue;
    // A cut along an image's edge leaves a flat sliver (or nothing); an image not cut has a
    // positive area.
    if (cut && sgn(twice_area(poly)) <= 0) continue;
    exact::Polygon2 piece;
    for (const Q2& x : poly) piece.push_back(lazy_point(x));
    pieces.push_back(std::move(piece));
  }
  if (pieces.empty()) return;
  exact::PolygonSet2 shadow;
  shadow.join(pieces.begin(), pieces.end());
  std::vector<exact::PolygonWithHoles2> regions;
  shadow.polygons_with_holes(std::back_inserter(regions));
  out.regions = regions.size();

  // Back to 3D on the plane (as given, not turned): x_k = -(c + n_i x_i + n_j x_j) / n_k.
  // Everything below works on the vertices' exact rational coordinates, taken from each lazy
  // point once (CGAL::exact), never on new lazy numbers: each lazy node evaluated exactly costs
  // a std::call_once (and, in glibc, a futex wake system call), and areas, border edges and
  // cells built as lazy expressions were a third of a tile's time.
  const int i = P.i, j = P.j, k = P.k;
  const mpq_class scale_squared = (P.n[0] * P.n[0] + P.n[1] * P.n[1] + P.n[2] * P.n[2]) / (P.n[k] * P.n[k]);
  const bool flipped = scene.planes[P.plane_id].normal[k] < 0;  // the chart sees the plane clockwise
  // A plane normal to axis k (the ground): x_k is one number, -c / n_k, the same double as the
  // general expression gives (0 x_i and 0 x_j add exact zeros, intervals included).
  const bool level = sgn(P.n[i]) == 0 && sgn(P.n[j]) == 0;
  const double level_k = level ? exact::round_mpq_to_double(mpq_class(-P.c / P.n[k]).get_mpq_t()) : 0.0;
  mpq_class chart_area = 0, twice;
  std::vector<exact::Polygon2> cells;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const exact::Polygon2& outer = regions[r].outer_boundary();
    // Edges on the tile's inner borders: where this region may continue in the next tile.
    const std::size_t n = outer.size();
    for (std::size_t a = 0; a < n; ++a) {
      const auto& source = exact_of(outer[a]);
      const auto& target = exact_of(outer[(a + 1) % n]);
      for (int axis = 0; axis < 2; ++axis) {
        const mpq_class& sa = axis == 0 ? source.x() : source.y();
        const mpq_class& ta = axis == 0 ? target.x() : target.y();
        if (sa != ta) continue;  // not parallel to that border
        for (int high = 0; high < 2; ++high) {
          if (!(high ? has_upper[axis] : has_lower[axis]) || sa != (high ? upper[axis] : lower[axis])) continue;
          mpq_class from(axis == 0 ? source.y() : source.x());
          mpq_class to(axis == 0 ? target.y() : target.x());
          if (from > to) std::swap(from, to);
          const std::size_t cut = cell_of[axis] - (high ? 0 : 1);
          out.border.push_back({static_cast<std::size_t>(axis) * 65536 + cut, high == 1, from, to, r});
        }
      }
    }
    // Simple cells, and the region's exact twice area as the sum of theirs (they tile it).
    cells.clear();
    const bool whole = regions[r].number_of_holes() == 0 && !exact::has_repeated_vertex(outer);
    if (!whole) exact::append_simple_cells(regions[r], cells);
    const std::size_t count = whole ? 1 : cells.size();
    for (std::size_t c = 0; c < count; ++c) {
      const exact::Polygon2& cell = whole ? outer : cells[c];
      twice = exact_twice_area(cell);
      chart_area += twice;
      std::vector<glm::dvec3> polygon;
      polygon.reserve(cell.size());
      for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
        glm::dvec3 x;
        if (P.sheared) {  // back from the tile frame, exactly, then each coordinate's double
          const auto& e = exact_of(*v);
          const Q2 q = from_frame(P, e.x(), e.y());
          x[i] = exact::round_mpq_to_double(q[0].get_mpq_t());
          x[j] = exact::round_mpq_to_double(q[1].get_mpq_t());
          x[k] = level ? level_k : exact::round_mpq_to_double(mpq_class(-(P.c + P.n[i] * q[0] + P.n[j] * q[1]) / P.n[k]).get_mpq_t());
          polygon.push_back(x);
          continue;
        }
        // Each coordinate the double nearest to its exact value (CGAL::to_double would give the
        // midpoint of whatever interval the lazy number holds at that moment).
        const auto& e = exact_of(*v);
        x[i] = exact::round_mpq_to_double(e.x().get_mpq_t());
        x[j] = exact::round_mpq_to_double(e.y().get_mpq_t());
        x[k] = level ? level_k : exact::round_mpq_to_double(mpq_class(-(P.c + P.n[i] * e.x() + P.n[j] * e.y()) / P.n[k]).get_mpq_t());
        polygon.push_back(x);
      }
      if (flipped == (sgn(twice) > 0)) std::reverse(polygon.begin(), polygon.end());
      out.polygons.push_back(std::move(polygon));
      out.region_id.push_back(r);
      out.polygon_area.push_back(area_3d(twice, scale_squared));
    }
  }
  out.chart_area = chart_area / 2;
}

namespace {

/// Union-find over the regions of a pair.
struct Components {
  std::vector<std::size_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
  std::size_t find(std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the first region
  }
};

}  // namespace

void assemble(const Pair& P, std::vector<TileResult>& tiles, PlaneShadow& out) {
  std::vector<std::size_t> offset(tiles.size() + 1, 0);
  for (std::size_t t = 0; t < tiles.size(); ++t) offset[t + 1] = offset[t] + tiles[t].regions;
  Components components(offset.back());
  std::vector<BorderEdge> border;
  for (std::size_t t = 0; t < tiles.size(); ++t)
    for (BorderEdge& e : tiles[t].border) {
      e.region += offset[t];
      border.push_back(std::move(e));
    }
  std::sort(border.begin(), border.end(), [](const BorderEdge& a, const BorderEdge& b) {
    if (a.line != b.line) return a.line < b.line;
    return cmp(a.from, b.from) < 0;
  });
  // Edges of one side of a line never overlap one another; an edge of the other side that
  // starts before this one ends overlaps it along a stretch of positive length.
  for (std::size_t a = 0; a < border.size(); ++a)
    for (std::size_t b = a + 1; b < border.size() && border[b].line == border[a].line && border[b].from < border[a].to; ++b)
      if (border[b].high != border[a].high) components.join(border[a].region, border[b].region);
  std::vector<std::size_t> number(offset.back(), 0);
  std::size_t regions = 0;
  for (std::size_t r = 0; r < offset.back(); ++r) number[r] = components.find(r) == r ? regions++ : number[components.find(r)];
  mpq_class chart_area = 0;
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    TileResult& tile = tiles[t];
    chart_area += tile.chart_area;
    for (std::size_t c = 0; c < tile.polygons.size(); ++c) {
      out.polygons.push_back(std::move(tile.polygons[c]));
      out.region_id.push_back(number[offset[t] + tile.region_id[c]]);
      out.polygon_area.push_back(tile.polygon_area[c]);
    }
  }
  const exact::FT nk(P.n[P.k]);
  const exact::FT scale_squared = exact::FT(P.n[0] * P.n[0] + P.n[1] * P.n[1] + P.n[2] * P.n[2]) / (nk * nk);
  out.area = exact::area_3d(exact::FT(chart_area), scale_squared);
}

}  // namespace shadow::planes::steps
