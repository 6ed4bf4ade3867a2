// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: what ShadowEngine prepares once per scene, shared by engine/shadow_engine.cpp
// (one light at a time) and engine/series.cpp (many suns together), and the scheduler both run
// their work items with (engine/rounds.cpp).
#pragma once

#include "core/culling.hpp"
#include "core/convex_solid.hpp"
#include "core/face_prep.hpp"
#include "runtime/parallel.hpp"
#include "core/prepared_scene.hpp"
#include "exact/exact_receiver.hpp"
#include "exact/lazy_geometry.hpp"
#include "fast/fast_receiver.hpp"

#include <shadow/shadows.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <ctime>
#include <functional>
#include <memory>
#include <optional>
#include <vector>
#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace shadow {

struct ShadowEngine::Impl {
  const Scene* scene = nullptr;
  std::vector<core::FacePrep> prep;
  std::vector<double> face_area;
  core::CullScene cull;

  std::vector<core::ConvexSolid> solids;
  std::vector<int> solid_of;  ///< per face: index into solids, or -1
  std::optional<int> chart_least_bit;  ///< core::PreparedScene::chart_least_bit

  /// What the per-receiver computations read (pointers into this).
  [[nodiscard]] core::PreparedScene prepared() const {
    return {scene, &prep, &face_area, &cull, &solids, &solid_of, chart_least_bit};
  }

  /// Per-thread state: the exact engine's and the fast path's, and the counts of both.
  struct ThreadState {
    exact::ExactWorker exact;  // Epeck objects are never shared between threads
    fast::FastWorker fast;         // Arithmetic::Fast: the fast path's scratch state
    ShadowStats stats;
  };

  /// `threads` workers sized for this scene, each sized on its own thread (per-solid stamps and
  /// per-face caches: on a million faces and 16 threads, sizing them one after another was a serial
  /// tenth of a second and more).
  std::vector<ThreadState> make_workers(unsigned threads, bool fast) const;

  /// Frees the workers' caches (exact faces with their lazy numbers), each on its own thread: on
  /// 16 threads, freeing them one worker after another at the end was a serial tail.
  static void release_workers(std::vector<ThreadState>& workers);

  /// Result for one receiving face under one light (fragment_id local to the item).
  using Item = exact::ReceiverResult;

  /// One light's items, one per receiver, in blocks that several threads allocate: a million
  /// items made on one thread (about 170 MiB of first touches) were a serial fifth of a second.
  class ItemTable {
   public:
    ItemTable() = default;
    ItemTable(std::size_t count, unsigned threads) : size_(count) {
      blocks_.resize((count + kBlock - 1) / kBlock);
      runtime::parallel_for_blocks(count, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
        blocks_[b].resize(end - begin);
      });
    }
    Item& operator[](std::size_t r) { return blocks_[r / kBlock][r % kBlock]; }
    const Item& operator[](std::size_t r) const { return blocks_[r / kBlock][r % kBlock]; }
    [[nodiscard]] std::size_t size() const { return size_; }
    /// Frees the items on `threads` threads (a million items' destructors are a serial pass
    /// otherwise); the table is empty after.
    void release(unsigned threads) {
      runtime::parallel_for(blocks_.size(), threads, [&](unsigned, std::size_t b) { std::vector<Item>().swap(blocks_[b]); });
      blocks_.clear();
      size_ = 0;
    }

