// SPDX-License-Identifier: GPL-3.0-or-later
// shadow::SeriesJob (shadow/series_job.hpp): the `shadow series` job as a library unit. Its table
// against the engine's own compute_series, a stop on the stop flag then a resume (the same
// files as one uninterrupted run), the output directory's lock, two ranks of a world made of
// threads against one rank (the same files), checkpoints and ranks of another scene refused,
// and the progress reports.
#include "support/series_job_files.hpp"

#include <shadow/series_job.hpp>
#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <condition_variable>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;

/// This process's scratch directories, removed when the tests end.
fs::path scratch_root() {
  return fs::temp_directory_path() / ("libshadow-series-job-" + std::to_string(::getpid()));
}

class RemoveScratch : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(scratch_root(), ignored);
  }
};
const auto* const kRemoveScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

/// A fresh directory for one test.
fs::path scratch(const std::string& name) {
  const fs::path dir = scratch_root() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The sun example (a tower, a block and a house on a ground, Berlin) over two June days, one
/// sun per hour (34 instants above the horizon), written into `dir`; `tower_height` changes the
/// scene but not its shape (faces, instants); `map` asks for the house's sun-hours map.
fs::path write_scene(const fs::path& dir, double tower_height = 30, bool map = false) {
  std::ifstream in(fs::path(LIBSHADOW_EXAMPLES_DIR) / "sun" / "scene.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["sun"]["end"] = "2026-06-22";
  for (auto& polygon : scene["meshes"][1]["polygons"])
    for (auto& vertex : polygon)
      if (vertex[2].get<double>() > 0) vertex[2] = tower_height;
  if (map) scene["sun_hours_map"] = {"house"};
  const fs::path file = dir / "scene.json";
  std::ofstream(file) << scene.dump(1);
  return file;
}

shadow::SeriesJobOptions job_options(const fs::path& scene, const fs::path& output) {
  shadow::SeriesJobOptions options;
  options.scene = scene;
  options.output = output;
  options.threads = 1;
  return options;
}

/// The ranks of a world made of threads meet here: each hands in its slot, and once every rank
/// has, each gets all of them (index = rank).
class Rendezvous {
 public:
  struct Slot {
    std::string bytes;
    std::exception_ptr error;
  };
  explicit Rendezvous(int ranks) : ranks_(ranks) {}

  std::vector<Slot> exchange(int rank, Slot mine) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return !draining_; });  // the previous exchange is still read
    if (arrived_ == 0) slots_.assign(static_cast<std::size_t>(ranks_), Slot{});
    slots_[static_cast<std::size_t>(rank)] = std::move(mine);
    if (++arrived_ == ranks_) {
      draining_ = true;
      left_ = ranks_;
      ++generation_;
      changed_.notify_all();
    } else {
      const std::size_t generation = generation_;
      changed_.wait(lock, [&] { return generation_ != generation; });
    }
    std::vector<Slot> all = slots_;
    if (--left_ == 0) {
      draining_ = false;
      arrived_ = 0;
      changed_.notify_all();
    }
    return all;
  }

 private:
  int ranks_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Slot> slots_;
  int arrived_ = 0, left_ = 0;
  bool draining_ = false;
  std::size_t generation_ = 0;
};

/// One rank of a world whose ranks are threads of this process.
class ThreadWorld final : public shadow::SeriesWorld {
 public:
  ThreadWorld(Rendezvous& meeting, int rank, int size) : meeting_(meeting), rank_(rank), size_(size) {}
  [[nodiscard]] int rank() const override { return rank_; }
  [[nodiscard]] int size() const override { return size_; }
  void agree(std::exception_ptr error) override {
    for (const Rendezvous::Slot& slot : meeting_.exchange(rank_, {"", error}))
      if (slot.error) std::rethrow_exception(slot.error);  // the lowest failing rank's
  }
  std::uint64_t max(std::uint64_t value) override {
    std::uint64_t out = 0;
    for (const Rendezvous::Slot& slot : meeting_.exchange(rank_, {std::to_string(value), nullptr}))
      out = std::max<std::uint64_t>(out, std::stoull(slot.bytes));
    return out;
  }
  std::vector<std::string> gather(const std::string& bytes) override {
    std::vector<std::string> out;
    for (Rendezvous::Slot& slot : meeting_.exchange(rank_, {bytes, nullptr})) out.push_back(std::move(slot.bytes));
    if (rank_ != 0) out.clear();
    return out;
  }
  void broadcast(std::string& bytes) override { bytes = meeting_.exchange(rank_, {bytes, nullptr})[0].bytes; }

