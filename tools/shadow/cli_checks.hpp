// SPDX-License-Identifier: GPL-3.0-or-later
// Option checks and helpers shared by `shadow compute`, `shadow series` and `shadow render`. CLI11's own Range and
// NonNegativeNumber let NaN through (every comparison with NaN is false) and print the range
// of a double in 309 digits; these say what is expected in a few words.
#pragma once

#include <shadow/error.hpp>
#include <shadow/scene_io.hpp>

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstddef>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace shadow_cli {

/// Usage errors (any malformed command line) and bad input: exit 2.
inline constexpr int kUsageExit = 2;

inline std::string short_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

/// A whole number in [lo, hi], written in decimal digits only.
inline CLI::Validator integer_in(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        errno = 0;
        char* end = nullptr;
        const long long value = std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || end == text.c_str() || *end != '\0' || errno == ERANGE || value < lo || value > hi)
          return "expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got \"" +
                 text + "\"";
        return {};
      },
      "INT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

/// The largest --tile-casters / --fast-tile-casters (a billion candidate casters: more than a
/// scene has; 0 turns tiles off).
constexpr long long kMaxTileCasters = 1000000000;

/// What `--tile-casters` and `--fast-tile-casters` say about one command's results: their help
/// texts differ in these parts only.
struct TileOptionsHelp {
  std::string casters_when;  ///< after "more candidate casters": "" or " at an instant"
  std::string kept;          ///< the results that exact tiles leave unchanged
  std::string cut;           ///< what exact tiles cut at tile borders (the polygons)
  std::string fast_switch;   ///< how the command's help names the fast path
  std::string fast_changes;  ///< the results that the fast path's tiles change within their bounds
};

/// Adds `--tile-casters` and `--fast-tile-casters` (into `tile_casters` and `fast_tile_casters`)
/// to `command`, with the defaults of `Options` (shadow::ShadowOptions, shadow::SeriesOptions).
template <class Options>
void add_tile_options(CLI::App& command, std::size_t& tile_casters, std::size_t& fast_tile_casters,
                      const TileOptionsHelp& help) {
  command
      .add_option("--tile-casters", tile_casters,
                  "Split a large receiver into tiles when it has more candidate casters" + help.casters_when +
                      " than this (exact arithmetic; " + help.kept + " unchanged, " + help.cut +
                      " cut at tile borders; 0: never; docs/tiles.md)")
      ->default_val(Options{}.tile_casters)
      ->check(integer_in(0, kMaxTileCasters));
  command
      .add_option("--fast-tile-casters", fast_tile_casters,
                  "The same for " + help.fast_switch + " (" + help.fast_changes +
                      " change within their bounds; 0: never)")
      ->default_val(Options{}.fast_tile_casters)
      ->check(integer_in(0, kMaxTileCasters));
}

/// A finite number in [lo, hi] (NaN and infinities rejected), `hi_text` naming the top.
inline CLI::Validator finite_in(double lo, double hi, const std::string& hi_text = {}) {
  const std::string top = hi_text.empty() ? short_number(hi) : hi_text;
  return CLI::Validator(
      [lo, hi, top](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(value) || !(value >= lo) ||
            !(value <= hi))
          return "expected a finite number from " + short_number(lo) + " to " + top + ", got \"" + text + "\"";
        return {};
      },
      "NUMBER in [" + short_number(lo) + ", " + top + "]");
}

/// A finite number > 0 and at most `hi`.
inline CLI::Validator positive_up_to(double hi) {
  return CLI::Validator(
      [hi](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(value) || !(value > 0) ||
            !(value <= hi))
          return "expected a finite number > 0 and at most " + short_number(hi) + ", got \"" + text + "\"";
        return {};
      },
      "NUMBER > 0");
}

/// CLI11's message on one line (it may hold newlines), for `shadow: error: ...`.
inline std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return shadow::escape_control(text);  // any other control byte (ESC, NUL) shown as \xHH
}

/// Exit codes, printed at the end of `shadow --help`.
inline const char* exit_codes_help() {
  return "Exit status: 0 success; 2 bad input or a usage error (one line on stderr naming the file, "
         "place and problem, or the option); 3 an output could not be written (including OUTDIR locked "
         "by another running shadow); 4 internal error (a bug: please report it); 5 `shadow series --checkpoint` "
         "stopped by a signal (--resume finishes it); 6 out of memory (one line naming the stage; no report.json).";
}

/// The help of `--skip-invalid` (compute, series, render).
inline const char* skip_invalid_help() {
  return "Leave out faces that fail validation (not planar, boundary intersecting itself, fewer than 3 "
         "distinct vertices, ...) instead of stopping: one warning each (the first 10, then a count), all "
         "listed in report.json (skipped_faces); face ids count the faces kept";
}

/// How `shadow irradiance` and `shadow radiosity` read their scene: --planarity-tolerance,
/// --orient-outward, --lod and --skip-invalid (validation's errors suggest these flags).
inline void add_scene_reading_options(CLI::App* cmd, double& planarity_tolerance, bool& orient_outward,
                                      std::string& lod, bool& skip_invalid) {
  cmd->add_option("--planarity-tolerance", planarity_tolerance,
                  "Largest vertex distance from a face's plane, relative to the face's size")
      ->default_val(1e-6)
      ->check(positive_up_to(1.0));
  cmd->add_flag("--orient-outward", orient_outward, "Turn the closed parts of every mesh outward");
  cmd->add_option("--lod", lod, "CityJSON level of detail to read (default: the highest of each city object)");
  cmd->add_flag("--skip-invalid", skip_invalid, skip_invalid_help());
}

/// The load options of `shadow compute`, `shadow series` and `shadow render` (the same four
/// flags, and `--threads` for validation's per-face checks).
inline shadow::LoadOptions load_options(double planarity_tolerance, bool orient_outward, const std::string& lod,
                                        unsigned threads = 0, bool skip_invalid = false) {
  shadow::LoadOptions options;
  options.skip_invalid = skip_invalid;
  options.threads = threads;
  options.planarity_tolerance = planarity_tolerance;
  options.orient_outward = orient_outward;
  options.cityjson_lod = lod;
  return options;
}

/// Call from a catch block: an InputError found while computing (a light, an option) names no
/// file; it gets the scene file's name. One that names its file is rethrown as it is.
[[noreturn]] inline void rethrow_naming_scene(const shadow::InputError& e, const std::string& scene) {
  if (!e.where().file.empty()) throw;
  throw shadow::InputError({scene, e.where().place}, e.problem());
}

}  // namespace shadow_cli
