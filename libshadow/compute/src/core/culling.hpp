// SPDX-License-Identifier: GPL-3.0-or-later
// Culling in double precision: which faces can possibly shadow a receiver. Every test is
// conservative: it rejects a face only when it is certainly, by a margin far above rounding
// error, outside the receiver's slab, prism or pyramid. Whatever passes is decided exactly.
#pragma once

#include "geometry/box_sides.hpp"
#include "geometry/unit_vector.hpp"
#include "core/face_prep.hpp"
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
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow::core {

/// A face in a local frame (scene centre subtracted) with a unit normal, for culling. Plain
/// data without defaults: make_cull_scene sets every field of every face on the thread of its
/// block, so that a million faces' 64 MB are not first written (zeroed) on one thread before.
struct CullFace {
  std::size_t first, count;  ///< range in CullScene::vertices
  glm::dvec3 normal;         ///< unit normal (front side); 0 for a degenerate face
  /// Rigorous bound on |normal - the exact unit Newell normal| (up to 2: direction unknown).
  /// Large for thin faces, whose rounded edge vectors lose the normal's direction.
  double normal_error;
  double offset;  ///< plane: normal . p + offset = 0 (local frame)
  /// How far the exact engine may move a vertex of this face: faces that are planar only within
  /// tolerance are lifted onto their exact plane; culling must allow for it. 0 if exactly planar.
  double slack;
};

/// Whether the face's normal, times `outward` (+1 its front, -1 its back), certainly points away
/// from `to_light` (a unit vector): the normal's direction is known within normal_error, and the
/// two unit vectors' rounding and dot product are within 16 eps. (False for a degenerate face,
/// whose error is 2.)
inline bool certainly_turned_away(const CullFace& face, const glm::dvec3& to_light, double outward = 1.0) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  return outward * glm::dot(face.normal, to_light) < -(face.normal_error + 16 * eps);
}

struct CullScene {
  glm::dvec3 origin{0.0};
  double diameter = 1.0;
  /// The faces' vertices in the local frame, and the faces. Filled on every thread by
  /// make_cull_scene (UninitVector: their pages first touched there).
  runtime::UninitVector<glm::dvec3> vertices;
  runtime::UninitVector<CullFace> faces;
  /// Per face, when some face is on a closed solid that is not convex (else empty): +1 when its
  /// normal points out of the solid, -1 when into it, +2 and -2 the same on a solid closed by
  /// horizontal caps facing down (walls and roofs without a floor: valid under a light above
  /// the horizon only), 0 when it is on none (exact::find_convex_solids' closed_outward). Under
  /// a directional light the solid's faces turned away from it cast nothing that its faces
  /// turned to it do not (ReceiverCuller).
  std::vector<signed char> closed_outward;
};

/// A box in the local frame (CullScene's) around some faces' vertices, with the largest of their
/// slacks: what ReceiverCuller::may_cast_any needs to rule out every one of those faces at once.
struct LocalBounds {
  glm::dvec3 lo{0.0}, hi{0.0};
  double slack = 0;
};

/// Each face's LocalBounds (a degenerate face's too: it is never asked for), on `threads`
/// threads. They do not depend on the light: a series makes them once for all its suns.
std::vector<LocalBounds> face_bounds(const CullScene& scene, unsigned threads = 1);

/// An affine function on local-frame points with the margin below which its sign is unsure.
struct DoubleAffine {
  glm::dvec3 a{0.0};
  double b = 0.0;
  double tolerance = 0.0;
  [[nodiscard]] double operator()(const glm::dvec3& p) const { return glm::dot(a, p) + b; }
};