 private:
  Rendezvous& meeting_;
  int rank_, size_;
};

/// Runs the job on `ranks` threads, rank r with options[r]; each rank's result or error.
struct RankOutcome {
  std::optional<shadow::SeriesJobResult> result;
  std::exception_ptr error;
};
std::vector<RankOutcome> run_ranks(const std::vector<shadow::SeriesJobOptions>& options) {
  const int ranks = static_cast<int>(options.size());
  Rendezvous meeting(ranks);
  std::vector<RankOutcome> outcomes(options.size());
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      ThreadWorld world(meeting, r, ranks);
      try {
        shadow::SeriesJob job(options[static_cast<std::size_t>(r)], world);
        outcomes[static_cast<std::size_t>(r)].result = job.run();
      } catch (...) {
        outcomes[static_cast<std::size_t>(r)].error = std::current_exception();
      }
    });
  for (std::thread& t : threads) t.join();
  return outcomes;
}

TEST(SeriesJob, TableIsTheEnginesSeries) {
  const fs::path dir = scratch("table");
  const fs::path scene_file = write_scene(dir);
  const shadow::SeriesJobResult result = shadow::test::run_series_job(job_options(scene_file, dir / "out"));

  // Independently: the scene's suns through the engine in one call.
  const shadow::Scene scene = shadow::load_scene(scene_file);
  const shadow::SunSeries suns = shadow::sun_series(scene);
  shadow::SeriesOptions options;
  options.threads = 1;
  const shadow::SeriesResult expected = shadow::ShadowEngine(scene, 1).compute_series(suns.lights, options);
  ASSERT_EQ(result.suns.lights.size(), 34u);
  EXPECT_EQ(result.series.faces, expected.faces);
  EXPECT_EQ(result.series.lit_area, expected.lit_area);
  EXPECT_EQ(result.series.lit_fraction, expected.lit_fraction);
  EXPECT_EQ(result.resumed, 0u);
  EXPECT_EQ(result.every, 1u);  // two days: every instant in series.pvd
  ASSERT_FALSE(result.written.empty());
  EXPECT_EQ(result.written.back().filename(), "report.json");  // last: marks a complete run
  EXPECT_TRUE(fs::exists(dir / "out" / "sunlit.csv"));
  EXPECT_FALSE(fs::exists(dir / "out" / "series.checkpoint"));
}

