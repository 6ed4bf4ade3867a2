// SPDX-License-Identifier: GPL-3.0-or-later
// A large OBJ text is read in parts on several threads (readers/obj_reader.cpp,
// parse_obj_in_chunks): the same faces, lines and groups as one thread, and the same first
// error, whatever the thread count and wherever the parts are cut. Compared here on generated
// texts cut into parts of 64 bytes and up, with and without errors.
#include "readers/obj_reader.hpp"

#include <shadow/error.hpp>
#include <shadow/input_file.hpp>
#include <shadow/scene_io.hpp>

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace {

struct Outcome {
  std::vector<std::vector<glm::dvec3>> faces;
  std::vector<std::size_t> lines;
  std::vector<std::string> groups;
  std::string error;  // empty: none
};

Outcome parse(const std::string& text, unsigned threads, std::size_t chunk) {
  Outcome o;
  try {
    o.faces = shadow::detail::parse_obj_with_lines(text, "mesh.obj", &o.lines, &o.groups, threads, chunk);
  } catch (const shadow::InputError& e) {
    o.faces.clear();
    o.lines.clear();
    o.groups.clear();
    o.error = e.what();
  }
  return o;
}

/// An OBJ text of about `statements` lines: vertices, faces with positive, negative and v/t/n
/// references, groups, comments, blank and CRLF lines; with `error`, one bad statement of a kind
/// chosen by the seed somewhere in it.
std::string make_obj(std::uint32_t seed, int statements, bool error) {
  std::mt19937 rng(seed);
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
  std::string text = pick(10) == 0 ? "\xEF\xBB\xBF" : "";
  int vertices = 0;
  const int bad_at = error ? pick(statements) : -1;
  for (int s = 0; s < statements; ++s) {
    if (s == bad_at) {
      switch (pick(7)) {
        case 0: text += "v 1 2 x\n"; break;
        case 1: text += "v 1 2\n"; break;
        case 2: text += "f 1 2/ 3\n"; break;
        case 3: text += "f " + std::to_string(vertices + 5) + " 1 2\n"; break;
        case 4: text += "f 0 1 2\n"; break;
        case 5: text += "f 1 2\n"; break;
        default: text += "f -" + std::to_string(vertices + 1) + " zz 1\n"; break;  // range before syntax
      }
      continue;
    }
    const int kind = vertices < 3 ? 0 : pick(10);
    if (kind <= 3) {
      text += "v " + std::to_string(pick(1000)) + "." + std::to_string(pick(100)) + " " + std::to_string(pick(50)) +
              " +" + std::to_string(pick(9)) + (pick(5) == 0 ? " 1.0" : "") + (pick(4) == 0 ? "\r\n" : "\n");
      ++vertices;
    } else if (kind <= 6) {
      text += pick(8) == 0 ? "fo" : "f";
      const int n = 3 + pick(3);
      for (int i = 0; i < n; ++i) {
        const int v = 1 + pick(vertices);
        const std::string ref = pick(3) == 0 ? "-" + std::to_string(vertices - v + 1) : std::to_string(v);
        text += " " + ref + (pick(4) == 0 ? "/1/2" : pick(5) == 0 ? "//3" : "");
      }
      text += pick(6) == 0 ? "  # a comment\n" : "\n";
    } else if (kind == 7) {
      text += (pick(2) == 0 ? "g" : "o") + std::string(pick(4) == 0 ? "" : " part" + std::to_string(pick(20))) +
              (pick(3) == 0 ? " b" : "") + "\n";
    } else if (kind == 8) {
      text += pick(2) == 0 ? "\n" : "# just a comment\n";
    } else {
      text += "vn 0 0 1\nusemtl stone\n";
    }
  }
  return text;
}

void expect_same(const std::string& text, const std::string& what) {
  const Outcome one = parse(text, 1, 1 << 18);
  for (const unsigned threads : {2u, 4u})
    for (const std::size_t chunk : {std::size_t{64}, std::size_t{200}, std::size_t{1000}}) {
      const Outcome many = parse(text, threads, chunk);
      ASSERT_EQ(many.error, one.error) << what << ", " << threads << " threads, parts of " << chunk;
      ASSERT_EQ(many.faces, one.faces) << what;
      ASSERT_EQ(many.lines, one.lines) << what;
      ASSERT_EQ(many.groups, one.groups) << what;
    }
}

}  // namespace

TEST(ObjChunks, ValidTextsGiveTheSameFacesLinesAndGroupsAsOneThread) {
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    const std::string text = make_obj(seed, 400, false);
    expect_same(text, "seed " + std::to_string(seed));
    EXPECT_GT(parse(text, 4, 64).faces.size(), 50u);
  }
}

TEST(ObjChunks, TextsWithAnErrorGiveTheSameFirstErrorAsOneThread) {
  std::size_t errors = 0;
  for (std::uint32_t seed = 100; seed <= 260; ++seed) {
    const std::string text = make_obj(seed, 300, true);
    expect_same(text, "seed " + std::to_string(seed));
    errors += parse(text, 1, 1 << 18).error.empty() ? 0 : 1;
  }
  EXPECT_GT(errors, 150u);  // nearly every injected statement is an error
}

TEST(ObjChunks, TwoErrorsInDifferentPartsReportTheFirst) {
  std::string text;
  for (int i = 0; i < 200; ++i) text += "v " + std::to_string(i) + " 0 0\n";
  text += "f 1 2 999\n";  // line 201: out of range
  for (int i = 0; i < 200; ++i) text += "f 1 2 3\n";
  text += "v 1 2 oops\n";  // a later part's parse error
  const Outcome many = parse(text, 4, 64);
  EXPECT_EQ(many.error, "mesh.obj: line 201: vertex index 999 is out of range (the file has 200 vertices so far)");
  expect_same(text, "two errors");
}

