// SPDX-License-Identifier: GPL-3.0-or-later
// The series files streamed as the instants complete (docs/series.md, "Streaming"): a job in
// rounds of a few instants that keeps no table writes byte for byte what the whole table
// written at once gives; its summaries are the whole-table functions' (sun_hours,
// surface_series, object_sun_hours) bit for bit; a stream fed in any order writes the same
// files; a job stopped mid-stream leaves no temporaries and resumes to the same files.
#include "support/series_job_files.hpp"

#include <shadow/series_job.hpp>
#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

fs::path scratch_root() { return fs::temp_directory_path() / ("libshadow-series-stream-" + std::to_string(::getpid())); }

class RemoveScratch : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(scratch_root(), ignored);
  }
};
const auto* const kRemoveScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

fs::path scratch(const std::string& name) {
  const fs::path dir = scratch_root() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The sun example over two June days (34 instants above the horizon), with two faces of the
/// block named alike (a surface of two faces) and energyplus-shading.csv asked for.
fs::path write_scene(const fs::path& dir) {
  std::ifstream in(fs::path(LIBSHADOW_EXAMPLES_DIR) / "sun" / "scene.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["sun"]["end"] = "2026-06-22";
  scene["energyplus_shading"] = true;
  const fs::path file = dir / "scene.json";
  std::ofstream(file) << scene.dump(1);
  return file;
}

shadow::SeriesJobOptions job_options(const fs::path& scene, const fs::path& output) {
  shadow::SeriesJobOptions options;
  options.scene = scene;
  options.output = output;
  options.threads = 1;
  options.every = 1;
  return options;
}

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// The whole table of the scene's suns, one compute_series call, and its files written at once.
struct Whole {
  shadow::Scene scene;
  shadow::SunSeries suns;
  shadow::SeriesResult table;
};

Whole whole_table(const fs::path& scene_file) {
  Whole w;
  w.scene = shadow::load_scene(scene_file);
  w.suns = shadow::sun_series(w.scene);
  shadow::SeriesOptions options;
  options.threads = 1;
  w.table = shadow::ShadowEngine(w.scene, 1).compute_series(w.suns.lights, options);
  return w;
}

TEST(SeriesStream, JobInRoundsWithoutTheTableWritesTheWholeTablesFiles) {
  const fs::path dir = scratch("rounds");
  const fs::path scene_file = write_scene(dir);
  const Whole w = whole_table(scene_file);
  ASSERT_EQ(w.table.instants, 34u);
  {
    shadow::OutputDirectory out(dir / "whole");
    shadow::OutputDirectory::SeriesFiles files;
    files.every = 1;
    out.write_series(w.scene, w.suns, w.table, files);
  }
  shadow::SeriesJobOptions options = job_options(scene_file, dir / "streamed");
  options.keep_table = false;
  // Rounds of 3 instants, 12 of them (one process: a round is written while the next computes,
  // so a round takes half of round_cells).
  options.round_cells = 6 * w.table.faces.size();
  std::size_t reports = 0;
  options.progress = [&](const shadow::SeriesJobProgress&) { ++reports; };
  const shadow::SeriesJobResult result = shadow::test::run_series_job(options);
  EXPECT_GE(reports, 12u);
  EXPECT_TRUE(result.series.lit_area.empty());  // no table kept
  EXPECT_EQ(result.series.faces, w.table.faces);
  EXPECT_EQ(result.series.stats.casting_pairs, w.table.stats.casting_pairs);
  EXPECT_TRUE(fs::exists(dir / "streamed" / "energyplus-shading.csv"));
  // report.json's run differs (a job names its scene and options): compare it apart.
  fs::remove(dir / "whole" / "report.json");
  fs::rename(dir / "streamed" / "report.json", dir / "streamed.report.json");
  shadow::test::expect_same_files(dir / "whole", dir / "streamed", 16, {"energyplus-objects.idf"});

  // The same job keeping the table: the same files, and the table is the whole one.
  options.output = dir / "kept";
  options.keep_table = true;
  const shadow::SeriesJobResult kept = shadow::test::run_series_job(options);
  EXPECT_EQ(kept.series.lit_area, w.table.lit_area);
  EXPECT_EQ(kept.series.lit_fraction, w.table.lit_fraction);
  EXPECT_EQ(read_file(dir / "kept" / "report.json").size(), read_file(dir / "streamed.report.json").size());
  fs::remove(dir / "kept" / "report.json");
  shadow::test::expect_same_files(dir / "streamed", dir / "kept", 16, {"energyplus-objects.idf"});
}

TEST(SeriesStream, SummariesAreTheWholeTableFunctionsBitForBit) {
  // EnergyPlus's model: walls cut around their windows are surfaces of several faces.
  const fs::path dir = scratch("sums");
  shadow::SeriesJobOptions options =
      job_options(fs::path(LIBSHADOW_EXAMPLES_DIR) / "energyplus" / "box-office.idf", dir / "out");
  options.from = "2026-06-21";
  options.to = "2026-06-22";
  options.keep_table = false;
  options.round_cells = 64;  // rounds of a few instants
  const shadow::SeriesJobResult result = shadow::test::run_series_job(options);
  Whole w;
  w.scene = result.scene;
  w.suns = result.suns;
  shadow::SeriesOptions whole;
  whole.threads = 1;
  w.table = shadow::ShadowEngine(w.scene, 1).compute_series(w.suns.lights, whole);
  ASSERT_GT(w.table.instants, 20u);
  ASSERT_GT(64 / w.table.faces.size(), 0u);
  ASSERT_LT(64 / w.table.faces.size(), w.table.instants / 4);

  const double hours = w.suns.hours_per_instant;
  const std::vector<double> sun_hours = shadow::sun_hours(w.table, hours);
  const shadow::SurfaceSeries surfaces = shadow::surface_series(w.scene, w.table, hours);
  const shadow::ObjectSunHours objects = shadow::object_sun_hours(w.scene, w.table, hours);
  EXPECT_TRUE(std::any_of(surfaces.surfaces.begin(), surfaces.surfaces.end(),
                          [](const shadow::NamedSurface& s) { return s.faces.size() > 1; }));
  // report.json is written a member and a face at a time: the text nlohmann writes for the whole
  // document, key order kept.
  const std::string text = read_file(dir / "out" / "report.json");
  EXPECT_EQ(nlohmann::ordered_json::parse(text).dump(2) + "\n", text);
  const nlohmann::json report = nlohmann::json::parse(text);
  // JSON numbers are written in the shortest form that reads back to the same double.
  ASSERT_EQ(report["faces"].size(), w.table.faces.size());
  for (std::size_t r = 0; r < w.table.faces.size(); ++r)
    EXPECT_EQ(report["faces"][r]["sun_hours"].get<double>(), sun_hours[r]) << "face row " << r;
  ASSERT_EQ(report["series"]["surfaces"].size(), surfaces.surfaces.size());
  for (std::size_t s = 0; s < surfaces.surfaces.size(); ++s)
    EXPECT_EQ(report["series"]["surfaces"][s]["sun_hours"].get<double>(), surfaces.sun_hours[s]);
  ASSERT_EQ(report["series"]["objects"].size(), objects.objects.size());
  for (std::size_t o = 0; o < objects.objects.size(); ++o) {
    EXPECT_EQ(report["series"]["objects"][o]["sunlit_area_hours"].get<double>(), objects.sunlit_area_hours[o]);
    EXPECT_EQ(report["series"]["objects"][o]["sun_hours"].get<double>(), objects.sun_hours[o]);
  }
  // sunlit.csv: every instant's row, each surface's fraction as surface_series() gives it.
  std::ifstream csv(dir / "out" / "sunlit.csv");
  std::string line;
  std::getline(csv, line);  // the header
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::stringstream fields(line);
    std::string field;
    std::getline(fields, field, ',');  // the time
    EXPECT_EQ(field, shadow::format_iso8601_utc(w.suns.times[rows]));
    for (std::size_t s = 0; s < surfaces.surfaces.size(); ++s) {
      ASSERT_TRUE(std::getline(fields, field, ','));
      EXPECT_EQ(std::strtod(field.c_str(), nullptr), surfaces.lit_fraction[s * surfaces.instants + rows])
          << "instant " << rows << " surface " << s;
    }
    ++rows;
  }
  EXPECT_EQ(rows, w.table.instants);
}

TEST(SeriesStream, InstantsInAnyOrderWriteTheSameFiles) {
  const fs::path dir = scratch("order");
  const Whole w = whole_table(write_scene(dir));
  shadow::OutputDirectory::SeriesFiles files;
  files.every = 2;
  {
    shadow::OutputDirectory out(dir / "in-order");
    out.write_series(w.scene, w.suns, w.table, files);
  }
  std::vector<std::size_t> order(w.table.instants);
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), std::mt19937(20261129));
  {
    shadow::OutputDirectory out(dir / "shuffled");
    shadow::SeriesFileStream stream = out.stream_series(w.scene, w.suns, w.table, files);
    for (std::size_t i : order) stream.add(i, shadow::SeriesColumn::of(w.table, i));
    EXPECT_EQ(stream.written(), w.table.instants);
    EXPECT_THROW(stream.add(order[0], shadow::SeriesColumn::of(w.table, order[0])), std::logic_error);
    stream.finish();
    const shadow::SurfaceSeries sums = shadow::surface_series(w.scene, w.table, w.suns.hours_per_instant);
    EXPECT_EQ(stream.surfaces().sun_hours, sums.sun_hours);
    EXPECT_EQ(stream.surfaces().area, sums.area);
  }  // the directory's lock goes
  shadow::test::expect_same_files(dir / "in-order", dir / "shuffled", 16, {"energyplus-objects.idf"});

  // An instant missing: no file is put in place, and no temporary stays behind.
  shadow::OutputDirectory gap(dir / "gap");
  {
    shadow::SeriesFileStream unfinished = gap.stream_series(w.scene, w.suns, w.table, files);
    for (std::size_t i = 1; i < w.table.instants; ++i) unfinished.add(i, shadow::SeriesColumn::of(w.table, i));
    EXPECT_EQ(unfinished.written(), 0u);
    EXPECT_THROW(unfinished.finish(), std::logic_error);
  }
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir / "gap"))
    EXPECT_TRUE(e.is_directory() || e.path().filename() == ".shadow.lock") << e.path();
}

