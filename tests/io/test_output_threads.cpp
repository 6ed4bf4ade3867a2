// SPDX-License-Identifier: GPL-3.0-or-later
// The output files of a large result do not depend on the thread count: report.json's face
// entries are made on every thread (in blocks, written in face order), and the report is written
// on a thread of its own while the VTK files are written on the calling thread. Same bytes at 1, 2 and 4 threads, and report.json
// is exactly nlohmann's dump(2) of its own content (the text the report had when it was one
// document).
#include <shadow/output.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
using shadow::Face;
using shadow::FaceLighting;
using shadow::Light;
using shadow::LightType;
using shadow::Mesh;
using shadow::Scene;
using shadow::ShadowResult;

namespace {

/// `faces` square faces in two meshes (every 7th in a mesh that does not receive), named with
/// text that needs escaping, bytes that are not UTF-8 and a kind on some; three lights (one a
/// sun disk: extended keys); every receiving face lit by each light with areas that have no
/// short decimal form, some faces without area (null azimuth), some with dropped cells.
Scene make_scene(std::size_t faces) {
  Scene scene;
  scene.source = "/data/big \"city\"/scene.json";
  scene.meshes = {Mesh{"blocks", "blocks.obj", 0, 0, true}, Mesh{"trees\t", "", 0, 0, false}};
  for (std::size_t f = 0; f < faces; ++f) {
    Face face;
    const double x = 3.0 * static_cast<double>(f) + 1.0 / 3.0;
    face.vertices = {{x, 0.1, 0.0}, {x + 2.0, 0.1, 0.0}, {x + 2.0, 0.1, 3.0}, {x, 0.1, 3.0}};
    if (f % 97 == 5) face.vertices = {{x, 0, 0}, {x + 1, 0, 0}, {x + 2, 0, 0}};  // no area: null azimuth
    face.mesh = f % 7 == 3 ? 1 : 0;
    face.source = {"blocks.obj", "line " + std::to_string(f + 1)};
    // Sources the report writes from their parts, or through the escaping of the whole: no file,
    // no place, neither, a Windows path, a name with a quote, bytes beyond ASCII, a control byte;
    // files alternating within a block of faces.
    switch (f % 23) {
      case 2: face.source = {"", "line 9"}; break;
      case 4: face.source = {"blocks.obj", ""}; break;
      case 6: face.source = {"", ""}; break;
      case 8: face.source = {"C:\\models\\blocks.obj", "line 3"}; break;
      case 10: face.source = {"the \"old\" blocks.obj", "line 4"}; break;
      case 12: face.source = {"caf\xC3\xA9.obj", "line 5"}; break;
      case 14: face.source = {"blocks.obj", "line\x01 6"}; break;
      case 16: face.source = {"other.obj", "line " + std::to_string(f)}; break;
      default: break;
    }
    if (f % 5 == 0) face.name = "wall \"" + std::to_string(f / 5) + "\"\n\\";
    if (f % 11 == 0) face.name = std::string("caf\xC3\xA9 \xFF") + std::to_string(f);  // é, then a bad byte
    if (f % 3 == 0) face.kind = "WallSurface";
    scene.faces.push_back(face);
  }
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.to_light = {0.4, 0.3, 0.85};
  Light lamp;
  lamp.name = "lamp";
  lamp.type = LightType::Point;
  lamp.position = {1.0, 2.0, 9.5};
  Light disk = sun;
  disk.name = "sun disk";
  disk.angular_diameter = 0.53;
  scene.lights = {sun, lamp, disk};
  scene.warnings.push_back({{"blocks.obj", "line 7"}, "face has a repeated vertex"});
  return scene;
}

ShadowResult make_result(const Scene& scene, bool fast) {
  ShadowResult r;
  r.arithmetic = fast ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (scene.faces[f].mesh == 1) continue;
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
      FaceLighting e;
      e.face_id = f;
      e.light_id = l;
      e.area = 6.0 + 1e-12 * static_cast<double>(f);
      e.lit_area = e.area * (static_cast<double>((f * 7 + l) % 13) / 13.0);
      e.shadow_area = e.area - e.lit_area;
      e.lit_fraction = e.lit_area / e.area;
      e.faces_light = (f + l) % 4 != 0;
      e.lit_area_error_bound = fast ? 1e-9 * static_cast<double>(f % 5) : 0.0;
      if (f % 13 == 1) e.dropped_area = 1e-14 * static_cast<double>(f);
      e.fully_lit_area = e.lit_area / 2;
      e.penumbra_area = e.lit_area / 2;
      e.umbra_area = e.shadow_area;
      r.lighting.push_back(e);
    }
  }
  r.stats.receivers = scene.faces.size();
  return r;
}

