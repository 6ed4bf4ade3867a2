// SPDX-License-Identifier: GPL-3.0-or-later
// The `shadow` command line: `shadow compute SCENE.json -o OUTDIR`, `shadow render SCENE.json -o PNG`,
// `shadow sun --latitude LAT --longitude LON --time ISO8601` (tools/sun_command.cpp).
#include <shadow/shadow.hpp>

#ifdef LIBSHADOW_HAVE_RENDER
#include "render_module.hpp"
#endif

#include "cli_checks.hpp"
#include "out_of_memory.hpp"
#include "page_policy.hpp"
#include "progress_line.hpp"
#include "sun_command.hpp"
#include "world.hpp"

#include <CLI/CLI.hpp>

#include "radiosity_command.hpp"
#include "series_command.hpp"
#include "irradiance_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <optional>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;

/// Exit codes: 0 success, 2 bad input or usage error, 3 output failure (including an OUTDIR
/// locked by another run), 4 internal error, (5: `shadow series` stopped, series_command.cpp),
/// 6 out of memory (out_of_memory.hpp). README.md and `shadow --help` list them.
enum ExitCode { kOk = 0, kBadInput = 2, kOutputFailed = 3, kInternal = 4 };

struct ComputeArgs {
  std::string scene;
  std::string outdir;
  unsigned threads = 0;
  bool quiet = false;
  bool areas_only = false;
  double planarity_tolerance = 1e-6;
  double plane_window = 0.0;
  std::string arithmetic = "exact";
  bool orient_outward = false;
  bool skip_invalid = false;  // --skip-invalid: leave out faces that fail validation
  std::string lod;  // CityJSON level of detail; empty: the highest per object
  std::size_t tile_casters = shadow::ShadowOptions{}.tile_casters;
  std::size_t fast_tile_casters = shadow::ShadowOptions{}.fast_tile_casters;
};


/// The ParaView script that opens a result: installed beside the binary
/// (`<prefix>/share/libshadow/paraview`), or in the source tree of a build-tree binary.
fs::path paraview_script() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  const fs::path relative = fs::path("share") / "libshadow" / "paraview" / "open_result.py";
  if (!error && fs::exists(exe.parent_path().parent_path() / relative, error))
    return (exe.parent_path().parent_path() / relative).lexically_normal();
  return fs::path(LIBSHADOW_SOURCE_DIR) / "tools" / "paraview" / "open_result.py";
}

/// Lit fractions per mesh (a building, a city object): the first meshes, each with its first
/// lights; report.json's summary.per_mesh has them all.
/// The totals the summary prints: made while the output files are written (a million faces'
/// passes over the faces and the results took some 30 ms on one thread after them).
struct ComputeSummary {
  static constexpr std::size_t kMeshes = 20, kLights = 4, kLightLines = 20;
  std::size_t receivers = 0;
  std::vector<double> light_area, light_lit;           ///< the first kLightLines lights
  std::vector<std::vector<double>> mesh_area, mesh_lit;  ///< per mesh, its first kLights lights

  ComputeSummary(const shadow::Scene& scene, const shadow::ShadowResult& result) {
    for (std::size_t f = 0; f < scene.faces.size(); ++f) receivers += scene.is_receiver(f) ? 1 : 0;
    // Each light's and each mesh's totals in one pass over the results (each sum in the results'
    // order). A long list of lights (a model's year of suns) shows its first few and says where
    // the rest are; only the lights shown are summed per mesh: a model's year of suns on a city's
    // meshes would otherwise hold meshes x lights sums.
    const std::size_t light_lines = std::min(scene.lights.size(), kLightLines);
    light_area.assign(light_lines, 0.0);
    light_lit.assign(light_lines, 0.0);
    const std::size_t lights = std::min(scene.lights.size(), kLights);
    mesh_area.resize(scene.meshes.size());
    mesh_lit.resize(scene.meshes.size());
    for (const shadow::FaceLighting& fl : result.lighting) {
      if (fl.light_id < light_lines) {
        light_area[fl.light_id] += fl.area;
        light_lit[fl.light_id] += fl.lit_area;
      }
      if (fl.face_id >= scene.faces.size() || fl.light_id >= lights) continue;
      const std::size_t m = scene.faces[fl.face_id].mesh;
      if (m >= scene.meshes.size()) continue;
      if (mesh_area[m].empty()) {
        mesh_area[m].assign(lights, 0.0);
        mesh_lit[m].assign(lights, 0.0);
      }
      mesh_area[m][fl.light_id] += fl.area;
      mesh_lit[m][fl.light_id] += fl.lit_area;
    }
  }
};