TEST(ObjChunks, AContinuedLineIsReadOnOneThreadWithTheSameResult) {
  std::string text;
  for (int i = 0; i < 100; ++i) text += "v " + std::to_string(i) + " 0 \\\n 1\n";
  text += "f 1 2 3\n";
  expect_same(text, "continued lines");
  EXPECT_EQ(parse(text, 4, 64).lines, std::vector<std::size_t>{201});
}

TEST(ObjChunks, ASceneLoadsTheSameFacesOnOneAndFourThreads) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("libshadow-test_obj_chunks-" + std::to_string(getpid()));
  fs::create_directories(dir);
  // A large file: one generated text again and again (its positive references are to earlier
  // vertices and its negative ones relative, so every copy is valid), a group before each.
  std::string one = make_obj(1, 400, false);
  if (one.rfind("\xEF\xBB\xBF", 0) == 0) one.erase(0, 3);
  std::string obj;
  for (int copy = 0; obj.size() < (1u << 20); ++copy) obj += "g copy" + std::to_string(copy) + "\n" + one;
  std::ofstream(dir / "mesh.obj") << obj;
  std::ofstream(dir / "scene.json")
      << R"({"meshes": [{"name": "m", "file": "mesh.obj", "transform": [[1,0,0,5],[0,0,-1,0],[0,1,0,0.25],[0,0,0,1]]}],)"
      << R"( "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})";
  shadow::LoadOptions options;
  options.skip_invalid = true;  // random faces: some are not planar
  options.threads = 1;
  const shadow::Scene a = shadow::load_scene(dir / "scene.json", options);
  options.threads = 4;
  const shadow::Scene b = shadow::load_scene(dir / "scene.json", options);
  ASSERT_EQ(a.faces.size(), b.faces.size());
  ASSERT_GT(a.faces.size() + a.skipped_faces.size(), 1000u);
  for (std::size_t f = 0; f < a.faces.size(); ++f) {
    ASSERT_EQ(a.faces[f].vertices, b.faces[f].vertices) << f;
    ASSERT_EQ(a.faces[f].source.to_string(), b.faces[f].source.to_string()) << f;
    ASSERT_EQ(a.faces[f].name, b.faces[f].name) << f;
    ASSERT_EQ(a.faces[f].mesh, b.faces[f].mesh) << f;
  }
  ASSERT_EQ(a.skipped_faces.size(), b.skipped_faces.size());
  fs::remove_all(dir);
}

TEST(ObjChunks, TheFuzzCorpusGivesTheSameOutcomeAsOneThread) {
  namespace fs = std::filesystem;
  const fs::path corpus = fs::path(LIBSHADOW_TEST_DATA) / ".." / "fuzz" / "corpus" / "fuzz_obj";
  std::size_t files = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(corpus)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    expect_same(text, entry.path().filename().string());
    ++files;
  }
  EXPECT_GE(files, 10u);
}

// A mesh file's bytes are read in parts of 8 MiB on every thread (detail::read_input_bytes): the
// same bytes as read_input_file at 1, 2 and 3 threads, for sizes at, below and above the parts'
// bounds; the same errors and the same size limit.
TEST(ObjChunks, AFileReadInPartsOnEveryThreadHasTheSameBytes) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("libshadow_read_parts_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  constexpr std::size_t kPart = std::size_t{8} << 20;
  std::mt19937 rng(8);
  for (const std::size_t size : {std::size_t{0}, std::size_t{1}, kPart - 1, kPart, kPart + 1, 2 * kPart + 12345}) {
    std::string bytes(size, '\0');
    for (char& c : bytes) c = static_cast<char>(rng());
    const fs::path file = dir / "bytes.bin";
    std::ofstream(file, std::ios::binary) << bytes;
    ASSERT_EQ(shadow::read_input_file(file, "bytes.bin", size), bytes);
    for (unsigned threads : {1u, 2u, 3u}) {
      const shadow::runtime::UninitVector<char> read =
          shadow::detail::read_input_bytes(file, "bytes.bin", size, "the test's limit", threads);
      ASSERT_EQ(std::string(read.begin(), read.end()), bytes) << size << " bytes, " << threads << " threads";
    }
    if (size > 0) {
      try {
        (void)shadow::detail::read_input_bytes(file, "bytes.bin", size - 1, "the test's limit", 2);
        FAIL() << "a file above the limit was read";
      } catch (const shadow::InputError& e) {
        EXPECT_EQ(std::string(e.what()), "bytes.bin: file is larger than the limit of " + std::to_string(size - 1) +
                                             " bytes (the test's limit)");
      }
    }
  }
  for (const fs::path& bad : {dir / "missing.obj", dir}) {
    std::string expected, got;
    try {
      (void)shadow::read_input_file(bad, "bad.obj", 100);
    } catch (const shadow::InputError& e) {
      expected = e.what();
    }
    try {
      (void)shadow::detail::read_input_bytes(bad, "bad.obj", 100, "LoadOptions::max_file_bytes", 2);
    } catch (const shadow::InputError& e) {
      got = e.what();
    }
    EXPECT_FALSE(expected.empty());
    EXPECT_EQ(got, expected);
  }
  fs::remove_all(dir);
}