std::string report_text(const Scene& scene, const ShadowResult& result, unsigned threads) {
  shadow::RunInfo run;
  run.scene = "scene.json";
  run.started_utc = "2026-11-29T09:00:00Z";
  run.options.threads = threads;
  std::ostringstream out;
  shadow::write_report_json(out, scene, result, run);
  // The run's options name the thread count; nothing else may differ.
  return std::regex_replace(out.str(), std::regex("\"threads\": [0-9]+"), "\"threads\": 0");
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST(ReportThreads, TheSameBytesAtOneTwoAndFourThreadsAndEqualToOneDocumentsDump) {
  // 5,000 faces: several blocks of 1,024 faces and more than one window of blocks at 1 thread.
  const Scene scene = make_scene(5000);
  for (const bool fast : {false, true}) {
    const ShadowResult result = make_result(scene, fast);
    const std::string one = report_text(scene, result, 1);
    EXPECT_EQ(report_text(scene, result, 2), one) << "fast " << fast;
    EXPECT_EQ(report_text(scene, result, 4), one) << "fast " << fast;
    // The text is what nlohmann writes for the whole document, key order kept.
    const nlohmann::ordered_json document = nlohmann::ordered_json::parse(one);
    EXPECT_EQ(document.dump(2) + "\n", one) << "fast " << fast;
    ASSERT_EQ(document["faces"].size(), 5000u - 714u);  // every 7th face (from 3) receives nothing
    EXPECT_EQ(document["faces"][0]["id"], 0);
    EXPECT_EQ(document["faces"].back()["id"], 4999);
    EXPECT_EQ(document["faces"][4]["id"], 5);  // face 3 receives nothing
    EXPECT_TRUE(document["faces"][4]["azimuth"].is_null());  // face 5 has no area
    EXPECT_EQ(document["faces"][0]["lights"].size(), 3u);
    // Whole numbers stay doubles in the text, as nlohmann writes them.
    EXPECT_NE(one.find("\"tilt\": 90.0,\n"), std::string::npos);
    EXPECT_NE(one.find("\"area\": 6.0,\n"), std::string::npos);
    EXPECT_EQ(document["faces"][0]["lights"][2].count("umbra_area"), 1u);
    EXPECT_EQ(document["faces"][0]["lights"][0].count("lit_area_error_bound"), fast ? 1u : 0u);
  }
}

// Beyond one window of blocks at four threads too (a window is 4 x threads blocks of 1,024 faces;
// a writer thread writes one while the threads make the next): the hand-over to the next window.
TEST(ReportThreads, SeveralWindowsAtThreeAndFourThreads) {
  const Scene scene = make_scene(40000);  // 34,286 receiving faces: 34 blocks, three windows at 3 and 4
  const ShadowResult result = make_result(scene, true);
  const std::string one = report_text(scene, result, 1);
  EXPECT_EQ(report_text(scene, result, 3), one);
  EXPECT_EQ(report_text(scene, result, 4), one);
}

/// A stream buffer that takes `room` bytes, then fails every write.
class FullStreamBuffer : public std::streambuf {
 public:
  explicit FullStreamBuffer(std::size_t room) : room_(room) {}

 protected:
  int_type overflow(int_type c) override {
    if (room_ == 0) return traits_type::eof();
    --room_;
    return traits_type::not_eof(c);
  }
  std::streamsize xsputn(const char*, std::streamsize n) override {
    const auto taken = static_cast<std::streamsize>(std::min<std::size_t>(room_, static_cast<std::size_t>(n)));
    room_ -= static_cast<std::size_t>(taken);
    return taken;
  }

 private:
  std::size_t room_;
};

// A caller's stream that throws on failure (exceptions() set) throws to the caller at every
// thread count, also when the face entries are written by the writer thread (it used to end the
// program there: an exception leaving a std::thread calls std::terminate).
TEST(ReportThreads, AFailingStreamThatThrowsThrowsToTheCaller) {
  const Scene scene = make_scene(5000);
  const ShadowResult result = make_result(scene, false);
  for (const unsigned threads : {1u, 2u, 4u}) {
    FullStreamBuffer buffer(100000);  // past the header, within the face entries
    std::ostream out(&buffer);
    out.exceptions(std::ios::badbit | std::ios::failbit);
    shadow::RunInfo run;
    run.options.threads = threads;
    EXPECT_THROW(shadow::write_report_json(out, scene, result, run), std::ios_base::failure) << threads << " threads";
  }
}

TEST(ReportThreads, AReportWithoutFacesIsTheSameAtEveryThreadCount) {
  const Scene scene = make_scene(3);
  const ShadowResult empty;
  const std::string one = report_text(scene, empty, 1);
  EXPECT_EQ(report_text(scene, empty, 4), one);
  EXPECT_NE(one.find("\"faces\": [],\n"), std::string::npos);
}

TEST(ReportThreads, OutputDirectoryWritesTheSameFilesAtOneTwoAndFourThreads) {
  const Scene scene = make_scene(3000);
  const ShadowResult result = make_result(scene, false);
  const fs::path root = fs::temp_directory_path() / ("libshadow-test_output_threads-" + std::to_string(getpid()));
  fs::remove_all(root);
  std::vector<std::vector<std::string>> files;
  for (const unsigned threads : {1u, 2u, 4u}) {
    shadow::RunInfo run;
    run.scene = "scene.json";
    run.started_utc = "2026-11-29T09:00:00Z";
    run.options.threads = threads;
    const fs::path dir = root / std::to_string(threads);
    std::vector<fs::path> written;
    {
      shadow::OutputDirectory output(dir);
      written = output.write(scene, result, &run);
    }
    ASSERT_EQ(written.size(), 6u);
    EXPECT_EQ(written.back().filename(), "report.json");  // placed last
    std::vector<std::string> bytes;
    for (const fs::path& p : written) {
      std::string text = read_bytes(p);
      if (p.filename() == "report.json")
        text = std::regex_replace(text, std::regex("\"threads\": [0-9]+"), "\"threads\": 0");
      bytes.push_back(std::move(text));
    }
    files.push_back(std::move(bytes));
  }
  EXPECT_EQ(files[1], files[0]);
  EXPECT_EQ(files[2], files[0]);
  fs::remove_all(root);
}

// A result whose light ids lie beyond the scene's (a caller's own light, compute(light, id)),
// up to the largest size_t: each is written and summed under its own id, as any other.
TEST(ReportThreads, LightIdsBeyondTheScenesAreWrittenAndSummed) {
  const Scene scene = make_scene(40);
  ShadowResult result = make_result(scene, false);
  result.lighting.erase(std::remove_if(result.lighting.begin(), result.lighting.end(),
                                       [](const FaceLighting& e) { return e.light_id != 0; }),
                        result.lighting.end());
  for (FaceLighting& e : result.lighting) e.light_id = e.face_id % 2 ? 7 : std::numeric_limits<std::size_t>::max();  // (the first: the largest)
  for (const unsigned threads : {1u, 2u}) {
    const std::string text = report_text(scene, result, threads);
    const nlohmann::ordered_json document = nlohmann::ordered_json::parse(text);
    EXPECT_EQ(document.dump(2) + "\n", text);
    const nlohmann::ordered_json& per_light = document["summary"]["per_light"];
    ASSERT_EQ(per_light.size(), 2u) << threads << " threads";
    EXPECT_EQ(per_light[0]["light"], 7u);
    EXPECT_EQ(per_light[1]["light"], std::numeric_limits<std::size_t>::max());
    double area = 0;
    for (const FaceLighting& e : result.lighting)
      if (e.light_id == 7) area += e.area;
    EXPECT_NEAR(per_light[0]["area"].get<double>(), area, 1e-9 * area);
  }
}
