// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench radiosity-compare: radiosity (solve_radiosity) at several element sizes and the
// diffuse path tracer (path_trace_faces) at several path counts against a long path-traced
// reference, per face and as speed against error (docs/radiosity.md, "Against a path tracer").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace bench {

struct RadiosityCompareOptions {
  std::string scene;                           ///< empty: examples/cornell_room.json
  std::vector<double> element_areas{4.0, 1.0, 0.5};  ///< RadiosityOptions::max_element_area of each run
  double tolerance = 0.01;                     ///< RadiosityOptions::tolerance
  double patch_area = 0.0;                     ///< RadiosityOptions::patch_area (0: its default)
  std::vector<std::uint64_t> samples{16, 64, 256, 1024, 4096};  ///< paths per face of each tracer run
  std::uint64_t reference_samples = 1u << 20;  ///< paths per face of the reference
  std::uint64_t seed = 1;                      ///< the runs' seed (the reference's is seed + 1)
  unsigned threads = 2;
  std::string csv_path;                        ///< one row per run and face
  bool no_radiosity = false;                   ///< only the path tracer against the reference
  bool quick = false;                          ///< smoke run: one element size, small path counts
};

/// Adds the subcommand and its options to `app`.
CLI::App* add_radiosity_compare_command(CLI::App& app, RadiosityCompareOptions& options);

/// Runs it; prints Markdown tables. 2 on bad input (one line `shadow-bench: error: ...`).
int run_radiosity_compare(const RadiosityCompareOptions& options);

}  // namespace bench
