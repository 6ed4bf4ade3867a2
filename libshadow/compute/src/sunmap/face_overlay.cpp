// SPDX-License-Identifier: GPL-3.0-or-later
// One strip of one face's sun-hours overlay (face_overlay.hpp).
//
// The curves that enter the strip, clipped to its sides x0 <= x <= x1, and the strip's frame (a
// rectangle reaching below and above the chart) go into one CGAL arrangement whose curves carry
// (instant, side) data, merged where boundaries of several instants overlap. A breadth-first
// walk gives every face its hours: crossing an edge into instant i's region adds w_i, out of it
// subtracts w_i; it starts from the face along the frame's bottom, which lies below the chart
// (0 hours, outside), and never crosses the frame, so the strip needs nothing from its
// neighbours. A face that is not cut (one whole strip) walks from the unbounded face instead, as
// the map always did. Hours are exact rationals, so equal sets of instants give equal hours
// whatever path reached them. Edges with equal hours on both sides are removed (touching cells of
// equal hours merge), then, for the threshold map, edges with the same level on both sides; every
// remaining face is written like a fragment: simple cells (exact/regions.hpp), lifted to the
// face's plane, rounded once.
#include "sunmap/face_overlay.hpp"

#include "sunmap/lit_tiles.hpp"
#include "sunmap/pending_boundaries.hpp"
#include "sunmap/rough_segments.hpp"

#include "runtime/parallel.hpp"
#include "exact/lazy_geometry.hpp"
#include "exact/regions.hpp"

#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arrangement_2.h>

#include <algorithm>
#include <cstdint>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace shadow::sunmap {
namespace {

using namespace exact;

using Dcel = CGAL::Arr_face_extended_dcel<Traits, long>;  // face data: index into the walk's values
using Arrangement = CGAL::Arrangement_2<Traits, Dcel>;

double round_mpq(const mpq_class& q) { return exact::round_mpq_to_double(q.get_mpq_t()); }

/// A breadth-first walk over an arrangement's faces from those in `queue`: `visit_ccb(face,
/// ccb)` is called on every boundary (outer and inner) of each face taken from the queue, and
/// pushes the neighbours it reaches first.
template <class VisitCcb>
void walk_faces(std::deque<Arrangement::Face_handle>& queue, VisitCcb&& visit_ccb) {
  while (!queue.empty()) {
    const Arrangement::Face_handle f = queue.front();
    queue.pop_front();
    for (auto c = f->outer_ccbs_begin(); c != f->outer_ccbs_end(); ++c) visit_ccb(f, *c);
    for (auto c = f->inner_ccbs_begin(); c != f->inner_ccbs_end(); ++c) visit_ccb(f, *c);
  }
}

template <class Circulator>
Polygon2 ccb_polygon(Circulator first) {
  Polygon2 polygon;
  auto h = first;
  do {
    polygon.push_back(h->source()->point());
  } while (++h != first);
  return polygon;
}

/// The face of `arr` just inside the bottom side of `strip`'s frame (below the chart), or none.
Arrangement::Face_handle above_frame_bottom(Arrangement& arr, const Strip& strip) {
  const Arrangement::Face_handle unbounded = arr.unbounded_face();
  const FT ylo(strip.ylo);
  for (auto c = unbounded->inner_ccbs_begin(); c != unbounded->inner_ccbs_end(); ++c) {
    auto h = *c;
    do {
      if (h->source()->point().y() == ylo && h->target()->point().y() == ylo) return h->twin()->face();
    } while (++h != *c);
  }
  return Arrangement::Face_handle();
}

}  // namespace

class StripOverlay {
 public:
  StripOverlay(const OverlayRequest& r, const Strip& strip) : r_(r), strip_(strip), n_(r.hours->size()) {
    exact_to_mpq(r.face->area_scale_squared, scale_.get_mpq_t());
  }

  /// The full map (and its levels when asked): every curve `which` of `b` in one sweep.
  StripMap run(const FaceBoundaries& b, const std::vector<std::size_t>& which) {
    std::vector<Curve> curves = gather(b.curves, which, true);
    Arrangement arr;
    CGAL::insert(arr, curves.begin(), curves.end());  // one sweep: not stopped inside
    curves.clear();
    curves.shrink_to_fit();
    runtime::check_stop();
    outline_add_ = b.base;  // crossing the outline into the chart adds the whole-face instants
    walk(arr);
    StripMap out;
    out.level_area.resize(r_.levels.size() + 1);
    if (r_.full) {
      if (r_.merge) merge(arr, [&](long a, long c) { return hours_at_[a] == hours_at_[c]; });
      emit_all(arr, out, false);
    }
    if (!r_.levels.empty()) {
      level_.resize(hours_at_.size());
      for (std::size_t v = 0; v < hours_at_.size(); ++v) level_[v] = level_of(hours_at_[v]);
      merge(arr, [&](long a, long c) { return level_[a] == level_[c]; });
      emit_all(arr, out, true);
    }
    out.dropped = dropped_;
    return out;
  }

