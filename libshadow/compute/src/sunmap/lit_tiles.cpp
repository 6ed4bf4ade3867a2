// SPDX-License-Identifier: GPL-3.0-or-later
// The tiles an instant may light on a face (lit_tiles.hpp), in doubles but never missing one: a
// tile that a boundary passes through is marked, with a margin of an eighth of a tile and far
// more than the rounding, so rounding cannot miss it, and every other tile lies wholly inside or
// wholly outside the region, which the crossings of its row's centre line tell (the rounded
// boundary differs from the exact one only within marked tiles). The unmarked tiles found
// inside are the ones the region surely covers whole.
#include "sunmap/lit_tiles.hpp"

#include "runtime/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace shadow::sunmap {

std::size_t TileGrid::column(double x) const {
  const double c = std::floor((x - x0) / dx);
  return c <= 0 ? 0 : c >= static_cast<double>(n - 1) ? n - 1 : static_cast<std::size_t>(c);
}

std::size_t TileGrid::row(double y) const {
  const double r = std::floor((y - y0) / dy);
  return r <= 0 ? 0 : r >= static_cast<double>(n - 1) ? n - 1 : static_cast<std::size_t>(r);
}

TileGrid tile_grid(const exact::Polygon2& chart, std::size_t segments, std::size_t instants, double max_bits) {
  TileGrid g;
  if (segments < 16 || chart.size() < 3) return g;
  double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL;
  for (auto v = chart.vertices_begin(); v != chart.vertices_end(); ++v) {
    const auto x = CGAL::to_interval(v->x()), y = CGAL::to_interval(v->y());
    xmin = std::min(xmin, x.first), xmax = std::max(xmax, x.second);
    ymin = std::min(ymin, y.first), ymax = std::max(ymax, y.second);
  }
  if (!(xmax > xmin) || !(ymax > ymin)) return g;
  // About eight times the square root of the segments per side: a tile then holds a fraction
  // of a segment's worth of boundary. The cells that stay undecided longest lie near buildings,
  // in fans of shadow edges from their corners; twice the root (tried first, the tiles then
  // marked with their eight neighbours) left nearly every such cell under a tile some boundary
  // passed near at every instant, so that the tiles decided almost nothing.
  // The masks' bits per instant cutting the face: two masks of whole 64-bit words, and the
  // instant's index.
  const auto bits = [](double side) { return 2.0 * 64.0 * std::ceil(side * side / 64.0) + 64.0; };
  const double count = static_cast<double>(std::max<std::size_t>(instants, 1));
  double side = std::min({std::ceil(8.0 * std::sqrt(static_cast<double>(segments))), 256.0,
                          std::floor(std::sqrt(max_bits / (2.0 * count)))});
  while (side >= 4 && bits(side) * count > max_bits) --side;
  if (side < 4) return g;
  g.n = static_cast<std::size_t>(side);
  g.x0 = xmin;
  g.y0 = ymin;
  g.dx = (xmax - xmin) / static_cast<double>(g.n);
  g.dy = (ymax - ymin) / static_cast<double>(g.n);
  return g;
}

void mark_lit_tiles(const TileGrid& g, const Curve* first, const Curve* last, std::uint64_t* mask,
                    std::uint64_t* whole) {
  std::vector<RoughSegment> rough;
  rough.reserve(static_cast<std::size_t>(last - first));
  for (const Curve* c = first; c != last; ++c) rough.push_back(rough_segment(*c));
  mark_lit_tiles(g, rough.data(), rough.data() + rough.size(), mask, whole);
}