// report.json, written a member and a face at a time, is the whole document's dump(2): with a
// face name holding a bad byte (replaced, as compute's report does) and text that needs escaping,
// and with no receiving face at all (an empty faces array).
TEST(SeriesStream, ReportIsTheWholeDocumentsTextWithBadBytesAndWithNoFaces) {
  const fs::path dir = scratch("report-text");
  Whole w = whole_table(write_scene(dir));
  ASSERT_GE(w.table.faces.size(), 2u);
  w.scene.faces[w.table.faces[0]].name = std::string("caf\xC3\xA9 \xFF");  // e-acute, then a bad byte
  w.scene.faces[w.table.faces[1]].name = "wall \"1\"\t\\";
  {
    shadow::OutputDirectory out(dir / "named");
    out.write_series(w.scene, w.suns, w.table, shadow::OutputDirectory::SeriesFiles{});
  }
  const std::string text = read_file(dir / "named" / "report.json");
  const nlohmann::ordered_json document = nlohmann::ordered_json::parse(text);
  EXPECT_EQ(document.dump(2) + "\n", text);
  EXPECT_EQ(document["faces"][0]["name"], "caf\xC3\xA9 \xEF\xBF\xBD");  // U+FFFD for the bad byte
  EXPECT_EQ(document["faces"][1]["name"], "wall \"1\"\t\\");

  Whole none = whole_table(write_scene(dir));
  for (shadow::Mesh& m : none.scene.meshes) m.receiver = false;
  shadow::SeriesOptions options;
  options.threads = 1;
  none.table = shadow::ShadowEngine(none.scene, 1).compute_series(none.suns.lights, options);
  ASSERT_TRUE(none.table.faces.empty());
  {
    shadow::OutputDirectory out(dir / "none");
    out.write_series(none.scene, none.suns, none.table, shadow::OutputDirectory::SeriesFiles{});
  }
  const std::string empty = read_file(dir / "none" / "report.json");
  EXPECT_EQ(nlohmann::ordered_json::parse(empty).dump(2) + "\n", empty);
  EXPECT_NE(empty.find("\"faces\": [],\n"), std::string::npos);
}