  // The threshold map alone, in rounds of instants (LevelRounds). Each round sweeps one fresh
  // arrangement of the boundaries kept from the round before and the round's instants'
  // boundaries, walks it once for every face's hours, and replaces each hours value whose final
  // level is known (the level now is the level even if every instant still to come lit it, or,
  // with tiles, what may or surely will still come fixes it: settle) by the smallest value of
  // that level: the cell is settled, its level final. Only the edges with an open cell on a side
  // go on to the next round, each carrying its sides' states; an edge between two cells settled
  // now is frozen, with the jump of value across it, when their levels differ (a level boundary,
  // swept again only at the end), else dropped (kept_curves); the frame is swept whole each round.
  // The arrangement so holds the open cells' boundaries, not the level boundaries found so far
  // nor every instant's. No edge is removed from a large arrangement (CGAL walks a face's boundary to
  // remove an edge of it: removing many from one large region is slow). X-monotone curves
  // throughout: a kept edge is its arrangement curve, which keeps the supporting line of the
  // segment it was cut from, so that later intersections are computed from the input's lines and
  // not from lines through earlier intersections (whose exact numbers would grow round after
  // round). Instants arrive in time order, a batch at a time (feed), and are swept as soon as
  // they fill a round: only the instants not yet swept are held. With tiles, the instants come
  // in the order of a plan instead, the face's sunniest first (plan), and go the same way.

  /// The outline's curves `which` (and the strip's frame): the first round's kept edges.
  void begin(const std::vector<Curve>& outline, const std::vector<std::size_t>& which) {
    // The outline's edges carry the sides' states: the chart (open, 0 hours so far) on one side,
    // outside on the other.
    states_ = {{Side{Side::kOpen, 0}, Side{Side::kOutside, 0}}, {Side{Side::kOutside, 0}, Side{Side::kOpen, 0}}};
    for (const Curve& c : gather(outline, which, true)) {
      Traits::Data_container data(c.data());
      const std::size_t i = tag_instant(c.data());
      if (i == n_) data.insert(state_tag(tag_left(c.data()) ? 0 : 1));
      (i == n_ + 1 ? frame_ : kept_).emplace_back(c, data);
    }
    least_ = std::max<std::size_t>(r_.round_edges, 1);
    want_ = static_cast<double>(least_);
    begin_tiles();
  }

  void feed(const std::vector<Curve>& curves, const std::vector<std::size_t>& which, const mpq_class& whole,
            const mpq_class& unfed) {
    if (planned_) throw std::logic_error("LevelRounds: a planned strip is fed by feed_planned");
    for (const Curve& c : gather(curves, which, false)) {
      const std::size_t i = tag_instant(c.data());
      if (pending_.empty() || pending_.back().first != i) {
        pending_.emplace_back(i, std::vector<XCurve>{});
        pending_hours_ += (*r_.exact_hours)[i];
      }
      pending_.back().second.emplace_back(c, Traits::Data_container(c.data()));
      ++pending_segments_;
    }
    base_pending_ += whole;
    unfed_ = unfed;
    // A round takes instants until it holds `want_` new segments: sweep those that are here.
    while (!pending_.empty() && static_cast<double>(pending_segments_) >= want_) round();
  }

  /// The strip's instants (those of `order` whose boundary may enter it: with a segment among
  /// `which` of `segments`) in the order they are swept: band by band of `order` (cut before the
  /// positions `band_ends`; a band is fed at once), and within a band those lighting the most of
  /// the strip's tiles whole first; the tiles' counts and pending boundaries made of them alone;
  /// `whole` the hours of every instant lighting the whole face. (The hours are sums, so any
  /// order gives the same values; the sunniest first settle cells sooner: on a ground over many
  /// days, time order held the cells near buildings a few hours below the top level undecided
  /// until their sun came, day after day.)
  void plan(const std::vector<std::size_t>& order, const std::vector<std::size_t>& band_ends,
            const std::vector<RoughSegment>& segments, const std::vector<std::size_t>& which, const mpq_class& whole) {
    if (planned_ || rounds_ != 0 || !pending_.empty()) throw std::logic_error("LevelRounds: planned twice or late");
    planned_ = true;
    base_pending_ += whole;
    std::vector<char> present(n_, 0);
    for (std::size_t k : which) present[segments[k].instant] = 1;
    // (band, -tiles of the strip lit whole, position in the face's order, instant)
    std::vector<std::tuple<std::size_t, long, std::size_t, std::size_t>> key;
    std::size_t band = 0;
    for (std::size_t p = 0; p < order.size(); ++p) {
      while (band < band_ends.size() && band_ends[band] <= p) ++band;
      if (!present[order[p]]) continue;
      const long lit = counts_.empty() ? 0 : static_cast<long>(counts_.whole_tiles(order[p]));
      key.emplace_back(band, -lit, p, order[p]);
      unfed_ += (*r_.exact_hours)[order[p]];
    }
    std::sort(key.begin(), key.end());
    std::vector<std::size_t> instants;
    for (const auto& [b, lit, p, i] : key) {
      plan_.emplace_back(p, i);
      instants.push_back(i);
    }
    if (counts_.empty()) return;
    counts_.recount(instants);
    bounds_.build(*r_.tiles, counts_.first_column(), counts_.last_column(), strip_.whole, strip_.x0, strip_.x1,
                  instants, segments, which, *r_.hours);
  }