   private:
    static constexpr std::size_t kBlock = 4096;
    std::vector<std::vector<Item>> blocks_;
    std::size_t size_ = 0;
  };

  /// How a work item is computed: the arithmetic, whether fragments are built, and the tile
  /// threshold of whole receivers (0: never split).
  struct ItemMode {
    bool fast = false;
    bool polygons = false;
    std::size_t split_above = 0;
  };

  /// One work item: receiver f under `light_in` (grid: its light-space grid, or nullptr), or one
  /// tile of it (`tile`: the tile's FacePrep; nullptr for the whole face). A whole receiver with
  /// more candidates than mode.split_above is not computed: the item only says how many
  /// (split_candidates). `exact_light`: this worker's exact form of the light, made on first need.
  Item compute_item(ThreadState& w, std::optional<exact::ExactLight>& exact_light, std::size_t f, std::size_t light_id,
                    const Light& light_in, const core::LightSpaceGrid* grid, const ItemMode& mode,
                    const core::FacePrep* tile, ShadowStats& stats) const;

  /// A receiver under one light that asked to be split (compute_item's split_candidates), and
  /// the item its tiles' merged result goes to.
  struct SplitReceiver {
    std::size_t face = 0;
    std::size_t light_id = 0;
    const Light* light = nullptr;
    const core::LightSpaceGrid* grid = nullptr;
    std::size_t light_slot = 0;  ///< which of a worker's exact lights (exact_light below) it uses
    Item* out = nullptr;
  };

  /// One work item of a round: receiver `face` under one light (`grid`: its light-space grid,
  /// or nullptr), reported as `light_id`; `light_slot` picks the worker's exact light.
  struct WorkItem {
    std::size_t face = 0;
    std::size_t light_id = 0;
    const Light* light = nullptr;
    const core::LightSpaceGrid* grid = nullptr;
    std::size_t light_slot = 0;
  };

  /// A worker's exact form of the light of a slot (made on first need by compute_item).
  using ExactLightSlot = std::function<std::optional<exact::ExactLight>&(unsigned worker, std::size_t slot)>;

  /// How compute_rounds reports (either may be empty): `first(items_done)` during the first
  /// round (the items that asked for tiles not counted), `tiles(done, total, split_items)` in
  /// tiles during the tile round.
  struct RoundProgress {
    std::function<void(std::size_t)> first;
    std::function<void(std::size_t, std::size_t, std::size_t)> tiles;
  };

  /// What compute_rounds did: the items split into tiles and the time of each round.
  struct RoundsDone {
    std::size_t split = 0;
    double first_seconds = 0;
    double tile_seconds = 0;
  };

  /// The engine's scheduler, for compute() (one light, item = receiver) and compute_series() (a
  /// batch of instants, item = (instant, receiver)): the `count` items (describe(i)) whole, in
  /// runs of engine_detail::kRun on every worker; then those with more candidates than
  /// mode.split_above, by tiles (compute_splits). `finish(i, item)` takes item i's result: on the
  /// worker's thread for a whole item, on this thread in ascending i after the tile round for a
  /// split one. The results do not depend on the thread count.
  RoundsDone compute_rounds(std::size_t count, const std::function<WorkItem(std::size_t)>& describe,
                            const ItemMode& mode, std::vector<ThreadState>& workers, const ExactLightSlot& exact_light,
                            const std::function<void(std::size_t, Item&)>& finish,
                            const RoundProgress& progress) const;

  /// Computes the split receivers by tiles, every tile of every receiver one work item, and
  /// merges each receiver's tiles into its item: exact areas summed exactly and rounded once (the
  /// same bits as whole), fast ones summed with their bounds. `exact_light(worker, slot)` is that
  /// worker's exact light for a slot; `progress(done, total)` counts tiles.
  void compute_splits(std::vector<SplitReceiver>& splits, const ItemMode& mode, std::vector<ThreadState>& workers,
                      const ExactLightSlot& exact_light,
                      const std::function<void(std::size_t, std::size_t)>& progress) const;

  void compute_light(const Light& light, std::size_t light_id, const ShadowOptions& options,
                     std::vector<ThreadState>& workers, const std::vector<std::size_t>& receivers,
                     ItemTable& items, std::size_t progress_base, std::size_t progress_total) const;

  /// compute_light for an extended light (Light::is_extended): the centre's lit areas, then the
  /// exact fully-lit, penumbra and umbra regions (arealight/).
  void compute_extended_light(const Light& light, std::size_t light_id, const ShadowOptions& options,
                              std::vector<ThreadState>& workers, const std::vector<std::size_t>& receivers,
                              ItemTable& items, std::size_t progress_base, std::size_t progress_total) const;

  /// Computes `lights` (reported as `light_ids`) on every receiving face.
  ShadowResult run(const std::vector<const Light*>& lights, const std::vector<std::size_t>& light_ids,
                   const ShadowOptions& options) const;

  static ShadowResult assemble(std::vector<ItemTable>& per_light,
                               const std::vector<ThreadState>& workers);
};

namespace engine_detail {

/// CPU time of the calling thread (work items are timed with it: on a shared machine the wall
/// clock would count the other processes' time as the item's).
inline double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Adds one work item's CPU time to `stats`.
inline void count_item(ShadowStats& stats, double seconds) {
  stats.item_seconds += seconds;
  stats.longest_item_seconds = std::max(stats.longest_item_seconds, seconds);
}

/// Work items are handed out in runs of kRun consecutive ones: neighbouring receivers (a box's
/// six faces) share their casters, whose exact faces and caster lists the worker then still has,
/// and the thread's CPU clock is read twice per worker and parallel call (SpanTimer).
inline constexpr std::size_t kRun = 16;

/// Progress that never goes back: `base + done` of `total` handed to `callback` (none when it is
/// empty), a count below one already reported dropped. For one thread only (parallel_for calls
/// its progress on the calling thread).
class ForwardProgress {
 public:
  ForwardProgress(const std::function<void(const Progress&)>& callback, std::size_t base, std::size_t total)
      : callback_(callback), base_(base), total_(total) {}
  explicit operator bool() const { return static_cast<bool>(callback_); }
  void operator()(std::size_t done) {
    if (!callback_ || done < reported_) return;
    reported_ = done;
    callback_(Progress{base_ + done, total_});
  }