TEST(SeriesStream, StoppedMidStreamLeavesNoTemporariesAndResumesToTheSameFiles) {
  const fs::path dir = scratch("resume");
  const fs::path scene_file = write_scene(dir);
  const std::size_t rows = whole_table(scene_file).table.faces.size();
  shadow::SeriesJobOptions whole = job_options(scene_file, dir / "whole");
  whole.keep_table = false;
  shadow::test::run_series_job(whole);

  shadow::SeriesJobOptions options = job_options(scene_file, dir / "parts");
  options.keep_table = false;
  options.round_cells = 6 * rows;  // rounds of 3 (a round takes half: the next computes while it is written)
  options.stop_after = 7;          // stops after the third round: 9 instants streamed
  try {
    shadow::test::run_series_job(options);
    FAIL() << "the job did not stop";
  } catch (const shadow::SeriesJobStopped& stopped) {
    EXPECT_EQ(stopped.done, 9u);
  }
  EXPECT_FALSE(fs::exists(dir / "parts" / "report.json"));
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir / "parts")) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << "a temporary stayed behind: " << e.path();
  }
  options.stop_after = 0;
  options.resume = true;
  options.round_cells = 8 * rows;  // other rounds (of 4) on resuming: the same files
  const shadow::SeriesJobResult resumed = shadow::test::run_series_job(options);
  EXPECT_EQ(resumed.resumed, 9u);
  EXPECT_FALSE(fs::exists(dir / "parts" / "series.checkpoint"));
  shadow::test::expect_same_files(dir / "whole", dir / "parts", 16, {"energyplus-objects.idf"});
}

}  // namespace
