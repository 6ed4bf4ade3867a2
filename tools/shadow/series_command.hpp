// SPDX-License-Identifier: GPL-3.0-or-later
// The `shadow series` subcommand: the scene's sun instants as one job (docs/series.md).
#pragma once

#include <shadow/shadows.hpp>

#include <CLI/CLI.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

struct SeriesArgs {
  std::string scene;
  std::string outdir;
  unsigned threads = 0;
  bool fast = false;
  bool quiet = false;
  std::size_t every = 1;
  bool sun_hours_levels_given = false;  ///< --sun-hours-levels given (even empty: then an error)
  bool every_given = false;  ///< --every given: else shadow::default_series_every() decides (long periods: a bounded number)
  bool fragments = false;
  bool energyplus_shading = false;  ///< --energyplus-shading: write it for any scene, not only an EnergyPlus model
  std::string sun_hours_map;  ///< --sun-hours-map MESH[,MESH]: meshes that get the exact map
  std::string sun_hours_levels;  ///< --sun-hours-levels H[,H]: the threshold map's levels in hours
  bool sun_hours_levels_only = false;  ///< --sun-hours-levels-only: the threshold map alone
  std::optional<std::size_t> sun_hours_held_segments;  ///< --sun-hours-held-segments N
  double planarity_tolerance = 1e-6;
  bool orient_outward = false;
  bool skip_invalid = false;  ///< --skip-invalid: leave out faces that fail validation
  std::string lod;         ///< CityJSON level of detail; empty: the highest per object
  std::string from, to;    ///< --from/--to: override the sun period's dates (YYYY-MM-DD, local standard)
  int step_minutes = 0;    ///< --step: override its step in minutes (0: keep)
  bool checkpoint = false;  ///< --checkpoint: keep OUTDIR/series.checkpoint as the run goes
  bool resume = false;      ///< --resume: start from OUTDIR/series.checkpoint (implies --checkpoint)
  std::size_t stop_after = 0;  ///< --stop-after N (testing): stop once N instants are checkpointed
  /// --tile-casters / --fast-tile-casters: SeriesOptions' tile thresholds (docs/tiles.md)
  std::size_t tile_casters = shadow::SeriesOptions{}.tile_casters;
  std::size_t fast_tile_casters = shadow::SeriesOptions{}.fast_tile_casters;
  std::string write_idf;  ///< --write-idf FILE: a copy of the EnergyPlus model that imports the CSV
};

/// Declares the subcommand `series` and its options on `app`.
CLI::App* add_series_command(CLI::App& app, SeriesArgs& args);

/// Runs `shadow series`. @throws shadow::InputError, shadow::OutputError
int run_series(const SeriesArgs& args);