void mark_lit_tiles(const TileGrid& g, const RoughSegment* first, const RoughSegment* last, std::uint64_t* mask,
                    std::uint64_t* whole) {
  const std::size_t count = static_cast<std::size_t>(last - first);
  const std::size_t n = g.n;
  if (n == 0) return;
  std::fill(mask, mask + g.words(), std::uint64_t{0});
  if (whole) std::fill(whole, whole + g.words(), std::uint64_t{0});
  std::vector<char> boundary(n * n, 0);
  auto set = [&](std::size_t t) { mask[t / 64] |= std::uint64_t{1} << (t % 64); };
  // The boundary's tiles: points at most a quarter tile apart (along each axis) along each
  // segment, each marking every tile that meets the box of an eighth of a tile to each side
  // around it, widened by a margin far beyond the rounding of these doubles. Every point of the
  // segment lies within an eighth of a tile of one on each axis, so every tile the segment
  // passes through is marked, and no tile further than about a quarter tile from it.
  const double reach_x = 0.125 * g.dx + 1e-9 * (std::fabs(g.x0) + g.dx * static_cast<double>(n));
  const double reach_y = 0.125 * g.dy + 1e-9 * (std::fabs(g.y0) + g.dy * static_cast<double>(n));
  std::vector<double> xa(count), ya(count), xb(count), yb(count);
  for (std::size_t k = 0; k < count; ++k) {
    const RoughSegment& segment = first[k];
    xa[k] = segment.xa, ya[k] = segment.ya, xb[k] = segment.xb, yb[k] = segment.yb;
    const double span = std::max(std::fabs(xb[k] - xa[k]) / g.dx, std::fabs(yb[k] - ya[k]) / g.dy);
    const std::size_t steps = static_cast<std::size_t>(std::ceil(4.0 * span)) + 1;
    for (std::size_t s = 0; s <= steps; ++s) {
      const double u = static_cast<double>(s) / static_cast<double>(steps);
      const double x = xa[k] + u * (xb[k] - xa[k]), y = ya[k] + u * (yb[k] - ya[k]);
      const std::size_t c0 = g.column(x - reach_x), c1 = g.column(x + reach_x);
      const std::size_t r0 = g.row(y - reach_y), r1 = g.row(y + reach_y);
      for (std::size_t rr = r0; rr <= r1; ++rr)
        for (std::size_t cc = c0; cc <= c1; ++cc) boundary[rr * n + cc] = 1;
    }
  }
  // The other tiles: inside when an odd number of boundary crossings of the row's centre line lie
  // left of the tile's centre (each crossing counted once: half-open in y).
  std::vector<double> xs;
  for (std::size_t r = 0; r < n; ++r) {
    const double yc = g.y0 + (static_cast<double>(r) + 0.5) * g.dy;
    xs.clear();
    for (std::size_t k = 0; k < count; ++k)
      if ((ya[k] > yc) != (yb[k] > yc)) xs.push_back(xa[k] + (yc - ya[k]) * (xb[k] - xa[k]) / (yb[k] - ya[k]));
    std::sort(xs.begin(), xs.end());
    for (std::size_t c = 0; c < n; ++c) {
      const std::size_t t = r * n + c;
      if (boundary[t]) {
        set(t);
        continue;
      }
      const double xc = g.x0 + (static_cast<double>(c) + 0.5) * g.dx;
      const auto left = std::lower_bound(xs.begin(), xs.end(), xc) - xs.begin();
      if (left % 2 == 1) {
        set(t);
        // Inside, and no boundary passes through the closed tile: all of it lies in the region.
        if (whole) whole[t / 64] |= std::uint64_t{1} << (t % 64);
      }
    }
  }
}

void StripTileCounts::begin(const FaceTiles& tiles, bool whole_strip, double x0, double x1,
                            const std::vector<double>& hours, const std::vector<mpq_class>& exact_hours) {
  tiles_ = &tiles;
  hours_ = &hours;
  const TileGrid& g = tiles.grid;
  c0_ = whole_strip ? 0 : g.column(x0);
  c1_ = whole_strip ? g.n - 1 : g.column(x1);
  most_.assign((c1_ - c0_ + 1) * g.n, 0);
  least_.assign(most_.size(), 0);
  most_weight_ = 0, least_weight_ = 0;
  for (const mpq_class& w : exact_hours) {
    if (w > most_weight_) most_weight_ = w;
    if (sgn(w) > 0 && (sgn(least_weight_) == 0 || w < least_weight_)) least_weight_ = w;
  }
}

std::size_t FaceTiles::slot(std::size_t i) const {
  const auto it = std::lower_bound(instants.begin(), instants.end(), i);
  return it != instants.end() && *it == i ? static_cast<std::size_t>(it - instants.begin()) : SIZE_MAX;
}

