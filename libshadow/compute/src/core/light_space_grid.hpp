// SPDX-License-Identifier: GPL-3.0-or-later
// The light-space grid: the faces' boxes in the plane orthogonal to a directional light, in
// cells, so that a receiver's query meets only the faces whose boxes overlap its own, and, with a
// depth, only those reaching nearer the light than it (core/culling.hpp's CasterCandidates).
#pragma once

#include "core/cull_scene.hpp"
#include "core/face_prep.hpp"
#include "core/solid_outlines.hpp"
#include "geometry/unit_vector.hpp"
#include "runtime/parallel.hpp"
#include "runtime/uninit_vector.hpp"

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
#include <vector>

namespace shadow::core {

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
    d_ = d;
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
    runtime::UninitVector<double> reach(item_faces_.size());  // by slot: each face's reach
    // Boxes by blocks of faces; each block's union, then the blocks' (min and max: exact, so
    // the same box in any order).
    constexpr std::size_t kBlock = 8192;
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<Box> block_box(blocks);
    std::vector<char> block_any(blocks, 0);
    runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
      for (std::size_t f = begin; f < end; ++f) {
        if (prep[f].degenerate) continue;
        const Box& box = boxes_[slot_[f]] = box_of(scene, scene.faces[f], reach[slot_[f]]);
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
    // Each item's box: its faces' in increasing order (an item's faces are); its reach, the
    // largest of theirs.
    std::vector<Box> item_box(items);
    item_reach_.resize(items);
    for (std::size_t i = 0; i < items; ++i) {
      item_box[i] = boxes_[item_start_[i]];
      item_reach_[i] = reach[item_start_[i]];
      for (std::uint32_t k = item_start_[i] + 1; k < item_start_[i + 1]; ++k) {
        item_box[i] = merge(item_box[i], boxes_[k]);
        item_reach_[i] = std::max(item_reach_[i], reach[k]);
      }
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
    std::vector<double>().swap(item_reach_);  // (in the entries now)
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
  ///
  /// With `min_depth` (depth() of points, less the caller's room for its rounding), an item whose
  /// reach is below it is skipped whole as well: none of its points is as near the light as any
  /// point the caller asks about, so none lies between such a point and the light.
  template <class Visit, class KeepItem>
  void query(std::size_t face, Visit&& visit, KeepItem&& keep_item, std::uint32_t skip_item = kNoItem,
             double min_depth = std::numeric_limits<double>::lowest()) const {
    query_box(face_box(face), visit, keep_item, skip_item, min_depth);
  }

  /// Finds the outlines of `solids` (the scene's convex solids, as `solid_of` numbers them) seen
  /// from this grid's light, on `threads` threads, for both engines' casts of convex solids
  /// (outlines()).
  void find_outlines(const std::vector<ConvexSolid>& solids, unsigned threads = 1) {
    outlines_.emplace(solids, u_, v_, threads);  // (u_ x v_ = d_)
  }
  /// The outlines find_outlines() found, or null before it.
  [[nodiscard]] const SolidOutlines* outlines() const { return outlines_ ? &*outlines_ : nullptr; }

  /// How far towards the light a local-frame point lies (d . p, d the unit direction to it).
  [[nodiscard]] double depth(const glm::dvec3& p) const { return glm::dot(d_, p); }

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

  /// Calls visit(first face of the item) for each item whose light-space box contains `face`'s
  /// own and that reaches `min_depth` (as query's), in the order of the entries of the one cell
  /// that holds the centre of `face`'s box (an item containing the box is in every cell the box
  /// meets), until visit returns true. These are the only items whose shadow can cover the whole
  /// face; the caller decides whether one does. A filter only: no margin is needed.
  template <class Visit>
  void query_containing(std::size_t face, double min_depth, Visit&& visit) const {
    if (slot_[face] == kNoItem) return;
    const Box& b = boxes_[slot_[face]];
    const double cu = 0.5 * (b[0] + b[2]), cv = 0.5 * (b[1] + b[3]);
    if (!std::isfinite(cu) || !std::isfinite(cv)) return;
    const std::size_t c = cells_.cell_of(cu, cv);
    for (std::uint32_t e = start_[c]; e < start_[c + 1]; ++e) {
      const Entry& entry = entries_[e];
      if (entry.reach < min_depth) break;  // (the cell's entries by reach: the rest lie behind)
      const Box& o = entry.box;
      if ((int{o[0] <= b[0]} & int{o[1] <= b[1]} & int{b[2] <= o[2]} & int{b[3] <= o[3]}) == 0) continue;
      if (visit(static_cast<std::size_t>(item_faces_[entry.slots_begin]))) return;
    }
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
                  KeepItem&& keep_item, std::uint32_t skip_item = kNoItem,
                  double min_depth = std::numeric_limits<double>::lowest()) const {
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
    query_box(b, visit, keep_item, skip_item, min_depth);
  }

 private:
  template <class Visit, class KeepItem>
  void query_box(const std::array<double, 4>& b, Visit&& visit, KeepItem&& keep_item,
                 std::uint32_t skip_item = kNoItem, double min_depth = std::numeric_limits<double>::lowest()) const {
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
          // The cell's entries by reach, farthest first: the rest of them lie behind.
          if (entry.reach < min_depth) break;
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
    double reach;  ///< its item's reach (box_of)
    std::uint32_t first;
    std::uint32_t item;
    std::uint32_t slots_begin, slots_end;
  };
  static Box merge(const Box& a, const Box& b) {
    return {std::min(a[0], b[0]), std::min(a[1], b[1]), std::max(a[2], b[2]), std::max(a[3], b[3])};
  }
  /// A face's light-space box, and its reach: an upper bound on d . p over its points as the
  /// exact engine sees them (its vertices, moved by up to its slack), with room for rounding.
  Box box_of(const CullScene& scene, const CullFace& face, double& reach) const {
    Box b{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
    double w = std::numeric_limits<double>::lowest();
    for (std::size_t k = face.first; k < face.first + face.count; ++k) {
      const double u = glm::dot(u_, scene.vertices[k]), v = glm::dot(v_, scene.vertices[k]);
      b = {std::min(b[0], u), std::min(b[1], v), std::max(b[2], u), std::max(b[3], v)};
      w = std::max(w, glm::dot(d_, scene.vertices[k]));
    }
    reach = w + face.slack + margin_of(scene);
    return {b[0] - face.slack, b[1] - face.slack, b[2] + face.slack, b[3] + face.slack};
  }
  /// Room for the rounding of depths d . p in the local frame (|p| within the diameter; the
  /// unit vector and the dot product within a few ulps): far above it.
  static double margin_of(const CullScene& scene) { return 1e-9 * scene.diameter; }
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
  /// The cells' compressed rows of items (`start_`, `entries_`: each cell's items by reach
  /// (sort_cells_by_reach), each entry with its item's box) and `home_`. From kParallelCellItems items on, on
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
      sort_cells_by_reach(threads);
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
    sort_cells_by_reach(threads);
  }

  /// Item i's entry in a cell, with its box `box`.
  Entry make_entry(std::size_t i, const Box& box) const {
    return {box, item_reach_[i], first_cell(box), static_cast<std::uint32_t>(i), item_start_[i], item_start_[i + 1]};
  }

  /// Each cell's entries by reach, the farthest towards the light first (then by item), so that
  /// a query with a depth stops at the first entry that cannot reach it.
  void sort_cells_by_reach(unsigned threads) {
    const std::size_t cells = cells_.cells();
    auto sort_cell = [&](std::size_t c) {
      if (start_[c + 1] - start_[c] < 2) return;
      std::sort(entries_.begin() + start_[c], entries_.begin() + start_[c + 1], [](const Entry& a, const Entry& b) {
        return a.reach != b.reach ? a.reach > b.reach : a.item < b.item;
      });
    };
    if (threads <= 1 || entries_.size() < kParallelCellItems) {
      for (std::size_t c = 0; c < cells; ++c) sort_cell(c);
      return;
    }
    runtime::parallel_for_blocks(cells, 1024, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t c = begin; c < end; ++c) sort_cell(c);
    });
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
  glm::dvec3 d_{0.0};  ///< the unit direction to the light: depth d . p grows towards it
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
  std::vector<double> item_reach_;  ///< each item's reach (box_of), while the entries are made
  const std::vector<LocalBounds>* item_bounds_ = nullptr;  ///< each item's local box (the constructor's)
  std::vector<std::uint32_t> home_;  ///< per cell: the faces whose box's lower corner is in it
  std::optional<SolidOutlines> outlines_;  ///< the convex solids' outlines (find_outlines)
};

}  // namespace shadow::core
