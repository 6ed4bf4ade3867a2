// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity_command.hpp"

#include "cli_checks.hpp"

#include <shadow/error.hpp>
#include <shadow/output.hpp>
#include <shadow/radiosity.hpp>
#include <shadow/radiosity_output.hpp>
#include <shadow/scene_io.hpp>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>

CLI::App* add_radiosity_command(CLI::App& app, RadiosityArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "radiosity", "Global illumination by progressive radiosity with exact visibility: elements cut from the "
                   "exact lit and shadowed fragments, materials' reflectance and emittance; writes radiosity.vtp "
                   "and report.json (docs/radiosity.md)");
  cmd->footer(shadow_cli::exit_codes_help());
  cmd->add_option("scene", args.scene, "Scene file (JSON; see docs/scene-format.md)")->required();
  cmd->add_option("-o,--output", args.outdir, "Output directory (created if missing)")->required();
  cmd->add_option("--max-element-area", args.max_element_area,
                  "Refine the elements (triangles of the fragments) until none is larger than this, in m^2 "
                  "(0, the default: the fragments' triangles as they are)")
      ->check(shadow_cli::finite_in(0.0, 1e300));
  cmd->add_option("--patch-area", args.patch_area,
                  "Shooting patches (each the mean of the elements it holds) up to this area, in m^2 "
                  "(0, the default: 16 times --max-element-area)")
      ->check(shadow_cli::finite_in(0.0, 1e300));
  cmd->add_option("--tolerance", args.tolerance,
                  "Stop when the unshot power is at most this fraction of the power put in (default 0.001)")
      ->check(shadow_cli::finite_in(1e-12, 0.999999));
  cmd->add_option("--method", args.method,
                  "auto (the default: hierarchical above 4,000 patches), shooting (progressive refinement: "
                  "every patch shoots to every element) or hierarchical (links between groups of patches far "
                  "apart, gathering iterations; for cities)")
      ->check(CLI::IsMember({"auto", "shooting", "hierarchical"}));
  cmd->add_option("--link-separation", args.link_separation,
                  "Hierarchical: link two groups of patches as a whole when their radii add up to at most this "
                  "times their distance (default 0.4; smaller is closer to shooting and slower)")
      ->check(shadow_cli::finite_in(0.1, 0.999));
  cmd->add_option("--refine-tolerance", args.refine_tolerance,
                  "Adaptive refinement (shooting): split the elements across which the irradiance varies most "
                  "and solve again, until the element field's estimated relative error is at most this "
                  "(e.g. 0.02; 0, the default: no adaptive refinement)")
      ->check(shadow_cli::finite_in(0.0, 0.999));
  cmd->add_option("--refine-passes", args.refine_passes,
                  "Adaptive refinement: at most this many rounds of splitting in four (1 to 8, default 3)")
      ->check(shadow_cli::integer_in(1, 8));
  cmd->add_flag("--no-per-light", args.no_per_light,
                "Skip each light's share of the reflected light (report.json irradiance_by_light: one more "
                "solution per light when the scene has more than one source)");
  cmd->add_option("-t,--threads", args.threads, "Worker threads (0: all cores; at most 1024)")
      ->default_val(0)
      ->check(shadow_cli::integer_in(0, 1024));
  cmd->add_flag("-q,--quiet", args.quiet, "Print nothing but errors");
  // The scene is read as `shadow compute` reads it (validation's errors suggest these flags).
  shadow_cli::add_scene_reading_options(cmd, args.planarity_tolerance, args.orient_outward, args.lod, args.skip_invalid);
  return cmd;
}

