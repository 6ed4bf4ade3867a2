// SPDX-License-Identifier: GPL-3.0-or-later
// ShadowEngine::Impl::compute_rounds: the one scheduler of compute() and compute_series().
//
// Round one takes every work item whole, in runs of engine_detail::kRun consecutive items (the
// receivers of a box share their casters, which the worker then still has). An item whose
// receiver has more candidates than the tile threshold (a large city's ground) is not computed
// there: it waits for round two, where every tile of every such receiver is one work item, so
// that no thread waits at the end for one long receiver (docs/tiles.md).
#include "engine/engine_impl.hpp"

#include <algorithm>
#include <chrono>
#include <mutex>

namespace shadow {

ShadowEngine::Impl::RoundsDone ShadowEngine::Impl::compute_rounds(
    std::size_t count, const std::function<WorkItem(std::size_t)>& describe, const ItemMode& mode,
    std::vector<ThreadState>& workers, const ExactLightSlot& exact_light,
    const std::function<void(std::size_t, Item&)>& finish, const RoundProgress& progress) const {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  struct Pending {
    std::size_t index;
    Item item;  // its split_candidates, then the merged result
  };
  std::vector<Pending> pending;
  std::mutex pending_mutex;
  engine_detail::FirstRound first_round(count);
  std::function<void(std::size_t)> report_runs;
  if (progress.first) report_runs = [&](std::size_t runs) { progress.first(first_round.done(runs)); };
  std::vector<engine_detail::SpanTimer> timers(workers.size());
  runtime::parallel_for_blocks(
      count, engine_detail::kRun, static_cast<unsigned>(workers.size()),
      [&](unsigned wi, std::size_t, std::size_t begin, std::size_t end) {
        ThreadState& w = workers[wi];
        engine_detail::SpanTimer& timer = timers[wi];
        timer.block_started();
        for (std::size_t i = begin; i < end; ++i) {
          const WorkItem work = describe(i);
          Item out = compute_item(w, exact_light(wi, work.light_slot), work.face, work.light_id, *work.light, work.grid,
                                  mode, nullptr, w.stats);
          timer.item_done();
          if (out.split_candidates > 0) {  // tiled after the other items
            first_round.split.fetch_add(1);
            std::lock_guard<std::mutex> lock(pending_mutex);
            pending.push_back({i, std::move(out)});
            continue;
          }
          finish(i, out);
        }
      },
      report_runs, [&](unsigned wi) { timers[wi].leave(workers[wi].stats); });
  RoundsDone done;
  done.split = pending.size();
  const auto tiles_start = Clock::now();
  done.first_seconds = std::chrono::duration<double>(tiles_start - start).count();
  if (pending.empty()) return done;

  // In item order: the tiles, and so the merged results, do not depend on the threads.
  std::sort(pending.begin(), pending.end(), [](const Pending& a, const Pending& b) { return a.index < b.index; });
  std::vector<SplitReceiver> splits;
  for (Pending& p : pending) {
    const WorkItem work = describe(p.index);
    splits.push_back({work.face, work.light_id, work.light, work.grid, work.light_slot, &p.item});
  }
  std::function<void(std::size_t, std::size_t)> report_tiles;
  if (progress.tiles)
    report_tiles = [&](std::size_t tiles_done, std::size_t total) { progress.tiles(tiles_done, total, done.split); };
  compute_splits(splits, mode, workers, exact_light, report_tiles);
  for (Pending& p : pending) finish(p.index, p.item);
  done.tile_seconds = std::chrono::duration<double>(Clock::now() - tiles_start).count();
  return done;
}

}  // namespace shadow
