// SPDX-License-Identifier: GPL-3.0-or-later
// The series job's tests (test_series_job, test_series_stream): run a job in one process, and
// compare two output directories file by file.
#pragma once

#include <shadow/series_job.hpp>

#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>

namespace shadow::test {

/// Runs the job with a one-process world.
inline SeriesJobResult run_series_job(SeriesJobOptions options) {
  SingleProcessWorld world;
  SeriesJob job(std::move(options), world);
  return job.run();
}

/// Every file under `dir` but those named in `skip` (relative path -> bytes); report.json
/// without its start time.
inline std::map<std::string, std::string> files_of(const std::filesystem::path& dir,
                                                   const std::set<std::string>& skip = {}) {
  std::map<std::string, std::string> files;
  for (const std::filesystem::directory_entry& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file() || skip.count(e.path().filename().string())) continue;
    std::ifstream in(e.path(), std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    std::string text = bytes.str();
    if (e.path().filename() == "report.json")
      text = std::regex_replace(text, std::regex("\"started_utc\": \"[^\"]*\""), "\"started_utc\": \"\"");
    files[std::filesystem::relative(e.path(), dir).string()] = text;
  }
  return files;
}

/// The same files with the same bytes under `a` and `b` (files_of, skipping `skip`), at least
/// `at_least` of them.
inline void expect_same_files(const std::filesystem::path& a, const std::filesystem::path& b, std::size_t at_least,
                              const std::set<std::string>& skip = {}) {
  const auto fa = files_of(a, skip), fb = files_of(b, skip);
  ASSERT_GE(fa.size(), at_least);
  for (const auto& [name, bytes] : fa) {
    ASSERT_TRUE(fb.count(name)) << name << " missing in " << b;
    EXPECT_TRUE(fb.at(name) == bytes) << name << " differs between " << a << " and " << b;
  }
  EXPECT_EQ(fa.size(), fb.size());
}

}  // namespace shadow::test