/// A grid over the faces' bounding boxes in light space (the plane orthogonal to a directional
/// light): faces whose boxes do not overlap cannot shadow each other. Two uniform divisions of
/// the same box: the query cells, sized like the items, hold the items; the counting cells,
/// square, hold each face's count for count().
class LightSpaceGrid {
 public:
  /// With `solid_of` (the convex solid of each face, -1 for none), the faces of one convex solid
  /// are one entry of the grid: a query then meets a box once instead of each of its faces in
  /// each cell they share, and tests the faces' own boxes only for the solids it overlaps. The
  /// faces reported are the same either way.
  ///
  /// The faces' light-space boxes are computed on `threads` threads (0 counts as 1; the grid does
  /// not depend on it).
  ///
  /// With `item_bounds` (item_bounds() of the same scene, preparation and solids, which no light
  /// changes: a series makes them once for all its suns' grids), query() with an item test
  /// skips the items that test rules out whole. The grid keeps a pointer to them.
  LightSpaceGrid(const CullScene& scene, const std::vector<FacePrep>& prep, glm::dvec3 to_light,
                 const std::vector<int>* solid_of = nullptr, unsigned threads = 1,
                 const std::vector<LocalBounds>* item_bounds = nullptr)
      : solid_items_(solid_of) {
    const glm::dvec3 d = geometry::unit(to_light);
    const glm::dvec3 helper = std::abs(d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    u_ = glm::normalize(glm::cross(d, helper));
    v_ = glm::cross(d, u_);
    const std::size_t n = scene.faces.size();
    // Items: a convex solid's faces together, every other face alone (faces in increasing
    // order). Their faces' slots: each item's faces one after another (item_faces_), where the
    // faces' boxes are kept (boxes_), so that a query reads an item's boxes in a row.
    std::vector<std::uint32_t> item_of;
    const std::size_t items = number_items(prep, solid_of, item_of);
    if (item_bounds && item_bounds->size() != items)
      throw std::logic_error("LightSpaceGrid: item bounds made for another scene or solids");
    item_bounds_ = item_bounds;
    item_start_.assign(items + 1, 0);
    for (std::size_t f = 0; f < n; ++f)
      if (!prep[f].degenerate) ++item_start_[item_of[f] + 1];
    for (std::size_t i = 1; i < item_start_.size(); ++i) item_start_[i] += item_start_[i - 1];
    item_faces_.resize(item_start_.back());
    slot_.assign(n, kNoItem);
    {
      std::vector<std::uint32_t> fill(item_start_.begin(), item_start_.end() - 1);
      for (std::size_t f = 0; f < n; ++f) {
        if (prep[f].degenerate) continue;
        slot_[f] = fill[item_of[f]]++;
        item_faces_[slot_[f]] = static_cast<std::uint32_t>(f);
      }
    }
    item_of_ = std::move(item_of);
    boxes_.resize(item_faces_.size());  // uninitialised: each written below, on the thread of its block
    // Boxes by blocks of faces; each block's union, then the blocks' (min and max: exact, so
    // the same box in any order).
    constexpr std::size_t kBlock = 8192;
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<Box> block_box(blocks);
    std::vector<char> block_any(blocks, 0);
    runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
      for (std::size_t f = begin; f < end; ++f) {
        if (prep[f].degenerate) continue;
        const Box& box = boxes_[slot_[f]] = box_of(scene, scene.faces[f]);
        block_box[b] = block_any[b] ? merge(block_box[b], box) : box;
        block_any[b] = 1;
      }
    });
    Box all{};
    bool any = false;
    for (std::size_t b = 0; b < blocks; ++b) {
      if (!block_any[b]) continue;
      all = any ? merge(all, block_box[b]) : block_box[b];
      any = true;
    }
    margin_ = 1e-9 * scene.diameter;
    origin_ = {all[0] - margin_, all[1] - margin_};
    const double width = std::max(all[2] - all[0], 0.0) + 2 * margin_;
    const double height = std::max(all[3] - all[1], 0.0) + 2 * margin_;
    // The counting cells (count(), home_): about one per four faces, square. count() decides
    // which receivers are cut into tiles, so their layout stays as it was measured.
    const double cells_wanted = std::max<double>(1.0, 0.25 * static_cast<double>(n));
    const double square = std::max(std::sqrt(width * height / cells_wanted), 1e-300);
    counting_ = CellLayout(origin_, width, height, square, square);
    // Each item's box: its faces' in increasing order (an item's faces are).
    std::vector<Box> item_box(items);
    for (std::size_t i = 0; i < items; ++i) {
      item_box[i] = boxes_[item_start_[i]];
      for (std::uint32_t k = item_start_[i] + 1; k < item_start_[i + 1]; ++k) item_box[i] = merge(item_box[i], boxes_[k]);
    }
    // The query cells: as large as a typical item across each axis (the median of the items'
    // extents), and never smaller than the counting cells. A query of a box w x h over cells
    // cu x cv visits about (w + cu)(h + cv)(cu + w')(cv + h') / (cu cv) entries for items of w' x
    // h', least near cu = sqrt(w w'): about an item's size, the queries being items' faces. A low
    // sun flattens the light-space box, so square cells of a fourth of the faces came out a
    // quarter of a building wide, and each building was an entry in some twenty of them. At most
    // 16 counting cells merge into one, so that a few large items do not make one cell of all.
    double cu = square, cv = square;
    if (!item_box.empty()) {
      std::vector<double> extent(item_box.size());
      for (int axis = 0; axis < 2; ++axis) {
        for (std::size_t i = 0; i < item_box.size(); ++i) extent[i] = item_box[i][2 + axis] - item_box[i][axis];
        std::nth_element(extent.begin(), extent.begin() + static_cast<std::ptrdiff_t>(extent.size() / 2), extent.end());
        const double median = extent[extent.size() / 2];
        (axis == 0 ? cu : cv) = std::clamp(median, square, 16 * square);
      }
      if (cu * cv > 16 * square * square) {  // larger than 16 counting cells: shrink to that area
        const double f = std::sqrt(16 * square * square / (cu * cv));
        cu *= f;  // (each stays at least `square`: the other is at most 16 square)
        cv *= f;
      }
    }
    cells_ = CellLayout(origin_, width, height, cu, cv);
    fill_cells(item_box, threads);
  }

  /// Each item's local box (the box of its faces' vertices, their largest slack), in the grid's
  /// item order, for the constructor's `item_bounds`.
  static std::vector<LocalBounds> item_bounds(const CullScene& scene, const std::vector<FacePrep>& prep,
                                              const std::vector<int>* solid_of, unsigned threads = 1) {
    const std::vector<LocalBounds> faces = face_bounds(scene, threads);
    std::vector<std::uint32_t> item_of;
    std::vector<LocalBounds> items(number_items(prep, solid_of, item_of));
    std::vector<char> seen(items.size(), 0);
    for (std::size_t f = 0; f < prep.size(); ++f) {
      if (prep[f].degenerate) continue;
      LocalBounds& b = items[item_of[f]];
      const LocalBounds& o = faces[f];
      if (!seen[item_of[f]]) {
        b = o;
        seen[item_of[f]] = 1;
        continue;
      }
      b.lo = glm::min(b.lo, o.lo);  // (min and max: exact, in any order)
      b.hi = glm::max(b.hi, o.hi);
      b.slack = std::max(b.slack, o.slack);
    }
    return items;
  }

  /// The `solid_of` whose convex solids are items (null: every face its own item): a query visits
  /// the faces of each of those solids one after another, in increasing order. Only compared,
  /// never read.
  [[nodiscard]] const std::vector<int>* solid_items() const { return solid_items_; }

  /// Calls visit(face) once for every face whose light-space box overlaps `face`'s.
  ///
  /// `visit` may return bool instead of void: true then means that it drops every later face of
  /// the same item (a convex solid already listed), which the query then neither tests nor visits.
  template <class Visit>
  void query(std::size_t face, Visit&& visit) const {
    query_box(face_box(face), visit, [](const LocalBounds&) { return true; });
  }

  /// The same, but an item (a convex solid, or a face alone) for which keep_item(its local
  /// bounds) is false is skipped whole, its faces neither tested nor visited: keep_item must
  /// return false only where `visit` would drop every one of its faces anyway. Without item
  /// bounds (the constructor's `item_bounds`) every item is kept. Item `skip_item` (item_of();
  /// kNoItem: none) is skipped whole too, with or without bounds: `visit` must drop every one of
  /// its faces.
  template <class Visit, class KeepItem>
  void query(std::size_t face, Visit&& visit, KeepItem&& keep_item, std::uint32_t skip_item = kNoItem) const {
    query_box(face_box(face), visit, keep_item, skip_item);
  }

  static constexpr std::uint32_t kNoItem = UINT32_MAX;
  /// The item that holds `face` (all of its convex solid's faces, with `solid_of`), kNoItem for
  /// a degenerate face.
  [[nodiscard]] std::uint32_t item_of(std::size_t face) const { return item_of_[face]; }

  /// Whether query(receiver) reports face q (a face the grid holds): their light-space boxes
  /// overlap by the margin, the test query() makes of each face of an item it meets.
  [[nodiscard]] bool reports(std::size_t receiver, std::size_t q) const {
    const Box& b = face_box(receiver);
    const Box& fb = face_box(q);
    return fb[0] <= b[2] + margin_ && b[0] <= fb[2] + margin_ && fb[1] <= b[3] + margin_ && b[1] <= fb[3] + margin_;
  }

  /// About how many faces query(face) meets, in O(cells): the faces whose light-space box has its
  /// lower corner in a counting cell that `face`'s box touches (each face counted once). The
  /// counting cells are the grid's first layout (square, one per four faces), kept when the query
  /// cells were sized like the items: this count decides which receivers are cut into tiles.
  [[nodiscard]] std::size_t count(std::size_t face) const {
    std::size_t n = 0;
    for_cells(counting_, face_box(face), [&](std::size_t c) { n += home_[c]; });
    return n;
  }

  /// The same for a part of a face (a tile): the light-space box of `points` (local frame)
  /// widened by `slack` on every side, intersected with `face`'s own box.
  template <class Visit>
  void query_part(std::size_t face, const std::vector<glm::dvec3>& points, double slack, Visit&& visit) const {
    query_part(face, points, slack, visit, [](const LocalBounds&) { return true; });
  }
  /// query_part with an item test, as query's.
  template <class Visit, class KeepItem>
  void query_part(std::size_t face, const std::vector<glm::dvec3>& points, double slack, Visit&& visit,
                  KeepItem&& keep_item, std::uint32_t skip_item = kNoItem) const {
    Box b{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
    for (const glm::dvec3& p : points) {
      const double u = glm::dot(u_, p), v = glm::dot(v_, p);
      b = {std::min(b[0], u), std::min(b[1], v), std::max(b[2], u), std::max(b[3], v)};
    }
    const Box& f = face_box(face);
    b = {std::max(b[0] - slack, f[0]), std::max(b[1] - slack, f[1]), std::min(b[2] + slack, f[2]),
         std::min(b[3] + slack, f[3])};
    if (!(b[0] <= b[2]) || !(b[1] <= b[3])) b = f;  // (rounding: fall back to the whole face)
    query_box(b, visit, keep_item, skip_item);
  }

 private:
  template <class Visit, class KeepItem>
  void query_box(const std::array<double, 4>& b, Visit&& visit, KeepItem&& keep_item,
                 std::uint32_t skip_item = kNoItem) const {
    const LocalBounds* item_bounds = item_bounds_ ? item_bounds_->data() : nullptr;
    // Each overlapping face is reported once, in one cell both boxes cover (below), instead of
    // once per shared cell: most faces span several cells, and their repeats were most of a
    // query's visits.
    const int u0 = cells_.index_u(b[0] - margin_), u1 = cells_.index_u(b[2] + margin_);
    const int v0 = cells_.index_v(b[1] - margin_), v1 = cells_.index_v(b[3] + margin_);
    // The overlap tests are the same comparisons of the same sums as ever, combined with `&`
    // instead of `&&`: one branch per entry or face instead of four. Their outcomes are data,
    // not patterns, so every branch was a likely misprediction; those were most of a query's
    // time (perf: the samples on the branches after the comparisons).
    const double b2 = b[2] + margin_, b3 = b[3] + margin_;
    auto overlaps = [&](const Box& o) -> int {
      return int{o[0] <= b2} & int{b[0] <= o[2] + margin_} & int{o[1] <= b3} & int{b[1] <= o[3] + margin_};
    };
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        const std::size_t c = static_cast<std::size_t>(v) * cells_.nu + u;
        for (std::uint32_t e = start_[c]; e < start_[c + 1]; ++e) {
          // An item is taken only in the first cell (lowest u, lowest v) that both the query
          // and the item cover: the item is registered in cells [iu, ...] x [iv, ...] and the
          // query visits [u0, u1] x [v0, v1]; with the boxes overlapping by the margin, iu <= u1
          // and u0 <= the item's last cell (and so for v), so that cell is visited and holds
          // the item. Integers only: no floor and division per entry, as a corner's cell took.
          const Entry& entry = entries_[e];
          const int home = int{std::max(u0, static_cast<int>(entry.first & 0xffff)) == u} &
                           int{std::max(v0, static_cast<int>(entry.first >> 16)) == v};
          // The entry's own copy of its item's box: read in cell order, no jump per entry.
          if (!(overlaps(entry.box) & home)) continue;
          // The caller's own item (the receiver's solid, none of whose faces it takes): its
          // faces overlap the receiver's box and were each tested and visited to be dropped.
          if (entry.item == skip_item) continue;
          // The item's faces' boxes, in a row from its first slot (in the entry: no look-up
          // first), are fetched while its bounds are tested.
          __builtin_prefetch(&boxes_[entry.slots_begin]);
          // An item the caller rules out whole (a solid behind the receiver's plane): none of
          // its faces' boxes and vertices are read (a cache miss each).
          if (item_bounds && !keep_item(item_bounds[entry.item])) continue;
          // The item's faces whose own boxes overlap, until `visit` has done with the item.
          for (std::uint32_t k = entry.slots_begin; k < entry.slots_end; ++k) {
            if (!overlaps(boxes_[k])) continue;
            const std::uint32_t f = item_faces_[k];
            if constexpr (std::is_same_v<decltype(visit(f)), bool>) {
              if (visit(f)) break;
            } else {
              visit(f);
            }
          }
        }
      }
  }

  /// The grid's items: a convex solid's faces together (by `solid_of`), every other face alone,
  /// numbered in the order of their first faces; degenerate faces are in none. Fills item_of
  /// (per face) and returns the number of items.
  static std::size_t number_items(const std::vector<FacePrep>& prep, const std::vector<int>* solid_of,
                                  std::vector<std::uint32_t>& item_of) {
    const std::size_t n = prep.size();
    item_of.assign(n, kNoItem);
    std::vector<std::uint32_t> item_of_solid;
    std::size_t items = 0;
    for (std::size_t f = 0; f < n; ++f) {
      if (prep[f].degenerate) continue;
      const int s = solid_of ? (*solid_of)[f] : -1;
      if (s >= 0) {
        if (item_of_solid.size() <= static_cast<std::size_t>(s)) item_of_solid.resize(static_cast<std::size_t>(s) + 1, UINT32_MAX);
        if (item_of_solid[static_cast<std::size_t>(s)] == UINT32_MAX) item_of_solid[static_cast<std::size_t>(s)] = static_cast<std::uint32_t>(items++);
        item_of[f] = item_of_solid[static_cast<std::size_t>(s)];
      } else {
        item_of[f] = static_cast<std::uint32_t>(items++);
      }
    }
    return items;
  }

  static int cell_index(double x, double origin, double size, int count) {
    return std::clamp(static_cast<int>(std::floor((x - origin) / size)), 0, count - 1);
  }

  using Box = std::array<double, 4>;  // umin, vmin, umax, vmax
  /// An item in a cell: its box, its first cell (first_cell), and its faces' slots.
  struct Entry {
    Box box;
    std::uint32_t first;
    std::uint32_t item;
    std::uint32_t slots_begin, slots_end;
  };
  static Box merge(const Box& a, const Box& b) {
    return {std::min(a[0], b[0]), std::min(a[1], b[1]), std::max(a[2], b[2]), std::max(a[3], b[3])};
  }
  Box box_of(const CullScene& scene, const CullFace& face) const {
    Box b{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
    for (std::size_t k = face.first; k < face.first + face.count; ++k) {
      const double u = glm::dot(u_, scene.vertices[k]), v = glm::dot(v_, scene.vertices[k]);
      b = {std::min(b[0], u), std::min(b[1], v), std::max(b[2], u), std::max(b[3], v)};
    }
    return {b[0] - face.slack, b[1] - face.slack, b[2] + face.slack, b[3] + face.slack};
  }
  /// A division of the light-space box into nu x nv cells of about the sizes asked for.
  struct CellLayout {
    CellLayout() = default;
    CellLayout(std::array<double, 2> from, double width, double height, double size_u, double size_v)
        : origin(from),
          nu(static_cast<int>(std::clamp(std::ceil(width / size_u), 1.0, 2048.0))),
          nv(static_cast<int>(std::clamp(std::ceil(height / size_v), 1.0, 2048.0))) {
      cell_u = width / nu;
      cell_v = height / nv;
    }
    [[nodiscard]] int index_u(double u) const { return cell_index(u, origin[0], cell_u, nu); }
    [[nodiscard]] int index_v(double v) const { return cell_index(v, origin[1], cell_v, nv); }
    [[nodiscard]] std::size_t cells() const { return static_cast<std::size_t>(nu) * nv; }
    /// The cell of a point (a box's lower corner).
    [[nodiscard]] std::size_t cell_of(double u, double v) const {
      const int cu = std::clamp(static_cast<int>(std::floor((u - origin[0]) / cell_u)), 0, nu - 1);
      const int cv = std::clamp(static_cast<int>(std::floor((v - origin[1]) / cell_v)), 0, nv - 1);
      return static_cast<std::size_t>(cv) * nu + cu;
    }
    std::array<double, 2> origin{0, 0};
    double cell_u = 1, cell_v = 1;
    int nu = 1, nv = 1;
  };
  /// The cells' compressed rows of items (`start_`, `entries_`: each cell's items in increasing
  /// order, each entry with its item's box) and `home_`. From kParallelCellItems items on, on
  /// `threads` threads: the items in as many ranges, counted per range and cell, each range's
  /// place in a cell after the ranges before it, so that every row is the one a single pass fills.
  static constexpr std::size_t kParallelCellItems = 4096;
  void fill_cells(const std::vector<Box>& item_box, unsigned threads) {
    const std::size_t items = item_box.size(), n = boxes_.size(), cells = cells_.cells(),
                      counting_cells = counting_.cells();
    // At most 2^24 counters a table (ranges x cells): 64 MiB a table.
    const std::size_t ranges = std::clamp<std::size_t>(
        std::min<std::size_t>(items / kParallelCellItems,
                              (std::size_t{1} << 24) / std::max<std::size_t>(std::max(cells, counting_cells), 1)),
        1,
        std::max(threads, 1u));
    if (ranges == 1) {  // one pass: count, prefix sum, fill
      start_.assign(cells + 1, 0);
      for (std::size_t i = 0; i < items; ++i) for_cells(cells_, item_box[i], [&](std::size_t c) { ++start_[c + 1]; });
      home_.assign(counting_cells, 0);
      for (std::size_t k = 0; k < n; ++k) ++home_[counting_.cell_of(boxes_[k][0], boxes_[k][1])];  // (every slot a face)
      for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
      entries_.resize(start_.back());
      std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
      for (std::size_t i = 0; i < items; ++i) {
        const Entry entry = make_entry(i, item_box[i]);
        for_cells(cells_, item_box[i], [&](std::size_t c) { entries_[fill[c]++] = entry; });
      }
      return;
    }
    auto range_begin = [&](std::size_t r, std::size_t count) { return count * r / ranges; };
    // count[r][c]: range r's items in cell c (then: where range r's next item of cell c goes).
    std::vector<std::vector<std::uint32_t>> count(ranges, std::vector<std::uint32_t>(cells, 0));
    std::vector<std::vector<std::uint32_t>> home(ranges, std::vector<std::uint32_t>(counting_cells, 0));
    runtime::parallel_for(ranges, static_cast<unsigned>(ranges), [&](unsigned, std::size_t r) {
      for (std::size_t i = range_begin(r, items); i < range_begin(r + 1, items); ++i)
        for_cells(cells_, item_box[i], [&](std::size_t c) { ++count[r][c]; });
      for (std::size_t k = range_begin(r, n); k < range_begin(r + 1, n); ++k)
        ++home[r][counting_.cell_of(boxes_[k][0], boxes_[k][1])];
    });
    start_.assign(cells + 1, 0);
    for (std::size_t c = 0; c < cells; ++c) {
      std::uint32_t at = start_[c];
      for (std::size_t r = 0; r < ranges; ++r) {
        const std::uint32_t k = count[r][c];
        count[r][c] = at;
        at += k;
      }
      start_[c + 1] = at;
    }
    home_.assign(counting_cells, 0);
    for (std::size_t c = 0; c < counting_cells; ++c)
      for (std::size_t r = 0; r < ranges; ++r) home_[c] += home[r][c];
    entries_.resize(start_.back());
    runtime::parallel_for(ranges, static_cast<unsigned>(ranges), [&](unsigned, std::size_t r) {
      for (std::size_t i = range_begin(r, items); i < range_begin(r + 1, items); ++i) {
        const Entry entry = make_entry(i, item_box[i]);
        for_cells(cells_, item_box[i], [&](std::size_t c) { entries_[count[r][c]++] = entry; });
      }
    });
  }

  /// Item i's entry in a cell, with its box `box`.
  Entry make_entry(std::size_t i, const Box& box) const {
    return {box, first_cell(box), static_cast<std::uint32_t>(i), item_start_[i], item_start_[i + 1]};
  }

  /// A face's light-space box (a degenerate face's: empty, at 0).
  [[nodiscard]] const Box& face_box(std::size_t face) const {
    static constexpr Box kNone{};
    return slot_[face] == kNoItem ? kNone : boxes_[slot_[face]];
  }

  /// The first cell for_cells(b) visits, as u | v << 16 (nu, nv <= 2048).
  std::uint32_t first_cell(const Box& b) const {
    return static_cast<std::uint32_t>(cells_.index_u(b[0] - margin_)) |
           static_cast<std::uint32_t>(cells_.index_v(b[1] - margin_)) << 16;
  }

  template <class Visit>
  void for_cells(const CellLayout& layout, const Box& b, Visit&& visit) const {
    const int u0 = layout.index_u(b[0] - margin_), u1 = layout.index_u(b[2] + margin_);
    const int v0 = layout.index_v(b[1] - margin_), v1 = layout.index_v(b[3] + margin_);
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) visit(static_cast<std::size_t>(v) * layout.nu + u);
  }

  const std::vector<int>* solid_items_ = nullptr;
  glm::dvec3 u_{0.0}, v_{0.0};
  // The arrays by slot and by entry are filled on every thread: UninitVector, so that their pages
  // are first touched there rather than zeroed on the calling thread before (a million faces:
  // some 70 MB).
  runtime::UninitVector<Box> boxes_;  ///< the faces' boxes, by slot (item_faces_' order)
  std::vector<std::uint32_t> slot_;  ///< each face's slot (kNoItem: degenerate)
  std::array<double, 2> origin_{0, 0};
  double margin_ = 0;
  CellLayout counting_;  ///< home_'s cells, for count()
  CellLayout cells_;     ///< the entries' cells, for queries
  std::vector<std::uint32_t> start_;
  runtime::UninitVector<Entry> entries_;  ///< items, by cell
  std::vector<std::uint32_t> item_start_, item_faces_;  ///< each item's faces (compressed rows)
  std::vector<std::uint32_t> item_of_;  ///< each face's item (kNoItem: degenerate)
  const std::vector<LocalBounds>* item_bounds_ = nullptr;  ///< each item's local box (the constructor's)
  std::vector<std::uint32_t> home_;  ///< per cell: the faces whose box's lower corner is in it
};