TEST(SeriesJob, StoppedThenResumedWritesTheUninterruptedFiles) {
  const fs::path dir = scratch("resume");
  const fs::path scene_file = write_scene(dir);
  shadow::test::run_series_job(job_options(scene_file, dir / "whole"));

  // Stopped by the flag (as the CLI's signal handler sets it) during the first round.
  std::atomic<int> stop{0};
  shadow::SeriesJobOptions options = job_options(scene_file, dir / "parts");
  options.checkpoint = true;
  options.stop = &stop;
  options.progress = [&](const shadow::SeriesJobProgress& p) {
    if (p.done > 0) stop = 15;
  };
  std::size_t stopped_at = 0;
  try {
    shadow::test::run_series_job(options);
    FAIL() << "the job did not stop";
  } catch (const shadow::SeriesJobStopped& stopped) {
    stopped_at = stopped.done;
    EXPECT_EQ(stopped.signal, 15);
    EXPECT_EQ(stopped.total, 34u);
    EXPECT_EQ(stopped.checkpoint, dir / "parts" / "series.checkpoint");
  }
  EXPECT_EQ(stopped_at, 8u);  // the first round: 4 instants per thread, at least 8
  EXPECT_TRUE(fs::exists(dir / "parts" / "series.checkpoint"));
  EXPECT_FALSE(fs::exists(dir / "parts" / "report.json"));  // incomplete

  options.progress = nullptr;
  stop = 0;
  options.checkpoint = false;
  options.resume = true;
  std::vector<std::string> notices;
  options.notice = [&](const std::string& line) { notices.push_back(line); };
  const shadow::SeriesJobResult resumed = shadow::test::run_series_job(options);
  EXPECT_EQ(resumed.resumed, stopped_at);
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_NE(notices[0].find("resuming from"), std::string::npos) << notices[0];
  EXPECT_NE(notices[0].find("8 of 34 instants done"), std::string::npos) << notices[0];
  EXPECT_FALSE(fs::exists(dir / "parts" / "series.checkpoint"));
  shadow::test::expect_same_files(dir / "whole", dir / "parts", 1);
}

/// The message of the OutputError that `options` fails with while files may grow to `bytes` at
/// most (SIGXFSZ ignored, so that write() fails instead: a full disk), "" when it does not.
std::string output_error_with_small_files(const shadow::SeriesJobOptions& options, rlim_t bytes) {
  // The limit and the ignored signal, undone on every way out (an unexpected exception too).
  struct SmallFiles {
    rlimit old_limit{};
    void (*old_handler)(int) = SIG_DFL;
    bool set = false;
    explicit SmallFiles(rlim_t limit) {
      if (getrlimit(RLIMIT_FSIZE, &old_limit) != 0) return;
      old_handler = std::signal(SIGXFSZ, SIG_IGN);
      rlimit small = old_limit;
      small.rlim_cur = limit;
      set = setrlimit(RLIMIT_FSIZE, &small) == 0;
    }
    ~SmallFiles() {
      setrlimit(RLIMIT_FSIZE, &old_limit);
      std::signal(SIGXFSZ, old_handler);
    }
  } small(bytes);
  if (!small.set) return "setrlimit failed";
  try {
    shadow::test::run_series_job(options);
  } catch (const shadow::OutputError& e) {
    return e.what();
  }
  return "";
}

TEST(SeriesJob, AFullDiskWhileARoundIsWrittenBehindIsOneOutputErrorAndLeavesNoOutputs) {
  // Each round's files are written while the next computes, so the write fails on the writer's
  // thread, and its error must stop the job as an in-line write's did: found when a round is to
  // start (rounds of one instant), or after the last round (one round of every instant).
  const fs::path dir = scratch("full");
  const fs::path scene_file = write_scene(dir);
  for (const std::size_t round_cells : {std::size_t{1}, std::size_t{1} << 21}) {
    const fs::path out = dir / ("out-" + std::to_string(round_cells));
    shadow::SeriesJobOptions options = job_options(scene_file, out);
    options.keep_table = false;
    options.round_cells = round_cells;
    const std::string message = output_error_with_small_files(options, 4096);  // past the headers
    ASSERT_FALSE(message.empty()) << "expected an OutputError";
    EXPECT_EQ(message.find(out.string()), 0u) << message;
    EXPECT_NE(message.find(std::strerror(EFBIG)), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(out / "report.json"));
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(out))
      EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << "left behind: " << e.path();
    // The same job with room writes every file.
    options.output = dir / ("room-" + std::to_string(round_cells));
    EXPECT_NO_THROW(shadow::test::run_series_job(options));
    EXPECT_TRUE(fs::exists(options.output / "report.json"));
  }
}