void StripTileCounts::add_slot(std::size_t s, bool add) {
  if ((*hours_)[tiles_->instants[s]] == 0) return;  // adds no hours: never counted
  const std::size_t n = tiles_->grid.n;
  for (std::size_t c = c0_; c <= c1_; ++c)
    for (std::size_t r = 0; r < n; ++r) {
      const std::size_t tile = r * n + c, at = (c - c0_) * n + r;
      if (!tiles_->lit(s, tile)) continue;
      most_[at] += add ? 1 : -1;
      if (tiles_->lit_whole(s, tile)) least_[at] += add ? 1 : -1;
    }
}

void StripTileCounts::count(std::size_t i, bool add) {
  if (empty()) return;
  const std::size_t s = tiles_->slot(i);
  if (s != SIZE_MAX) add_slot(s, add);
}

void StripTileCounts::recount(const std::vector<std::size_t>& instants) {
  std::fill(most_.begin(), most_.end(), 0);
  std::fill(least_.begin(), least_.end(), 0);
  for (std::size_t i : instants) count(i, true);
}

std::size_t StripTileCounts::whole_tiles(std::size_t i) const {
  if (empty()) return 0;
  const std::size_t s = tiles_->slot(i), n = tiles_->grid.n;
  std::size_t count = 0;
  if (s == SIZE_MAX) return 0;
  for (std::size_t c = c0_; c <= c1_; ++c)
    for (std::size_t r = 0; r < n; ++r) count += tiles_->lit_whole(s, r * n + c) ? 1 : 0;
  return count;
}

StripTileCounts::Range StripTileCounts::under(double xmin, double xmax, double ymin, double ymax) const {
  const TileGrid& g = tiles_->grid;
  const std::size_t c0 = std::max(c0_, g.column(xmin)), c1 = std::min(c1_, g.column(xmax));
  const std::size_t r0 = g.row(ymin), r1 = g.row(ymax);
  Range out;
  std::uint32_t least = UINT32_MAX;
  for (std::size_t c = c0; c <= c1; ++c)
    for (std::size_t r = r0; r <= r1; ++r) {
      const std::size_t at = (c - c0_) * g.n + r;
      out.most = std::max(out.most, most_[at]);
      least = std::min(least, least_[at]);
    }
  out.least = least == UINT32_MAX ? 0 : least;
  return out;
}

std::vector<std::size_t> sweep_order(const FaceTiles& t) {
  std::vector<std::size_t> order = t.instants;  // ascending
  if (t.grid.n == 0) return order;
  std::vector<std::pair<long, std::size_t>> key;  // (-tiles lit whole, instant)
  for (std::size_t i : order) {
    const std::size_t slot = t.slot(i), words = t.grid.words();
    long whole = 0;
    for (std::size_t w = 0; slot != SIZE_MAX && w < words; ++w)
      whole += __builtin_popcountll(t.whole_masks[slot * words + w]);
    key.emplace_back(-whole, i);
  }
  std::stable_sort(key.begin(), key.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t p = 0; p < key.size(); ++p) order[p] = key[p].second;
  return order;
}

FaceTiles make_face_tiles(const exact::Polygon2& chart, const std::vector<RoughSegment>& rough,
                          const std::vector<std::pair<std::size_t, std::size_t>>& runs, const mpq_class& whole,
                          double max_bits, unsigned threads) {
  std::size_t most = 0;
  for (const auto& [b, e] : runs) most = std::max(most, e - b);
  FaceTiles t;
  t.grid = tile_grid(chart, most, runs.size(), max_bits);
  t.instants.resize(runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r) t.instants[r] = rough[runs[r].first].instant;
  if (t.grid.n == 0) return t;
  t.whole = whole;
  t.masks.assign(t.grid.words() * runs.size(), 0);
  t.whole_masks.assign(t.grid.words() * runs.size(), 0);
  runtime::parallel_for(runs.size(), threads, [&](unsigned, std::size_t r) {
    const auto [b, e] = runs[r];
    mark_lit_tiles(t.grid, rough.data() + b, rough.data() + e, t.masks.data() + r * t.grid.words(),
                   t.whole_masks.data() + r * t.grid.words());
  });
  return t;
}

}  // namespace shadow::sunmap