 private:
  const std::function<void(const Progress&)>& callback_;
  std::size_t base_, total_;
  std::size_t reported_ = 0;
};

/// The first round of `items` work items, handed out in runs of kRun, some of which ask to be
/// split into tiles (counted in `split`, from any thread): an item that asked counts as done
/// when its tiles are, in the tile round. A split item is known only once its run has begun, so
/// done() can fall behind a value it gave before (ForwardProgress drops those).
struct FirstRound {
  explicit FirstRound(std::size_t item_count) : items(item_count) {}
  /// The items done when `runs` runs are, less those that asked to be split so far.
  [[nodiscard]] std::size_t done(std::size_t runs) const {
    const std::size_t finished = std::min(items, runs * kRun);
    return finished - std::min(finished, split.load());
  }
  std::size_t items;
  std::atomic<std::size_t> split{0};
};

/// A cheap tick count for timing one work item: the time-stamp counter where there is one (a few
/// nanoseconds; the steady clock through the vDSO was 1.5% of a fast year, read once per item
/// of some 2 us), else the steady clock in nanoseconds. Only ratios of differences within one
/// span of one thread are used (an item's ticks over the span's), so the rate does not matter.
inline std::uint64_t item_ticks() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  const auto since = std::chrono::steady_clock::now().time_since_epoch();
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(since).count());
#endif
}

/// Times the work items a thread takes in one parallel call, block after block (runs of
/// receivers): the thread's CPU clock is read when its first block starts and when it leaves the
/// call (`leave`, from parallel_for's `leaving`), since reading it is a system call (about
/// 0.5 us on the 2-core machine, a quarter of a fast receiver's whole item: timing every item
/// made the fast path at a 40 degree sun 1.35 times slower, and reading it at every block's
/// ends was still 2-3% of a fast year). Each item is timed in item_ticks, and the longest one's
/// CPU time is its share of the span's ticks times the span's CPU time (at most the whole: a
/// preempted thread's item is not counted longer than the thread ran). One per worker, used by
/// that worker's thread only.
class alignas(64) SpanTimer {
 public:
  /// A block starts: the span opens on the first (the CPU clock read), and an item's time
  /// starts at the block, not at the end of the worker's last one.
  void block_started() {
    item_start_ = item_ticks();
    if (open_) return;
    open_ = true;
    cpu_start_ = thread_cpu_seconds();
    start_ = item_start_;
  }
  /// An item of the block ends (the next starts).
  void item_done() {
    const std::uint64_t now = item_ticks();
    // (After a move to another core the counter may read lower: that item is not counted.)
    if (now > item_start_) longest_ = std::max(longest_, now - item_start_);
    item_start_ = now;
  }
  /// The worker takes no more blocks: adds the span's CPU time and its longest item to `stats`
  /// (nothing when it took none), and closes it.
  void leave(ShadowStats& stats) {
    if (!open_) return;
    const double cpu = thread_cpu_seconds() - cpu_start_;
    const std::uint64_t now = item_ticks();
    const double span = now > start_ ? static_cast<double>(now - start_) : 0.0;
    // A span that reads as empty (a counter behind the start's, on another core) reports no
    // longest item rather than the whole span.
    const double share = span > 0 ? std::min(1.0, static_cast<double>(longest_) / span) : 0.0;
    stats.item_seconds += cpu;
    stats.longest_item_seconds = std::max(stats.longest_item_seconds, share * cpu);
    open_ = false;
    longest_ = 0;
  }

 private:
  bool open_ = false;
  double cpu_start_ = 0;
  std::uint64_t start_ = 0, item_start_ = 0, longest_ = 0;
};

/// Appends `fragments` (ids local to one item or tile) to `out` with their ids shifted by
/// `next_id`, which then grows by the ids they used: an item's tiles in order, or a result's
/// items in order, numbered as one.
inline void append_renumbered(std::vector<Fragment>& fragments, std::vector<Fragment>& out, std::size_t& next_id) {
  std::size_t used = 0;
  for (Fragment& fragment : fragments) {
    used = std::max(used, fragment.fragment_id + 1);
    fragment.fragment_id += next_id;
    out.push_back(std::move(fragment));
  }
  next_id += used;
}