  bool planned() const { return planned_; }

  /// Feeds the planned instants at positions before `order_end` of the face's order: `which`
  /// of `curves` are every boundary of theirs that may enter the strip (and of no other
  /// instant). Sweeps every round that they fill.
  void feed_planned(const std::vector<Curve>& curves, const std::vector<std::size_t>& which, std::size_t order_end) {
    if (!planned_) throw std::logic_error("LevelRounds: feed_planned before plan");
    std::unordered_map<std::size_t, std::vector<XCurve>> by_instant;
    for (const Curve& c : gather(curves, which, false))
      by_instant[tag_instant(c.data())].emplace_back(c, Traits::Data_container(c.data()));
    while (!plan_.empty() && plan_.front().first < order_end) {
      const std::size_t i = plan_.front().second;
      plan_.pop_front();
      std::vector<XCurve> mine;
      const auto it = by_instant.find(i);
      if (it != by_instant.end()) {
        mine = std::move(it->second);
        by_instant.erase(it);
      }
      pending_segments_ += mine.size();
      pending_hours_ += (*r_.exact_hours)[i];
      unfed_ -= (*r_.exact_hours)[i];
      pending_.emplace_back(i, std::move(mine));
    }
    if (!by_instant.empty()) throw std::logic_error("LevelRounds: a boundary of an instant not planned in the strip");
    while (!pending_.empty() && static_cast<double>(pending_segments_) >= want_) round();
  }

  StripMap finish() {
    if (!plan_.empty()) throw std::logic_error("LevelRounds: finished before every planned instant was fed");
    unfed_ = 0;
    while (!pending_.empty()) round();
    // Whole-face hours still to add, or cells left open by a round swept while instants were
    // still to come (streamed: the later ones may never have reached this strip): one more round,
    // with nothing left to come, settles every cell.
    if (rounds_ == 0 || sgn(base_pending_) != 0 || !kept_.empty()) round();
    bounds_ = {};
    // Every cell is now settled (nothing remains to come), so the edges frozen round by round are
    // the level boundaries: one last sweep of them alone (and the frame) gives the level regions.
    if (!kept_.empty()) throw std::logic_error("LevelRounds: a cell is still open after the last round");
    Arrangement arr;
    frozen_.insert(frozen_.end(), frame_.begin(), frame_.end());
    CGAL::insert(arr, frozen_.begin(), frozen_.end());
    kept_ = {};
    frozen_ = {};
    outline_add_ = 0;
    walk(arr);
    StripMap out;
    out.level_area.resize(r_.levels.size() + 1);
    level_.resize(hours_at_.size());
    for (std::size_t v = 0; v < hours_at_.size(); ++v) level_[v] = level_of(hours_at_[v]);
    emit_all(arr, out, true);
    out.dropped = dropped_;
    return out;
  }

 private:
  /// One round: the kept edges and the next instants' boundaries, swept, walked and settled.
  void round() {
    runtime::check_stop();
    const std::size_t kept_in = kept_.size();
    std::vector<XCurve> curves = std::move(kept_);
    kept_ = {};
    curves.insert(curves.end(), frame_.begin(), frame_.end());
    std::size_t added = 0;
    while (!pending_.empty() && (added == 0 || static_cast<double>(added) < want_)) {
      auto& [i, more] = pending_.front();
      added += more.size();
      pending_segments_ -= more.size();
      pending_hours_ -= (*r_.exact_hours)[i];
      counts_.count(i, false);
      for (XCurve& c : more) curves.push_back(std::move(c));
      pending_.pop_front();
      ++walked_;
    }
    if (!bounds_.empty()) bounds_.walked(walked_);
    Arrangement arr;
    CGAL::insert(arr, curves.begin(), curves.end());  // one sweep of a fresh arrangement
    curves = {};
    outline_add_ = base_pending_;  // the whole-face hours fed since the last walk
    whole_walked_ += base_pending_;
    base_pending_ = 0;
    walk_round(arr);
    outline_add_ = 0;
    settle(arr, unfed_ + pending_hours_);
    kept_ = kept_curves(arr);
    ++rounds_;
    // Every strip of every face is held between feeds: keep only what the next round needs
    // (the kept edges and their states), not the walk's values of every face of this arrangement.
    hours_at_ = {};
    inside_ = {};
    fresh_ = {};
    open_ = {};
    // The new segments of a round cross one another (shadows of one caster at neighbouring
    // instants), so the arrangement grows faster than they do, up to about the square of their
    // number. Each round aims its arrangement at about twice the edges kept (at least twice
    // round_edges): the next share a is the smaller of what a linear guess (a x the edges each
    // new segment brought this time) and a quadratic one (a^2 x those edges / this round's new
    // segments) allow, at most twice the last share and at least a quarter of it. (Aiming at four
    // times with the linear guess alone, the second round of a day's suns on a 40-box ground
    // held 57,000-85,000 edges where about 30,000 were aimed at, and two such on two threads
    // made the peak: docs/benchmarks.md.)
    const double edges = static_cast<double>(arr.number_of_edges());
    const double new_in = static_cast<double>(std::max<std::size_t>(added, 1));
    const double per_new = std::max(1.0, (edges - static_cast<double>(kept_in)) / new_in);
    const double target = 2.0 * static_cast<double>(std::max(kept_.size(), least_));
    const double room = std::max(1.0, target - static_cast<double>(kept_.size()));
    const double aim = std::max(1.0, std::min(room / per_new, std::sqrt(room * new_in / per_new)));
    want_ = std::min(std::max(aim, want_ / 4), 2 * want_);
  }

