// SPDX-License-Identifier: GPL-3.0-or-later
// The steps of the shadows on planes (plane_shadows.cpp), shared by their files: the casters'
// images on a plane's chart (plane_shadows_casts.cpp) and their union by tiles
// (plane_shadows_union.cpp). Internal to planes/.
#pragma once

#include "core/culling.hpp"
#include "core/face_prep.hpp"
#include "planes/plane_shadows.hpp"

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <gmpxx.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace shadow::planes::steps {

using Q4 = std::array<mpq_class, 4>;  // homogeneous point or plane, exact
using Q3 = std::array<mpq_class, 3>;
using Q2 = std::array<mpq_class, 2>;  // a point of the plane's chart (axes i, j)

/// One caster's image on the plane's chart: a convex polygon, counter-clockwise, of positive
/// area. Plain GMP rationals (not lazy CGAL numbers), so the tile threads may read it at once.
struct Image {
  std::vector<Q2> vertices;   ///< in the pair's tile frame (Pair::sheared)
  std::array<double, 4> box;  ///< lo_0, lo_1, hi_0, hi_1: doubles that enclose the exact box
};

inline double below(const mpq_class& q) { return std::nextafter(q.get_d(), -std::numeric_limits<double>::infinity()); }
inline double above(const mpq_class& q) { return std::nextafter(q.get_d(), std::numeric_limits<double>::infinity()); }

/// One plane and one light, exactly: the plane turned toward the light, Blinn's matrix, the
/// chart and the window.
struct Pair {
  std::size_t plane_id = 0, light_id = 0;
  double window = 0;
  bool casts = false;  ///< false when the light lies in the plane (or shines along it)
  bool point = false;
  Q3 n;                ///< the plane's normal as given (not turned)
  mpq_class c;
  Q4 p, l;             ///< the plane turned toward the light; the light (x, 1) or (d, 0)
  mpq_class pl;        ///< p . l > 0
  std::array<Q4, 4> M;
  int k = 2, i = 0, j = 1;
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  std::array<mpq_class, 4> bound;  ///< lo[0], hi[0], lo[1], hi[1] exactly
  std::array<Q4, 4> sides;         ///< the prism or pyramid over the window
  Q4 level;                        ///< p.l - p.x >= 0 (point lights)
  std::array<bool, 3> p_nonzero{};  ///< which of p's first three coefficients are not zero
  std::array<mpq_class, 2> ratio;   ///< l_i / p.l and l_j / p.l (directional lights)
  glm::dvec3 normal{0.0}, point_on{0.0};  ///< the plane as given, for the double filter
  double turn = 1;                        ///< -1 when p is the plane turned around
  /// The tile frame: images are united in coordinates (u_0, u_1) of the chart sheared along the
  /// shadows of a directional light, u_lead = x_lead and u_other = x_other - slope x_lead, with
  /// slope = l_other / l_lead (|slope| <= 1, a double taken exactly). Every shadow runs along
  /// u_lead there (to within the slope's rounding), so that tiles cut along u_other are strips
  /// that a low sun's long shadows seldom cross, and the cuts stay lines of one exact double
  /// coordinate (what keeps CGAL's filters deciding points on them). A shear has determinant 1:
  /// areas and orientations are the chart's. Point lights (shadows in every direction) and a
  /// light within about 6 degrees of the chart's axis k keep the chart (sheared false).
  bool sheared = false;
  int lead = 0;
  mpq_class slope = 0;
};

/// What casts: a face (its convex pieces) or a closed convex solid, in the order of the faces.
struct Unit {
  int solid = -1;  ///< index into the solids, or -1 for a face on its own
  std::size_t face = 0;
};

/// The tile grid of a pair: inner cuts along its tile frame's two axes (Pair::sheared; infinite
/// outer bounds).
struct Grid {
  std::array<std::vector<double>, 2> cuts;  ///< strictly increasing, finite
  [[nodiscard]] std::size_t columns() const { return cuts[0].size() + 1; }
  [[nodiscard]] std::size_t rows() const { return cuts[1].size() + 1; }
  [[nodiscard]] std::size_t tiles() const { return columns() * rows(); }
};

/// An edge of a tile's region lying on one of the tile's inner borders.
struct BorderEdge {
  std::size_t line = 0;  ///< which cut: axis * 65536 + cut index
  bool high = false;     ///< the edge lies on the tile's upper border along that axis
  mpq_class from, to;    ///< its extent along the other axis, from < to
  std::size_t region = 0;  ///< the region, numbered within the pair (tile offsets added later)
};

/// What one tile of one pair gives: polygons in 3D, exact chart area, edges on its borders.
struct TileResult {
  std::vector<std::vector<glm::dvec3>> polygons;
  std::vector<std::size_t> region_id;  ///< within the tile
  std::vector<double> polygon_area;
  std::size_t regions = 0;
  mpq_class chart_area = 0;
  std::vector<BorderEdge> border;
};

/// The same clip in the chart, to the axis bound x_c >= m (upper: x_c <= m). The crossing gets m
/// exactly in coordinate c. Returns whether anything was cut away.
bool clip_axis(std::vector<Q2>& poly, int c, const mpq_class& m, bool upper);

/// Twice the signed area of a chart polygon (counter-clockwise positive).
mpq_class twice_area(const std::vector<Q2>& poly);

/// The plane turned toward the light, Blinn's matrix, the chart, the window and the tile frame
/// of one plane and one light.
Pair make_pair(const Scene& scene, std::size_t plane_id, std::size_t light_id, const core::SceneFrame& frame,
               double window, bool shear);

/// A tile-frame point back to the chart.
Q2 from_frame(const Pair& P, const mpq_class& u0, const mpq_class& u1);

/// The casts of units [first, last) for one pair, in unit order.
void cast_units(const Scene& scene, const std::vector<core::FacePrep>& prep, const std::vector<core::ConvexSolid>& solids,
                const std::vector<std::vector<std::size_t>>& solid_faces, const std::vector<Unit>& units, std::size_t first,
                std::size_t last, const Pair& P, std::vector<Image>& out, bool& reaches);

/// Cuts at quantiles of the images' centres along the tile frame's axes, so that tiles hold
/// similar numbers of images (about images / per_tile tiles), and tiles at least
/// Tiling::tile_over_image times as wide as the median image along each axis (an image cut into
/// many pieces costs more than the tiles save): an axis along which images are long (u_lead of a
/// sheared frame under a low sun) gets fewer cuts and the other more. Depends on the images
/// only, never on the thread count.
Grid make_grid(const std::vector<Image>& images, const Tiling& tiling);

/// Unites the images of one tile (clipped to it) and writes its regions back onto the plane.
void unite_tile(const Scene& scene, const Pair& P, const std::vector<Image>& images, const Grid& grid,
                const std::vector<std::size_t>& members, std::size_t tile, TileResult& out);

/// The tiles' results, in tile order, as one PlaneShadow: regions that share a stretch of
/// border (not a mere point) are one region, as the untiled union would have made them.
void assemble(const Pair& P, std::vector<TileResult>& tiles, PlaneShadow& out);

}  // namespace shadow::planes::steps