int run_radiosity(const RadiosityArgs& args) {
  using Clock = std::chrono::steady_clock;
  const std::string started = shadow::utc_now();
  shadow::Scene scene =
      shadow::load_scene(args.scene, shadow_cli::load_options(args.planarity_tolerance, args.orient_outward, args.lod,
                                                              args.threads, args.skip_invalid));
  shadow::OutputDirectory output(args.outdir);
  if (!args.quiet)
    for (const shadow::Warning& warning : scene.warnings)
      std::cerr << "shadow: warning: " << warning.to_string() << "\n";
  shadow::RadiosityOptions options;
  options.max_element_area = args.max_element_area;
  options.patch_area = args.patch_area;
  options.tolerance = args.tolerance;
  options.threads = args.threads;
  options.method = args.method == "shooting"       ? shadow::RadiosityMethod::shooting
                   : args.method == "hierarchical" ? shadow::RadiosityMethod::hierarchical
                                                   : shadow::RadiosityMethod::automatic;
  options.link_separation = args.link_separation;
  options.refine_tolerance = args.refine_tolerance;
  options.refine_passes = args.refine_passes;
  options.per_light = !args.no_per_light;
  const bool terminal = isatty(STDERR_FILENO) != 0;
  auto last_line = Clock::now();
  bool shown = false;
  options.progress = [&](const shadow::RadiosityProgress& p) {
    if (args.quiet) return;
    const auto now = Clock::now();
    if (now - last_line < std::chrono::seconds(terminal ? 0 : 5)) return;
    last_line = now;
    if (p.links_fraction < 1.0)
      std::fprintf(stderr, terminal ? "\r\033[Kshadow: radiosity links %.0f%%" : "shadow: radiosity links %.0f%%\n",
                   100.0 * p.links_fraction);
    else
      std::fprintf(stderr,
                   terminal ? "\r\033[Kshadow: radiosity %zu %s, unshot %.3g%%" : "shadow: radiosity %zu %s, unshot %.3g%%\n",
                   p.shots, p.shots_are_iterations ? "iterations" : "shots", 100.0 * p.unshot_fraction);
    std::fflush(stderr);
    shown = terminal;
  };
  const auto start = Clock::now();
  shadow::RadiosityResult result;
  try {
    result = shadow::solve_radiosity(scene, options);
  } catch (const shadow::InputError& e) {
    shadow_cli::rethrow_naming_scene(e, args.scene);
  }
  if (shown) std::fprintf(stderr, "\n");
  shadow::RadiosityRunInfo run;
  run.scene = args.scene;
  run.started_utc = started;
  run.options = options;
  run.options.progress = nullptr;
  run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  shadow::write_radiosity_outputs(output.path(), scene, result, run);
  if (!args.quiet) {
    if (result.hierarchical)
      std::printf("radiosity: %zu elements in %zu patches on %zu faces, hierarchical: %zu near and %zu far links, "
                  "%zu iterations in %.2f s%s\n",
                  result.elements.size(), result.patches, scene.faces.size(), result.near_links, result.far_links,
                  result.iterations, run.seconds, result.converged ? "" : " (not converged)");
    else
      std::printf("radiosity: %zu elements in %zu patches on %zu faces, %zu shots in %.2f s%s\n",
                  result.elements.size(), result.patches, scene.faces.size(), result.shots, run.seconds,
                  result.converged ? "" : " (not converged)");
    if (!scene.skipped_faces.empty())
      std::printf("  skipped: %zu invalid faces (--skip-invalid; report.json: skipped_faces)\n", scene.skipped_faces.size());
    if (options.refine_tolerance > 0)
      std::printf("  adaptive refinement: %zu -> %zu elements in %zu passes, estimated element field error %.3g%%\n",
                  result.initial_elements, result.elements.size(), result.refine_passes,
                  100.0 * result.discretization_error);
    std::printf("  unshot %.4g%% of the power put in, error estimate %.3g%%\n", 100.0 * result.unshot_fraction,
                100.0 * result.error_estimate);
    std::printf("  balance (W): emitted %.6g + direct %.6g = absorbed %.6g + escaped %.6g + unshot %.6g "
                "(residual %.2g)\n",
                result.emitted_power, result.direct_power, result.absorbed_power, result.escaped_power,
                result.unshot_power, result.balance_residual);
    std::printf("  wrote %s/radiosity.vtp and report.json\n", args.outdir.c_str());
  }
  return 0;
}