TEST(SeriesJob, SecondJobOnTheSameDirectoryIsRefused) {
  const fs::path dir = scratch("lock");
  const fs::path scene_file = write_scene(dir);
  shadow::SeriesJobOptions first = job_options(scene_file, dir / "out");
  std::string refused;
  bool tried = false;
  // While the first job computes (it holds the directory), a second one starts on it.
  first.progress = [&](const shadow::SeriesJobProgress&) {
    if (tried) return;
    tried = true;
    try {
      shadow::test::run_series_job(job_options(scene_file, dir / "out"));
    } catch (const shadow::OutputError& e) {
      refused = e.what();
    }
  };
  const shadow::SeriesJobResult result = shadow::test::run_series_job(first);
  EXPECT_TRUE(tried);
  EXPECT_NE(refused.find("another shadow process is writing to this directory"), std::string::npos) << refused;
  EXPECT_EQ(result.series.instants, 34u);  // the first job finished undisturbed
  EXPECT_TRUE(fs::exists(dir / "out" / "report.json"));
  // Once the first job is done, the directory is free again.
  EXPECT_NO_THROW(shadow::test::run_series_job(job_options(scene_file, dir / "out")));
}

TEST(SeriesJob, TwoRanksWriteWhatOneRankWrites) {
  const fs::path dir = scratch("ranks");
  const fs::path scene_file = write_scene(dir, 30, true);
  shadow::SeriesJobOptions one = job_options(scene_file, dir / "one");
  one.fragments = true;
  const shadow::SeriesJobResult single = shadow::test::run_series_job(one);
  ASSERT_TRUE(single.map);
  ASSERT_FALSE(single.map->cells.empty());

  std::vector<shadow::SeriesJobOptions> options(2, job_options(scene_file, dir / "two"));
  std::vector<std::size_t> reports(2, 0);
  for (std::size_t r = 0; r < 2; ++r) {
    options[r].fragments = true;
    options[r].checkpoint = true;  // rounds of 8, gathered after each
    options[r].progress = [&reports, r](const shadow::SeriesJobProgress&) { ++reports[r]; };
  }
  const std::vector<RankOutcome> outcomes = run_ranks(options);
  for (const RankOutcome& o : outcomes) {
    if (o.error) std::rethrow_exception(o.error);
    ASSERT_TRUE(o.result);
    EXPECT_EQ(o.result->ranks, 2);
  }
  EXPECT_GT(reports[0], 0u);
  EXPECT_EQ(reports[1], 0u);  // rank 0 reports for all
  const shadow::SeriesJobResult& root = *outcomes[0].result;
  EXPECT_EQ(root.series.lit_area, single.series.lit_area);
  EXPECT_TRUE(outcomes[1].result->written.empty());  // rank 0 writes
  ASSERT_TRUE(root.map);
  EXPECT_EQ(root.map->regions, single.map->regions);
  shadow::test::expect_same_files(dir / "one", dir / "two", 1);
}

TEST(SeriesJob, CheckpointOfAnotherSceneIsRefused) {
  const fs::path dir = scratch("digest");
  const fs::path scene_file = write_scene(dir);
  shadow::SeriesJobOptions options = job_options(scene_file, dir / "out");
  options.stop_after = 8;
  EXPECT_THROW(shadow::test::run_series_job(options), shadow::SeriesJobStopped);
  // The same shape (faces, instants), another tower: the checkpoint's digest does not match.
  const fs::path other = write_scene(dir / "..", 31);
  options = job_options(other, dir / "out");
  options.resume = true;
  try {
    shadow::test::run_series_job(options);
    FAIL() << "a checkpoint of another scene was used";
  } catch (const shadow::InputError& e) {
    EXPECT_NE(e.problem().find("another scene or other options"), std::string::npos) << e.what();
    EXPECT_EQ(e.where().file, (dir / "out" / "series.checkpoint").string());
  }
  EXPECT_TRUE(fs::exists(dir / "out" / "series.checkpoint"));  // kept: the right scene may resume it
  options = job_options(scene_file, dir / "out");
  options.resume = true;
  EXPECT_EQ(shadow::test::run_series_job(options).resumed, 8u);
}

