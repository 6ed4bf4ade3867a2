// SPDX-License-Identifier: GPL-3.0-or-later
// The `shadow irradiance` subcommand: irradiation over a weather year (docs/irradiance.md).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

struct IrradianceArgs {
  std::string scene;
  std::string weather;
  std::string outdir;
  std::string sky = "perez";
  int sky_patches = 145;
  double ground_reflectance = -1.0;  ///< < 0: the EPW's albedo, else 0.2
  std::string from, to;              ///< MM-DD or YYYY-MM-DD (the year is not used)
  bool fast = false;
  bool hourly = false;
  bool reflections = false;  // --reflections: the scene's own reflections (radiosity)
  bool quiet = false;
  unsigned threads = 0;
  double planarity_tolerance = 1e-6;
  bool orient_outward = false;
  bool skip_invalid = false;
  std::string lod;
  std::string map;  ///< --map MESH[,MESH]: meshes that get irradiation_map.vtp
  std::string ground;  ///< --ground MESH[,MESH]: the meshes that are the ground (Scene::ground)
};

/// Declares the subcommand `irradiance` and its options on `app`.
CLI::App* add_irradiance_command(CLI::App& app, IrradianceArgs& args);

/// Runs `shadow irradiance`. @throws shadow::InputError, shadow::OutputError
int run_irradiance(const IrradianceArgs& args);