  std::size_t level_of(const mpq_class& hours) const {
    std::size_t level = 0;
    while (level < r_.levels.size() && r_.levels[level] <= hours) ++level;
    return level;
  }

  /// Settles the faces of open cells (fresh_; the others are outside the chart or settled in an
  /// earlier round) whose level is decided, marking the rest in open_. Replaces every value that is decided, whatever the hours still to come add, by the smallest
  /// value of its level (0 below the lowest): it keeps its level under any later additions, since
  /// level l's smallest value plus what may come stays below level l + 1 when the value did. What
  /// may come is `remaining` (every instant not yet walked), or, with tiles, for a face the hours
  /// not yet walked of the instants lighting the whole face, plus the most that the instants not
  /// yet walked may bring to one tile under the face's bounding box (tiles_bound). With tiles, a value also is decided at the top level when what surely comes
  /// (the whole-face hours not yet walked, and the least that the instants lighting a tile whole
  /// bring to one tile under the face) takes it there: it gets the top level's smallest value,
  /// which stays at the top level under any addition, as the face's hours do. Where the tiles
  /// decide neither, the boundaries still to come that may enter the cell itself are looked at
  /// (settled_level).
  void settle(const Arrangement& arr, const mpq_class& remaining) {
    mpq_class most, least;
    const std::size_t top = r_.levels.size();
    open_ = fresh_;
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
      const auto v = static_cast<std::size_t>(f->data());
      if (!fresh_[v]) continue;  // outside, or settled in an earlier round
      std::size_t now = level_of(hours_at_[v]);
      if (now != level_of(hours_at_[v] + remaining)) {
        if (counts_.empty() || f->is_unbounded()) continue;  // undecided: kept exactly
        const Box box = tiles_bound(f, most, least);
        if (level_of(hours_at_[v] + least) == top) {
          now = top;  // surely reaches the top level
        } else if (most >= remaining || now != level_of(hours_at_[v] + most)) {
          // Undecided by the tiles: by the boundaries that may enter the cell itself?
          if (bounds_.empty()) continue;
          now = settled_level(counts_, bounds_, box.xmin, box.xmax, box.ymin, box.ymax, hours_at_[v],
                              whole_total_ - whole_walked_, r_.levels, now);
          if (now == SIZE_MAX) continue;  // undecided
        }
      }
      hours_at_[v] = now == 0 ? mpq_class(0) : r_.levels[now - 1];
      open_[v] = 0;
    }
  }

  /// The tiles' counts under the strip (StripTileCounts), filled by plan.
  void begin_tiles() {
    if (r_.tiles == nullptr || r_.tiles->grid.n == 0) return;
    counts_.begin(*r_.tiles, strip_.whole, strip_.x0, strip_.x1, *r_.hours, *r_.exact_hours);
    whole_total_ = r_.tiles->whole;
  }

  /// Bounds on what the instants not yet walked add to face `f`: at most `most` (the whole-face
  /// hours not yet walked and the largest count of those that may light a tile meeting f's
  /// bounding box, times the largest weight), at least `least` (the same whole-face hours and the
  /// smallest count of those lighting such a tile whole, times the smallest positive weight).
  struct Box {
    double xmin, xmax, ymin, ymax;
  };
  Box tiles_bound(Arrangement::Face_const_handle f, mpq_class& most, mpq_class& least) const {
    double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL;
    auto h = f->outer_ccb();
    const auto first = h;
    do {
      const auto x = CGAL::to_interval(h->target()->point().x()), y = CGAL::to_interval(h->target()->point().y());
      xmin = std::min(xmin, x.first), xmax = std::max(xmax, x.second);
      ymin = std::min(ymin, y.first), ymax = std::max(ymax, y.second);
    } while (++h != first);
    const StripTileCounts::Range range = counts_.under(xmin, xmax, ymin, ymax);
    most = whole_total_ - whole_walked_;
    least = most;
    if (range.most != 0) most += counts_.most_weight() * range.most;
    if (range.least != 0) least += counts_.least_weight() * range.least;
    return {xmin, xmax, ymin, ymax};
  }

  /// A side of a kept edge: outside the chart, settled at a level (its smallest value), or open
  /// with its hours so far.
  struct Side {
    enum Kind : int { kOutside, kSettled, kOpen } kind;
    mpq_class value;
    bool operator==(const Side& o) const { return kind == o.kind && (kind == kOutside || value == o.value); }
  };
  long state_tag(std::size_t k) const { return static_cast<long>(n_ + 3 + k); }

  /// The state of walked face v now (after settle).
  Side side_of(std::size_t v) const {
    if (inside_[v] <= 0) return Side{Side::kOutside, 0};
    return Side{open_[v] ? Side::kOpen : Side::kSettled, hours_at_[v]};
  }

  /// The edges of `arr` for the next round, and those frozen for the last sweep. An edge with an
  /// open cell on a side is kept, carrying both sides' states (a tag n + 3 + k for states_[k])
  /// and the outline's tag. An edge between two cells settled now (one of them at least in this
  /// round) is a level boundary when their levels (or sides of the chart) differ: it is frozen,
  /// carrying the jump of value across it (a tag n + 3 + k for frozen_jumps_[k]) and the
  /// outline's tag, and never swept again before the last sweep; otherwise it goes. Edges between
  /// cells settled in earlier rounds (the new instants' boundaries crossing them) go. A face
  /// settled earlier is known by the edge's own state for it: such faces merge across the edges
  /// frozen before, so their walked states say nothing. The frame's pieces go: the next round
  /// sweeps the frame's four sides again (its pieces, split wherever an edge ever met it, were
  /// most of the edges kept).
  std::vector<XCurve> kept_curves(const Arrangement& arr) {
    std::vector<XCurve> out;
    std::vector<std::pair<Side, Side>> states;
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
      Arrangement::Halfedge_const_handle h = e;
      if (h->direction() != CGAL::ARR_LEFT_TO_RIGHT) h = h->twin();
      const auto a = static_cast<std::size_t>(h->face()->data());  // left
      const auto b = static_cast<std::size_t>(h->twin()->face()->data());  // right
      Traits::Data_container data;
      const std::pair<Side, Side>* was = nullptr;
      bool frame = false;
      for (long tag : h->curve().data()) {
        const std::size_t i = tag_instant(tag);
        if (i == n_) data.insert(tag);  // the outline
        frame = frame || i == n_ + 1;
        if (i > n_ + 1) {
          if (was != nullptr) throw std::logic_error("LevelRounds: two kept edges overlap");
          was = &states_[i - n_ - 2];
        }
      }
      if (frame) continue;  // each round sweeps the whole frame again, not its pieces
      // An open cell's boundary with a region settled (or outside) before this round is always
      // (a piece of) a kept edge: a face of that region says nothing of its own level.
      if (was == nullptr && fresh_[a] != fresh_[b])
        throw std::logic_error("LevelRounds: an open cell meets a settled region along no kept edge");
      const Side left = fresh_[a] || was == nullptr ? side_of(a) : was->first;
      const Side right = fresh_[b] || was == nullptr ? side_of(b) : was->second;
      if (left.kind == Side::kOpen || right.kind == Side::kOpen) {
        if (left == right) continue;  // inside one open cell
        data.insert(state_tag(states.size()));
        states.emplace_back(left, right);
        out.push_back(edge_curve(h, data));
      } else if ((fresh_[a] || fresh_[b]) && !(left == right)) {
        // Like an instant's region of weight left - right on the left: crossing to the right
        // adds right - left.
        const mpq_class d = left.value - right.value;
        if (sgn(d) != 0) {
          auto [it, added] = frozen_index_.emplace(d, static_cast<long>(frozen_jumps_.size()));
          if (added) frozen_jumps_.push_back(d);
          data.insert(static_cast<long>(n_ + 3) + it->second);
        }
        frozen_.push_back(edge_curve(h, data));
      }
    }
    states_.swap(states);
    return out;
  }

  /// Walks a round's arrangement: every face gets the hours of the round's instants that light
  /// it (crossing an instant's boundary adds or takes its weight; from the face along the frame's
  /// bottom, outside the chart, or the unbounded face) and, from the kept edges' states, the
  /// state of the cell it lies in (crossing a kept edge gives the state of its far side; other
  /// edges keep it). A face of an open cell gets that cell's hours plus the round's, and the
  /// whole-face hours of the round (outline_add_); fresh_ marks them.
  void walk_round(Arrangement& arr) {
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) f->set_data(-1);
    const Arrangement::Face_handle unbounded = arr.unbounded_face();
    unbounded->set_data(0);
    std::vector<mpq_class> added(1, mpq_class(0));
    std::vector<Side> side(1, Side{Side::kOutside, 0});
    std::deque<Arrangement::Face_handle> queue;
    const auto seed = [&](Arrangement::Face_handle f) {
      f->set_data(static_cast<long>(added.size()));
      added.emplace_back(0);
      side.push_back(Side{Side::kOutside, 0});
      queue.push_back(f);
    };
    std::size_t beyond = 0;  // the unbounded face lies beyond a strip's frame
    if (strip_.whole) {
      queue.push_back(unbounded);
    } else {
      beyond = 1;
      const Arrangement::Face_handle below = above_frame_bottom(arr, strip_);
      if (below != Arrangement::Face_handle()) seed(below);  // below the chart: outside, nothing lit
    }
    auto visit_ccb = [&](Arrangement::Face_handle from, Arrangement::Ccb_halfedge_circulator first) {
      auto h = first;
      do {
        const Arrangement::Face_handle to = h->twin()->face();
        if (to->data() < 0) {
          const auto v = static_cast<std::size_t>(from->data());
          mpq_class value = added[v];
          Side state = side[v];
          const bool left_to_right = h->direction() == CGAL::ARR_LEFT_TO_RIGHT;
          for (long tag : h->curve().data()) {
            const std::size_t i = tag_instant(tag);
            if (i >= n_ && i <= n_ + 1) continue;  // the outline (its states say it), a frame
            if (i > n_ + 1) {
              const auto& [left, right] = states_[i - n_ - 2];
              state = left_to_right ? right : left;  // `to` lies right of a left-to-right h
            } else {
              // `from` lies on h's left; the region lies on the left of the left-to-right run
              // when tag > 0.
              const bool from_in_region = left_to_right == tag_left(tag);
              value += from_in_region ? mpq_class(-(*r_.exact_hours)[i]) : (*r_.exact_hours)[i];
            }
          }
          to->set_data(static_cast<long>(added.size()));
          added.push_back(std::move(value));
          side.push_back(std::move(state));
          queue.push_back(to);
        }
      } while (++h != first);
    };
    walk_faces(queue, visit_ccb);
    hours_at_.assign(side.size(), mpq_class(0));
    inside_.assign(side.size(), 0);
    fresh_.assign(side.size(), 0);
    for (std::size_t v = 0; v < side.size(); ++v) {
      if (v < beyond) inside_[v] = -1;  // beyond the frame: never merged across it
      if (side[v].kind == Side::kOutside) continue;
      inside_[v] = 1;
      if (side[v].kind == Side::kSettled) {
        hours_at_[v] = side[v].value;
      } else {
        hours_at_[v] = side[v].value + added[v] + outline_add_;
        fresh_[v] = 1;
      }
    }
  }

  /// Left-to-right edge h as a curve carrying `data`: on the supporting line of the segment it was
  /// cut from (so that later intersections are computed from the input's lines), between the
  /// edge's own ends. (The arrangement's curve of an edge along collinear boundaries may reach
  /// beyond the edge: kept as it was, it overlapped its neighbours' in the next sweep.)
  static XCurve edge_curve(Arrangement::Halfedge_const_handle h, const Traits::Data_container& data) {
    const XCurve& cv = h->curve();
    const SegmentTraits::X_monotone_curve_2 piece(cv.line(), h->source()->point(), h->target()->point(), true,
                                                  cv.is_vertical(), false);
    return XCurve(piece, data);
  }

  /// The curves `which` of `all`, clipped to the strip, with its frame when `frame`.
  std::vector<Curve> gather(const std::vector<Curve>& all, const std::vector<std::size_t>& which, bool frame) const {
    std::vector<Curve> curves;
    curves.reserve(which.size() + 4);
    if (strip_.whole) {
      for (std::size_t c : which) curves.push_back(all[c]);
    } else {
      const FT x0(strip_.x0), x1(strip_.x1);
      Curve clipped;
      for (std::size_t c : which)
        if (clip_to_strip(all[c], x0, x1, clipped)) curves.push_back(std::move(clipped));
      if (!frame) return curves;
      Polygon2 rectangle;
      rectangle.push_back(Point2(strip_.x0, strip_.ylo));
      rectangle.push_back(Point2(strip_.x1, strip_.ylo));
      rectangle.push_back(Point2(strip_.x1, strip_.yhi));
      rectangle.push_back(Point2(strip_.x0, strip_.yhi));
      add_boundary(rectangle, static_cast<long>(n_ + 1), curves);
    }
    return curves;
  }

  /// Gives every face of `arr` its hours (data: an index into hours_at_ and inside_). From the
  /// unbounded face for a whole face; inside a strip from the face above the frame's bottom.
  /// Crossing halfedge h from h's face into its twin's leaves the regions on h's left and
  /// enters those on its right.
  void walk(Arrangement& arr) {
    const Strip& strip = strip_;
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) f->set_data(-1);
    const Arrangement::Face_handle unbounded = arr.unbounded_face();
    unbounded->set_data(0);
    hours_at_.assign(1, mpq_class(0));
    // Outside a strip's frame nothing is known: -1 never equals an inside count, so frame
    // edges are never merged away.
    inside_.assign(1, strip.whole ? 0 : -1);
    std::deque<Arrangement::Face_handle> queue;
    if (strip.whole) {
      queue.push_back(unbounded);
    } else {
      const Arrangement::Face_handle seed = above_frame_bottom(arr, strip);  // below the chart: 0 hours, outside
      if (seed != Arrangement::Face_handle()) {
        seed->set_data(1);
        hours_at_.push_back(mpq_class(0));
        inside_.push_back(0);
        queue.push_back(seed);
      }
    }
    auto visit_ccb = [&](Arrangement::Face_handle from, Arrangement::Ccb_halfedge_circulator first) {
      auto h = first;
      do {
        const Arrangement::Face_handle to = h->twin()->face();
        if (to->data() < 0) {
          mpq_class value = hours_at_[from->data()];
          int inside = inside_[from->data()];
          const bool left_to_right = h->direction() == CGAL::ARR_LEFT_TO_RIGHT;
          for (long tag : h->curve().data()) {
            const std::size_t i = tag_instant(tag);
            if (i == n_ + 1) continue;  // a frame (a strip's faces never reach one across it)
            // `from` lies on h's left; the region lies on the left of the left-to-right run
            // when tag > 0.
            const bool from_in_region = left_to_right == tag_left(tag);
            const int step = from_in_region ? -1 : 1;
            if (i == n_) {
              inside += step;
              if (sgn(outline_add_) != 0) value += step > 0 ? outline_add_ : mpq_class(-outline_add_);
            } else if (i > n_) {  // the last sweep: a frozen edge's jump (tags are positive)
              const mpq_class& jump = frozen_jumps_[i - n_ - 2];
              value += step > 0 ? jump : mpq_class(-jump);
            } else {
              value += step > 0 ? (*r_.exact_hours)[i] : mpq_class(-(*r_.exact_hours)[i]);
            }
          }
          to->set_data(static_cast<long>(hours_at_.size()));
          hours_at_.push_back(std::move(value));
          inside_.push_back(inside);
          queue.push_back(to);
        }
      } while (++h != first);
    };
    walk_faces(queue, visit_ccb);
  }

  /// Removes every edge with equal inside counts and equal(a, b) keys on both sides: touching
  /// cells become one face. No antenna is left, since every remaining edge separates faces of
  /// different keys.
  template <class Equal>
  void merge(Arrangement& arr, Equal equal) {
    std::vector<Arrangement::Halfedge_handle> removable;
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
      const long a = e->face()->data(), b = e->twin()->face()->data();
      if (a == b || (inside_[a] == inside_[b] && equal(a, b))) removable.push_back(e);
    }
    for (Arrangement::Halfedge_handle e : removable) arr.remove_edge(e);
  }

  void emit_all(Arrangement& arr, StripMap& out, bool levels) {
    std::vector<Polygon2> cells;
    std::vector<SunHoursCell>& dest = levels ? out.level_cells : out.cells;
    std::size_t& regions = levels ? out.level_regions : out.regions;
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
      if (f->is_unbounded() || inside_[f->data()] <= 0) continue;
      runtime::check_stop();
      PolygonWithHoles2 region(ccb_polygon(f->outer_ccb()));
      for (auto h = f->inner_ccbs_begin(); h != f->inner_ccbs_end(); ++h) region.add_hole(ccb_polygon(*h));
      const std::size_t level = levels ? level_[f->data()] : 0;
      const double value = !levels ? round_mpq(hours_at_[f->data()]) : level == 0 ? 0.0 : round_mpq(r_.levels[level - 1]);
      std::vector<mpq_class>& area = levels ? out.level_area[level] : out.hour_area[hours_at_[f->data()]];
      cells.clear();
      append_simple_cells(region, cells);
      const std::size_t before = dest.size();
      for (Polygon2& cell : cells) emit(cell, value, dest, area, !levels);
      if (dest.size() > before) {
        for (std::size_t c = before; c < dest.size(); ++c) dest[c].region_id = regions;
        ++regions;
      }
    }
    rounded_.clear();
  }

  /// A cell vertex lifted onto the face and rounded to doubles, once per point of the
  /// arrangement: a vertex is a corner of several cells, and the lift's exact evaluation and
  /// rounding were a fifth of a week's map on a real model. Keyed by the point's
  /// representation, which the entry holds (so no other point can take its address).
  const glm::dvec3& rounded(const Point2& p) {
    const auto it = rounded_.find(p.id());
    if (it != rounded_.end()) return it->second.second;
    const glm::dvec3 v = nearest_doubles(lift(p, *r_.face, r_.prep->axis));  // (before the entry: may throw)
    return rounded_.emplace(p.id(), std::make_pair(p, v)).first->second.second;
  }

  /// One simple cell as a SunHoursCell when its rounded polygon is clean, else its triangles
  /// (those that collapse are counted in dropped_area), as the exact engine writes fragments.
  void emit(Polygon2& cell, double value, std::vector<SunHoursCell>& dest, std::vector<mpq_class>& area,
            bool count_dropped) {
    const mpq_class cell_area = exact_polygon_area(cell);
    area.push_back(abs(cell_area));
    if (write(cell, cell_area, value, dest)) return;
    if (sgn(cell_area) < 0) cell.reverse_orientation();
    std::vector<Polygon2> triangles;
    triangulate_region(PolygonWithHoles2(cell), triangles);
    for (const Polygon2& t : triangles) {
      const mpq_class t_area = exact_polygon_area(t);
      if (!write(t, t_area, value, dest) && count_dropped) dropped_ += abs(t_area);
    }
  }

  bool write(const Polygon2& cell, const mpq_class& cell_area, double value, std::vector<SunHoursCell>& dest) {
    SunHoursCell c;
    c.face_id = r_.face_id;
    c.sun_hours = value;
    c.area = area_3d_mpq(cell_area, scale_);
    for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) c.polygon.push_back(rounded(*v));
    // The chart sees the face clockwise when flipped: restore the face's orientation.
    if (r_.prep->flipped == (sgn(cell_area) > 0)) std::reverse(c.polygon.begin(), c.polygon.end());
    if (!core::clean_double_polygon(c.polygon, r_.prep->axis)) return false;
    dest.push_back(std::move(c));
    return true;
  }

  const OverlayRequest& r_;
  std::unordered_map<CGAL::Handle::Id_type, std::pair<Point2, glm::dvec3>> rounded_;  ///< emit_all's (rounded())
  Strip strip_;
  std::size_t n_;
  mpq_class scale_;  ///< (3D area / chart area)^2, exact
  std::vector<mpq_class> hours_at_;  ///< per walked face (its data)
  std::vector<int> inside_;          ///< per walked face: 1 inside the chart, 0 outside
  std::vector<std::size_t> level_;   ///< per walked face: levels reached
  mpq_class outline_add_{0};         ///< the hours crossing the chart's outline inward adds
  // The threshold map alone (LevelRounds): the edges kept from the last round, the instants fed
  // and not yet swept (in time order: instant, its curves in the strip), their segments and
  // hours, the whole-face hours fed since the last walk, the hours of the instants still to be fed.
  std::vector<XCurve> kept_;
  std::vector<XCurve> frame_;                  ///< a strip's frame, whole
  std::vector<std::pair<Side, Side>> states_;  ///< the kept edges' sides (tags n + 3 + k)
  std::vector<char> fresh_, open_;             ///< per walked face: of an open cell; still open after settle
  std::vector<XCurve> frozen_;                 ///< the level boundaries found so far
  std::vector<mpq_class> frozen_jumps_;        ///< their jumps of value (tags n + 3 + k)
  std::map<mpq_class, long> frozen_index_;
  std::deque<std::pair<std::size_t, std::vector<XCurve>>> pending_;
  std::size_t pending_segments_ = 0;
  mpq_class pending_hours_{0}, base_pending_{0}, unfed_{0};
  std::size_t least_ = 1, rounds_ = 0;
  double want_ = 1;  ///< the new segments the next round takes (at least)
  // With tiles (OverlayRequest::tiles): the counts of the tiles under the strip, the instants fed
  // so far, and the whole-face hours in all and walked so far.
  StripTileCounts counts_;
  PendingBoundaries bounds_;  ///< with tiles: the boundaries of the instants not yet walked, by tile
  std::size_t walked_ = 0;    ///< instants walked
  bool planned_ = false;
  std::deque<std::pair<std::size_t, std::size_t>> plan_;  ///< planned, not yet fed: (order position, instant)
  mpq_class whole_total_{0}, whole_walked_{0};
  mpq_class dropped_{0};             ///< exact chart area of the cells too thin to write
};