TEST(SeriesJob, RankThatReadAnotherSceneStopsEveryRank) {
  const fs::path dir = scratch("ranks-digest");
  std::vector<shadow::SeriesJobOptions> options{job_options(write_scene(dir), dir / "out"),
                                                job_options(write_scene(dir / "..", 31), dir / "out")};
  const std::vector<RankOutcome> outcomes = run_ranks(options);
  for (const RankOutcome& o : outcomes) {
    ASSERT_TRUE(o.error);
    try {
      std::rethrow_exception(o.error);
    } catch (const shadow::InputError& e) {
      EXPECT_NE(e.problem().find("another scene or period than rank 0"), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(fs::exists(dir / "out" / "report.json"));
}

TEST(SeriesJob, ReportsProgressOfInstantsAndMapFaces) {
  const fs::path dir = scratch("progress");
  shadow::SeriesJobOptions options = job_options(write_scene(dir, 30, true), dir / "out");
  options.checkpoint = true;  // the map after the instants (the shared order: below)
  std::vector<shadow::SeriesJobProgress> instants, faces;
  std::vector<shadow::SeriesJobStage> stages;
  options.progress = [&](const shadow::SeriesJobProgress& p) {
    (p.part == shadow::SeriesJobProgress::Part::Instants ? instants : faces).push_back(p);
  };
  options.stage = [&](shadow::SeriesJobStage s) { stages.push_back(s); };
  const shadow::SeriesJobResult result = shadow::test::run_series_job(options);
  ASSERT_GE(instants.size(), 3u);
  EXPECT_EQ(instants.front().done, 0u);  // the start
  EXPECT_FALSE(instants.front().finished);
  for (std::size_t i = 1; i < instants.size(); ++i) {
    EXPECT_GE(instants[i].done, instants[i - 1].done);
    EXPECT_EQ(instants[i].total, 34u);
  }
  EXPECT_TRUE(instants.back().finished);
  EXPECT_EQ(instants.back().done, 34u);
  ASSERT_GE(faces.size(), 2u);
  EXPECT_TRUE(faces.back().finished);
  EXPECT_EQ(faces.back().done, result.map->faces.size());
  using S = shadow::SeriesJobStage;
  EXPECT_EQ(stages, (std::vector<S>{S::Loading, S::Preparing, S::Computing, S::Mapping, S::Writing}));
}

// In an exact series on one process the map runs first and its pass computes its receiving
// faces' lit areas for the series too (SunHoursOptions::series_table): every file as in the
// other order (share_map_pass = false: the instants, then the map), report.json but for its
// counters (which count the pass that ran); the rows' pairs counted once; a mapped mesh that is
// no receiver is no row. Also with the table not kept (as `shadow series` runs); a checkpointed
// run (never shared) stopped in the rounds and resumed writes the same files.
TEST(SeriesJob, MapThatSharesItsPassWritesTheSameFiles) {
  const fs::path dir = scratch("shared_map");
  const fs::path scene_file = write_scene(dir, 30, true);
  {  // the block mapped too; the house mapped but not a receiver
    nlohmann::json scene = nlohmann::json::parse(std::ifstream(scene_file));
    scene["sun_hours_map"] = {"house", "block"};
    scene["receivers"] = {"ground", "tower", "block"};
    std::ofstream(scene_file) << scene.dump(1);
  }
  auto report_without_counters = [](const fs::path& out) {
    nlohmann::json report = nlohmann::json::parse(std::ifstream(out / "report.json"));
    report.erase("stats");
    report["run"].erase("started_utc");
    return report;
  };
  for (const bool levels_only : {false, true}) {
    const std::string tag = levels_only ? "levels" : "full";
    std::vector<shadow::SeriesJobProgress::Part> parts;
    std::vector<shadow::SeriesJobStage> stages;
    shadow::SeriesJobOptions options = job_options(scene_file, dir / (tag + "_shared"));
    options.sun_hours_levels = {2, 5};
    options.sun_hours_levels_only = levels_only;
    options.keep_table = !levels_only;
    options.progress = [&](const shadow::SeriesJobProgress& p) { parts.push_back(p.part); };
    options.stage = [&](shadow::SeriesJobStage stage) { stages.push_back(stage); };
    const shadow::SeriesJobResult shared = shadow::test::run_series_job(options);
    ASSERT_FALSE(parts.empty());
    EXPECT_EQ(parts.front(), shadow::SeriesJobProgress::Part::MapFaces) << tag;  // the map came first
    using S = shadow::SeriesJobStage;
    EXPECT_EQ(stages, (std::vector<S>{S::Loading, S::Preparing, S::Computing, S::Mapping, S::Computing, S::Writing}));
    options.progress = nullptr;
    options.stage = nullptr;
    options.output = dir / (tag + "_apart");
    options.share_map_pass = false;
    const shadow::SeriesJobResult apart = shadow::test::run_series_job(options);
    shadow::test::expect_same_files(dir / (tag + "_shared"), dir / (tag + "_apart"), 5, {"report.json"});
    EXPECT_EQ(report_without_counters(dir / (tag + "_shared")), report_without_counters(dir / (tag + "_apart"))) << tag;
    EXPECT_EQ(shared.series.lit_area, apart.series.lit_area) << tag;
    EXPECT_EQ(shared.series.lit_fraction, apart.series.lit_fraction) << tag;
    EXPECT_EQ(shared.series.faces_light, apart.series.faces_light) << tag;
    // Every row's pairs counted once: neither twice (the rounds and the map's pass) nor the
    // house's (mapped, no row).
    EXPECT_EQ(shared.series.stats.receivers, shared.series.faces.size() * 34) << tag;
    EXPECT_EQ(shared.series.stats.receivers, apart.series.stats.receivers) << tag;
    ASSERT_TRUE(shared.map && apart.map);
    EXPECT_EQ(shadow::sun_hours_level_areas(*shared.map), shadow::sun_hours_level_areas(*apart.map)) << tag;
    EXPECT_GT(shared.map_seconds, 0.0);

    // Checkpointed: the map after the instants (each record holds every row's values and
    // counters), stopped after the first round, then resumed: the shared run's files.
    options.output = dir / (tag + "_resumed");
    options.share_map_pass = true;
    options.stop_after = 8;
    parts.clear();
    options.progress = [&](const shadow::SeriesJobProgress& p) { parts.push_back(p.part); };
    EXPECT_THROW(shadow::test::run_series_job(options), shadow::SeriesJobStopped) << tag;
    ASSERT_FALSE(parts.empty());
    EXPECT_EQ(parts.front(), shadow::SeriesJobProgress::Part::Instants) << tag;  // not shared
    options.progress = nullptr;
    options.stop_after = 0;
    options.resume = true;
    const shadow::SeriesJobResult resumed = shadow::test::run_series_job(options);
    EXPECT_EQ(resumed.resumed, 8u) << tag;
    EXPECT_EQ(resumed.series.stats.receivers, resumed.series.faces.size() * 34) << tag;
    shadow::test::expect_same_files(dir / (tag + "_shared"), dir / (tag + "_resumed"), 5, {"report.json"});
    EXPECT_EQ(report_without_counters(dir / (tag + "_shared")), report_without_counters(dir / (tag + "_resumed")))
        << tag;
  }
}

TEST(SeriesJob, DefaultEveryBoundsTheFilesOfLongPeriods) {
  std::vector<std::int64_t> week{0, 7 * 86400}, year{0, 365 * 86400};
  EXPECT_EQ(shadow::default_series_every(100, week), 1u);  // up to 7 days: every instant
  EXPECT_EQ(shadow::default_series_every(4400, year), 92u);  // ceil(4400 / 48)
  EXPECT_EQ(shadow::default_series_every(40, year), 1u);
}

}  // namespace