/// The exact form of a light: a point (w = 1) or a direction at infinity (w = 0).
using exact::to_exact_light;  // exact/lazy_geometry.hpp

/// The exact sign of receiver f's plane at the light (its facing): 0 for a degenerate face; one
/// determinant of the input doubles for an exactly planar face under a directional light (no
/// exact face built: half the receivers of a sun face away from it); else from its exact face.
inline int receiver_side(const core::PreparedScene& ctx, exact::ExactWorker& w, std::size_t f, const Light& light_in,
                         const exact::ExactLight& light) {
  const core::FacePrep& fp = (*ctx.prep)[f];
  if (fp.degenerate) return 0;
  if (fp.exactly_planar && light_in.type == LightType::Directional)
    return exact::directional_facing_sign(ctx.scene->faces[f].vertices, fp, light_in.to_light);
  return CGAL::sign(exact::plane_at_light(w.face(ctx, f), light));
}

/// Whether a directional light's grid should find the solids' outlines (find_outlines), which
/// the solid casts take instead of sorting each solid's points: the fast path's, and the exact
/// engine's where only areas are asked for (`areas_only`; with polygons it builds its hulls with
/// CGAL), and only where a solid may shade several receivers (as many receivers to compute as
/// solids, or more), not for a lone ground under a city (docs/benchmarks.md, the twenty-fourth
/// look). compute() and compute_series() decide alike.
inline bool outlines_pay(Arithmetic arithmetic, bool areas_only, std::size_t receivers, std::size_t solids) {
  return (arithmetic == Arithmetic::Fast || areas_only) && receivers >= solids;
}

/// Work items whose receiver is certainly turned away from its directional light, split off
/// before a round (compute_light and compute_series, areas only): half of a city's faces look
/// away from each sun, and each was a work item of its own. Items are row * count + k for rows
/// < `rows` and k < suns.size(): receiver face_of(row) under sun k (a unit direction to it, or
/// none for a light that is not directional). write(row, k) writes the attached shadow of each
/// pair certainly turned away: what either engine's job gives it (the fast job's first test is
/// this one; the exact engine decides the same side exactly), counted in the workers' stats as
/// a back-facing receiver. `live` gets the other items, in item order. Rows in blocks on every
/// thread (a 10,000-box city's batch on 16 threads is some four million tests), each block's
/// items kept apart, then joined.
template <class FaceOf, class Write>
void split_turned_away(const core::CullScene& cull, std::size_t rows, const std::vector<std::optional<glm::dvec3>>& suns,
                       FaceOf&& face_of, Write&& write, std::vector<std::size_t>& live,
                       std::vector<ShadowEngine::Impl::ThreadState>& workers) {
  constexpr std::size_t kRows = 512;
  const std::size_t count = suns.size();
  std::vector<std::vector<std::size_t>> blocks((rows + kRows - 1) / kRows);
  runtime::parallel_for_blocks(rows, kRows, static_cast<unsigned>(workers.size()),
                               [&](unsigned wi, std::size_t b, std::size_t begin, std::size_t end) {
    std::vector<std::size_t>& block = blocks[b];
    ShadowStats& stats = workers[wi].stats;
    for (std::size_t row = begin; row < end; ++row) {
      const core::CullFace& face = cull.faces[face_of(row)];
      for (std::size_t k = 0; k < count; ++k) {
        if (suns[k] && core::certainly_turned_away(face, *suns[k])) {
          write(row, k);
          ++stats.receivers;
          ++stats.back_facing;
        } else {
          block.push_back(row * count + k);
        }
      }
    }
  });
  live.clear();
  for (const std::vector<std::size_t>& block : blocks) live.insert(live.end(), block.begin(), block.end());
}

/// The scene's receiving faces in increasing order (compute() and compute_series()), found on
/// `threads` threads: each face's mesh is a read of its own record (a million faces: one cache
/// line each, some 20 ms on one thread).
inline std::vector<std::size_t> receiving_faces(const Scene& scene, unsigned threads) {
  constexpr std::size_t kBlock = 16384;
  const std::size_t n = scene.faces.size();
  std::vector<std::vector<std::size_t>> found((n + kBlock - 1) / kBlock);
  runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
      if (scene.is_receiver(f)) found[b].push_back(f);
  });
  if (found.size() == 1) return std::move(found[0]);
  std::vector<std::size_t> receivers;
  std::size_t count = 0;
  for (const std::vector<std::size_t>& block : found) count += block.size();
  receivers.reserve(count);
  for (const std::vector<std::size_t>& block : found) receivers.insert(receivers.end(), block.begin(), block.end());
  return receivers;
}

}  // namespace engine_detail
}  // namespace shadow
