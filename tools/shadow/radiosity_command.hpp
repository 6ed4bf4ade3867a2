// SPDX-License-Identifier: GPL-3.0-or-later
// The `shadow radiosity` subcommand: global illumination by radiosity (docs/radiosity.md).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

struct RadiosityArgs {
  std::string scene;
  std::string outdir;
  double max_element_area = 0.0;
  double patch_area = 0.0;  // --patch-area: shooting patches (0: 16 elements)
  double tolerance = 1e-3;
  std::string method = "auto";  // --method auto|shooting|hierarchical
  double link_separation = 0.4;
  double refine_tolerance = 0.0;
  int refine_passes = 3;
  bool no_per_light = false;  // --no-per-light
  unsigned threads = 0;
  bool quiet = false;
  double planarity_tolerance = 1e-6;
  bool orient_outward = false;  // --orient-outward
  std::string lod;              // --lod
  bool skip_invalid = false;    // --skip-invalid
};

/// Declares `shadow radiosity` and its options on `app`.
CLI::App* add_radiosity_command(CLI::App& app, RadiosityArgs& args);

/// Loads the scene, solves, writes radiosity.vtp and report.json and prints a summary; returns
/// the exit status. Bad input throws shadow::InputError (naming the scene file).
int run_radiosity(const RadiosityArgs& args);