void print_mesh_summary(const shadow::Scene& scene, const ComputeSummary& summary) {
  const std::size_t lights = std::min(scene.lights.size(), ComputeSummary::kLights);
  std::size_t shown = 0, with_results = 0;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (summary.mesh_area[m].empty()) continue;
    if (++with_results > ComputeSummary::kMeshes) continue;
    ++shown;
    std::printf("  mesh %s lit", scene.meshes[m].name.c_str());
    for (std::size_t l = 0; l < lights; ++l)
      std::printf("%s %s %.2f%%", l == 0 ? "" : ",", scene.lights[l].name.c_str(),
                  summary.mesh_area[m][l] > 0 ? 100.0 * summary.mesh_lit[m][l] / summary.mesh_area[m][l] : 0.0);
    std::printf("%s\n", scene.lights.size() > ComputeSummary::kLights ? ", ... (report.json: summary.per_mesh)" : "");
  }
  if (with_results > shown)
    std::printf("  ... %zu more meshes (report.json: summary.per_mesh)\n", with_results - shown);
}

int run_compute(const ComputeArgs& args) {
  // Reading and writing touch their memory about once, preparing and computing revisit it:
  // freed blocks kept for the first two only, on the page size cheaper on this host to touch
  // once (page_policy.hpp).
  const bool small_pages = shadow_cli::small_pages_for_touched_once();
  std::optional<shadow_cli::TouchedOnceStage> touched_once(std::in_place, small_pages);
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  shadow::RunInfo run;
  run.scene = args.scene;
  run.started_utc = shadow::utc_now();
  run.planarity_tolerance = args.planarity_tolerance;
  using shadow_cli::Stage;
  shadow_cli::set_stage(Stage::Loading);
  shadow::Scene scene = shadow::load_scene(
      args.scene, shadow_cli::load_options(args.planarity_tolerance, args.orient_outward, args.lod, args.threads,
                                            args.skip_invalid));
  const auto loaded = Clock::now();
  touched_once.reset();
  if (scene.lights.empty() && !scene.sun)
    // A model read whole (CityJSON, or an EnergyPlus file without a sun) brings no light.
    throw shadow::InputError({args.scene, ""},
                             "the scene has no lights (a model file carries none unless it gives a site and period "
                             "for the sun): write a scene JSON that names this file as a mesh \"file\" and add "
                             "\"lights\" or a \"sun\" block (docs/scene-format.md)");
  // Before computing: lock OUTDIR, clear what killed runs left, remove the old report.json (a
  // run killed from here on leaves no report, so nothing looks complete). Bad input above
  // leaves an earlier result alone.
  shadow::OutputDirectory output(args.outdir);
  if (!args.quiet)
    for (const shadow::Warning& warning : scene.warnings)
      std::cerr << "shadow: warning: " << warning.to_string() << "\n";

  // On a terminal one line rewritten in place; in a log a line now and then (progress_line.hpp).
  shadow_cli::ProgressLine progress(!args.quiet, "face-light pairs", 0, isatty(STDERR_FILENO) == 0);
  shadow::ShadowOptions options;
  options.threads = args.threads;
  options.polygons = !args.areas_only;
  options.plane_window = args.plane_window;
  if (args.arithmetic == "fast") options.arithmetic = shadow::Arithmetic::Fast;
  options.tile_casters = args.tile_casters;
  options.fast_tile_casters = args.fast_tile_casters;
  run.options = options;  // without the progress callback, which is no part of the identity
  options.progress = [&](const shadow::Progress& p) { progress.update(p); };
  shadow::ShadowResult result;
  Clock::time_point prepared;
  try {
    // compute_shadows(scene, options) in its two steps, so that running out of memory names the step.
    shadow_cli::set_stage(Stage::Preparing);
    const shadow::ShadowEngine engine(scene, options.threads);
    prepared = Clock::now();
    shadow_cli::set_stage(Stage::Computing);
    result = shadow::compute_shadows(engine, options);
  } catch (const shadow::InputError& e) {
    progress.finish();
    // Errors about lights found while computing still name the scene file.
    shadow_cli::rethrow_naming_scene(e, args.scene);
  }
  progress.finish();
  const auto computed = Clock::now();

  shadow_cli::set_stage(Stage::Writing);
  // The summary's totals on a thread of their own while the files are written (both read the
  // scene and the result, neither changes them); on this thread after them where one thread was
  // asked for, or where no thread could be started.
  std::optional<ComputeSummary> summary;
  std::exception_ptr summing_error;
  std::thread summing;
  if (!args.quiet && args.threads != 1) {
    try {
      summing = std::thread([&] {
        try {
          summary.emplace(scene, result);
        } catch (...) {
          summing_error = std::current_exception();
        }
      });
    } catch (const std::system_error&) {
      // (made below instead)
    }
  }
  struct JoinOnExit {
    std::thread& thread;
    ~JoinOnExit() {
      if (thread.joinable()) thread.join();
    }
  } join_summing{summing};
  touched_once.emplace(small_pages);
  const std::vector<fs::path> written = output.write(scene, result, &run);
  touched_once.reset();
  const auto finished = Clock::now();

  if (!args.quiet) {
    if (summing.joinable()) summing.join();
    if (summing_error) std::rethrow_exception(summing_error);
    if (!summary) summary.emplace(scene, result);
    auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    std::printf("shadow %s: %zu faces (%zu receiving), %zu lights, %zu fragments\n",
                shadow::version(), scene.faces.size(), summary->receivers, scene.lights.size(),
                result.fragments.size());
    if (args.skip_invalid || !scene.skipped_faces.empty())
      std::printf("  skipped: %zu invalid faces (--skip-invalid; report.json: skipped_faces)\n",
                  scene.skipped_faces.size());
    const std::size_t light_lines = summary->light_area.size();
    for (std::size_t l = 0; l < light_lines; ++l)
      std::printf("  light %zu %-12s lit %.6g of %.6g (%.2f%%)\n", l, scene.lights[l].name.c_str(),
                  summary->light_lit[l], summary->light_area[l],
                  summary->light_area[l] > 0 ? 100.0 * summary->light_lit[l] / summary->light_area[l] : 0.0);
    if (scene.lights.size() > light_lines) {
      std::printf("  ... %zu more lights (report.json: summary.per_light)\n", scene.lights.size() - light_lines);
      if (scene.sun)
        std::printf("  the scene's sun block is a period of %zu suns: `shadow series` computes them as a series "
                    "(sunlit fractions per instant, sun hours; docs/series.md)\n",
                    scene.lights.size());
    }
    print_mesh_summary(scene, *summary);
    if (options.arithmetic == shadow::Arithmetic::Fast)
      std::printf("  arithmetic fast: lit areas within their bounds in report.json (%llu receivers computed exactly)\n",
                  static_cast<unsigned long long>(result.stats.fast_exact_fallbacks));
    for (const shadow::PlaneShadow& ps : result.plane_shadows)
      std::printf("  plane %-8s light %-12s shadow area %.6g%s\n", scene.planes[ps.plane_id].name.c_str(),
                  scene.lights[ps.light_id].name.c_str(), ps.area,
                  ps.reaches_window ? " (reaches the window's edge: the shadow is longer)" : "");
    // The stages' wall times, so that a slow run says where its time went.
    std::printf("  computed in %.3f s (read and validated %.3f s, prepared %.3f s, shadows %.3f s), written in %.3f s\n",
                seconds(computed - start), seconds(loaded - start), seconds(prepared - loaded),
                seconds(computed - prepared), seconds(finished - computed));
    std::printf("  output: %s\n", fs::absolute(args.outdir).lexically_normal().c_str());
    for (const fs::path& p : written) std::printf("    %s\n", p.filename().c_str());
    const fs::path result_dir = fs::absolute(args.outdir).lexically_normal();
    std::printf("  open %s in ParaView, or with sensible defaults (docs/paraview.md):\n",
                (result_dir / "scene.vtm").c_str());
    const fs::path script = paraview_script();
    std::printf("    LIBSHADOW_RESULT=%s paraview --script=%s\n", result_dir.c_str(), script.c_str());
    std::printf("    %s %s %s --screenshot result.png   (headless)\n",
                (script.parent_path() / "pvpython.sh").c_str(), script.c_str(),
                result_dir.c_str());
  }
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  // Before anything allocates through GMP from a thread: GMP's failed allocations end the run
  // with the out-of-memory line and exit 6 instead of GMP's message and SIGABRT.
  shadow_cli::install_gmp_out_of_memory();
  shadow_cli::install_new_out_of_memory();
  shadow_cli::prepare_allocator_arenas();
  CLI::App app{"shadow: exact object-space shadows (libshadow " + std::string(shadow::version()) + ")"};
  app.set_version_flag("--version", std::string(shadow::version()));
  app.require_subcommand(1);
  app.footer(shadow_cli::exit_codes_help());

  ComputeArgs args;
  CLI::App* compute = app.add_subcommand(
      "compute", "Compute every light's lit and shadowed polygons on every face and write them to OUTDIR");
  compute->footer(shadow_cli::exit_codes_help());
  compute->add_option("scene", args.scene, "Scene file (JSON; see docs/scene-format.md)")->required();
  compute->add_option("-o,--output", args.outdir, "Output directory (created if missing)")->required();
  compute->add_option("-t,--threads", args.threads, "Worker threads (0: all cores; at most 1024)")
      ->default_val(0)
      ->check(shadow_cli::integer_in(0, 1024));
  compute->add_flag("-q,--quiet", args.quiet, "Print nothing but errors");
  compute->add_flag("--areas-only", args.areas_only,
                    "Compute lit areas only, no polygons: fragments.vtp then has no cells");
  compute->add_option("--plane-window", args.plane_window,
                      "Half side of the square window on each plane in which plane shadows are computed "
                      "(default: ten scene diagonals)")
      ->check(shadow_cli::finite_in(0.0, shadow::max_coordinate, "2^500 (about 3.27e150)"));
  compute->add_option("--arithmetic", args.arithmetic,
                      "exact (default), or fast: doubles and an integer grid, each face's lit area "
                      "with an error bound in report.json (docs/numeric-contract.md)")
      ->check(CLI::IsMember({"exact", "fast"}));
  compute->add_flag_callback("--fast", [&args] { args.arithmetic = "fast"; }, "Same as --arithmetic fast");
  compute->add_option("--planarity-tolerance", args.planarity_tolerance,
                      "Largest vertex distance from a face's plane, relative to the face's size")
      ->default_val(1e-6)
      ->check(shadow_cli::positive_up_to(1.0));
  compute->add_flag("--orient-outward", args.orient_outward,
                    "Turn the closed parts of every mesh outward: make each part's faces consistent, then "
                    "reverse a part whose faces point inward (each change is a warning)");
  shadow_cli::add_tile_options<shadow::ShadowOptions>(*compute, args.tile_casters, args.fast_tile_casters,
                                                      {"", "areas", "fragments", "--arithmetic fast", "areas"});
  compute->add_option("--lod", args.lod,
                      "CityJSON level of detail to read (\"1\", \"2\", \"2.2\"; default: the highest of each "
                      "city object)");
  compute->add_flag("--skip-invalid", args.skip_invalid, shadow_cli::skip_invalid_help());

  SeriesArgs series_args;
  CLI::App* series = add_series_command(app, series_args);

#ifdef LIBSHADOW_HAVE_RENDER
  RenderArgs render_args;
  CLI::App* render = app.add_subcommand(
      "render", "Draw the scene: lit by a lighting model with its exact shadows to a PNG image (needs an X "
                "display or xvfb-run; docs/lighting.md), its exact vector view to an .svg or .pdf "
                "(docs/vector-views.md), or its faces coloured by an irradiance result (--irradiation)");
  add_render_options(*render, render_args);
  render->footer(shadow_cli::exit_codes_help());
#endif

  IrradianceArgs irradiance_args;
  CLI::App* irradiance = add_irradiance_command(app, irradiance_args);
  RadiosityArgs radiosity_args;
  CLI::App* radiosity = add_radiosity_command(app, radiosity_args);

  SunArgs sun_args;
  CLI::App* sun = app.add_subcommand(
      "sun", "Print the sun's position (NREL SPA, topocentric, refraction included) at a place and UTC "
             "instant as one JSON line: time, elevation, azimuth (clockwise from north), zenith, to_light");
  add_sun_options(*sun, sun_args);
  sun->footer(shadow_cli::exit_codes_help());

  // An unknown subcommand would only get CLI11's "A subcommand is required": name it.
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') continue;
    bool found = true;
    try {
      app.get_subcommand(word);
    } catch (const CLI::OptionNotFound&) {
      found = false;
    }
    if (!found) {
#ifdef LIBSHADOW_HAVE_RENDER
      const char* known = "compute, series, irradiance, radiosity, render, sun";
#else
      const char* known = "compute, series, irradiance, radiosity, sun";
#endif
      std::cerr << "shadow: error: unknown subcommand \"" << shadow_cli::one_line(word) << "\" (known: " << known
                << "; see shadow --help)\n";
      return kBadInput;
    }
    break;  // the subcommand's own arguments follow
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version: CLI11 prints them and exits 0.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    // Every usage error: one line, exit 2, like bad input.
    std::cerr << "shadow: error: " << shadow_cli::one_line(e.what()) << " (see shadow --help)\n";
    return kBadInput;
  }

  // Only `shadow series` shares its work between MPI ranks; N copies of another subcommand
  // would each do all of it (and fight over OUTDIR's lock): say so once, from the first rank.
  if (!*series && shadow_cli::launcher_size() > 1) {
    if (shadow_cli::launcher_rank() == 0)
      std::cerr << "shadow: error: started by an MPI launcher with " << shadow_cli::launcher_size()
                << " processes: only `shadow series` runs across MPI ranks (docs/cluster.md); run this "
                   "subcommand as one process\n";
    return kBadInput;
  }
  try {
    if (*series) return run_series(series_args);
    if (*compute) return run_compute(args);
    if (*sun) return run_sun(sun_args);
    if (*irradiance) return run_irradiance(irradiance_args);
    if (*radiosity) return run_radiosity(radiosity_args);
#ifdef LIBSHADOW_HAVE_RENDER
    if (*render) {
      shadow_cli::set_stage(shadow_cli::Stage::Rendering);
      return run_render_module(render_args, argc, argv);
    }
#endif
  } catch (const shadow::InputError& e) {
    std::cerr << "shadow: error: " << e.what() << "\n";
    return kBadInput;
  } catch (const shadow::OutputError& e) {
    std::cerr << "shadow: error: " << e.what() << "\n";
    return kOutputFailed;
  } catch (const std::bad_alloc&) {
    // Thrown by code itself (operator new's failures end the run in the new handler).
    shadow_cli::print_out_of_memory();
    return shadow_cli::kOutOfMemory;
  } catch (const std::exception& e) {
    if (shadow_cli::is_thread_start_failure(e)) {
      shadow_cli::print_out_of_memory();
      return shadow_cli::kOutOfMemory;
    }
    std::cerr << "shadow: internal error: " << e.what() << "\n";
    return kInternal;
  }
  return kOk;
}