/// The conservative double-precision tests of one receiver (front-facing) under one light: its
/// plane and, unless the light grazes it, the four sides of the prism or pyramid over its chart
/// box. Shared by the exact engine and the fast path, so that both see the same candidates.
class ReceiverCuller {
 public:
  ReceiverCuller(const CullScene& cull, const FacePrep& fp, std::size_t face_id, const Light& light)
      : cull_(&cull) {
    const CullFace& cp = cull.faces[face_id];
    const double D = cull.diameter;
    glm::dvec3 lxyz;
    double lw;
    if (light.type == LightType::Point) {
      lxyz = light.position - cull.origin;
      lw = 1.0;
    } else {
      lxyz = geometry::unit(light.to_light);
      lw = 0.0;
      if (!cull.closed_outward.empty() && light.type == LightType::Directional) {  // (never a lamp: it may be inside)
        closed_outward_ = cull.closed_outward.data();
        to_light_ = lxyz;
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
  }

  /// False when may_cast is certainly false for every face whose vertices lie in `b` (with a
  /// slack of at most b.slack): for one of the tests, the box lies wholly outside it, with room
  /// for may_cast's own rounding. Its maximum over the box and may_cast's value at any vertex in
  /// it are each within 4 eps of their exact values relative to the same sum of magnitudes
  /// (three products and the constant), so a gap of 32 eps of that sum covers both.
  [[nodiscard]] bool may_cast_any(const LocalBounds& b) const {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    for (std::size_t t = 0; t < count_; ++t) {
      const DoubleAffine& f = tests_[t];
      double most = f.b, magnitude = std::abs(f.b);
      for (int c = 0; c < 3; ++c) {
        const double low = f.a[c] * b.lo[c], high = f.a[c] * b.hi[c];
        most += std::max(low, high);
        magnitude += std::max(std::abs(low), std::abs(high));
      }
      if (most + 32 * eps * magnitude < -(f.tolerance + length_[t] * b.slack)) return false;
    }
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
  const signed char* closed_outward_ = nullptr;  ///< CullScene::closed_outward under a directional light
  glm::dvec3 to_light_{0.0};
  bool above_caps_ = false;  ///< the light is certainly above every horizontal plane (to_light.z > 0)
  std::array<DoubleAffine, 5> tests_;
  std::array<double, 5> length_{};  ///< |tests_[t].a|
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
    if (grid && tile && tile_scene) {
      // A tile: the light-space box of its corners on the receiver's plane (local frame).
      const CullFace& cf = tile_scene->faces[receiver];
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
      grid->query_part(receiver, corners_, std::isfinite(slack) ? slack : 0.0, consider, keep_item, own_item);
    } else if (grid) {
      grid->query(receiver, consider, keep_item, own_item);
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

 private:
  std::vector<std::uint32_t> solid_seen_;
  std::uint32_t stamp_ = 0;
  std::vector<std::size_t> faces_;
  std::vector<glm::dvec3> corners_;
};

/// The centre and diagonal of the faces' bounding box (origin and 1 for a scene without faces).
struct SceneFrame {
  glm::dvec3 centre{0.0};
  double diagonal = 1.0;
};
/// With `threads` > 1 the box is found by blocks of faces on that many threads, merged in order:
/// the same box (every coordinate, -0.0 as one thread finds it) for any count.
SceneFrame scene_frame(const Scene& scene, unsigned threads = 1);

/// The faces in a local frame (scene centre subtracted), with unit normals; the faces divided
/// among `threads` threads (0 counts as 1; the result does not depend on it).
CullScene make_cull_scene(const Scene& scene, const std::vector<FacePrep>& prep, unsigned threads = 1);

}  // namespace shadow::core