StripMap overlay_strip(const OverlayRequest& request, const FaceBoundaries& b, const std::vector<std::size_t>& which,
                       const Strip& strip) {
  StripOverlay overlay(request, strip);
  return overlay.run(b, which);
}

LevelRounds::LevelRounds(const OverlayRequest& request, const Strip& strip, const std::vector<Curve>& outline,
                         const std::vector<std::size_t>& which)
    : request_(&request), strip_(strip), outline_(&outline), outline_which_(which) {}

StripOverlay& LevelRounds::started() {
  if (!impl_) {
    if (!outline_) throw std::logic_error("LevelRounds: used after finish");  // its outline may be gone
    impl_ = std::make_unique<StripOverlay>(*request_, strip_);
    impl_->begin(*outline_, outline_which_);
    outline_which_ = {};
  }
  return *impl_;
}

LevelRounds::~LevelRounds() = default;
LevelRounds::LevelRounds(LevelRounds&&) noexcept = default;
LevelRounds& LevelRounds::operator=(LevelRounds&&) noexcept = default;

void LevelRounds::feed(const std::vector<Curve>& curves, const std::vector<std::size_t>& which, const mpq_class& whole,
                       const mpq_class& unfed) {
  started().feed(curves, which, whole, unfed);
}

void LevelRounds::plan(const std::vector<std::size_t>& order, const std::vector<std::size_t>& band_ends,
                       const std::vector<RoughSegment>& segments, const std::vector<std::size_t>& which,
                       const mpq_class& whole) {
  started().plan(order, band_ends, segments, which, whole);
}

void LevelRounds::feed_planned(const std::vector<Curve>& curves, const std::vector<std::size_t>& which,
                               std::size_t order_end) {
  started().feed_planned(curves, which, order_end);
}

bool LevelRounds::planned() const { return impl_ && impl_->planned(); }

StripMap LevelRounds::finish() {
  StripMap out = started().finish();
  outline_ = nullptr;
  impl_.reset();  // the kept edges and the walk's values go now, not with the face's other strips
  return out;
}

}  // namespace shadow::sunmap
