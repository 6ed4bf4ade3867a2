// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench radiosity-compare: the speed against error of radiosity and of path tracing, the
// two methods of global illumination the seed contrasts, on one scene (the Cornell room by
// default). Errors are per face, against a long path-traced reference with its own standard error.
#include "bench_radiosity.hpp"

#include <shadow/baselines.hpp>
#include <shadow/radiosity.hpp>
#include <shadow/scene_io.hpp>

#include <CLI/CLI.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace bench {

namespace {

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// One run of one method: per-face irradiance (and standard errors for the tracer).
struct Run {
  std::string method, setting;
  double wall = 0, cpu = 0;
  std::string size;  ///< elements (radiosity) or paths (tracer)
  std::vector<double> h, se;  ///< by face id; se empty for radiosity
  std::vector<double> direct;  ///< radiosity: the direct irradiance by face id (exact shadows)
  std::string note;
};

/// Area-weighted RMS and worst relative error against the reference, and the worst |error| in
/// units of the combined standard error (the reference's and the run's own).
struct Errors {
  double rms = 0, worst = 0, worst_sigma = 0;
};

Errors errors_of(const Run& run, const shadow::PathTracerResult& ref) {
  Errors e;
  double area = 0, sum = 0;
  for (const shadow::IrradianceEstimate& r : ref.estimates) {
    if (r.paths == 0 || !(r.irradiance > 0)) continue;
    const double h = run.h[r.face_id];
    const double rel = (h - r.irradiance) / r.irradiance;
    sum += r.area * rel * rel;
    area += r.area;
    e.worst = std::max(e.worst, std::abs(rel));
    const double own = run.se.empty() ? 0.0 : run.se[r.face_id];
    const double sigma = std::sqrt(r.standard_error * r.standard_error + own * own);
    if (sigma > 0) e.worst_sigma = std::max(e.worst_sigma, std::abs(h - r.irradiance) / sigma);
  }
  e.rms = area > 0 ? std::sqrt(sum / area) : 0.0;
  return e;
}

std::string mesh_face(const shadow::Scene& scene, std::size_t f) {
  const shadow::Mesh& m = scene.meshes[scene.faces[f].mesh];
  return m.face_count > 1 ? m.name + "[" + std::to_string(f - m.first_face) + "]" : m.name;
}

Run radiosity_run(const shadow::Scene& scene, double element_area, const RadiosityCompareOptions& o) {
  shadow::RadiosityOptions ro;
  ro.max_element_area = element_area;
  ro.tolerance = o.tolerance;
  ro.patch_area = o.patch_area;
  ro.threads = o.threads;
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  const shadow::RadiosityResult r = shadow::solve_radiosity(scene, ro);
  Run run;
  run.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.cpu = cpu_seconds() - c0;
  run.method = "radiosity";
  char text[128];
  if (o.patch_area > 0) std::snprintf(text, sizeof text, "element <= %g m^2, patch <= %g m^2", element_area, o.patch_area);
  else std::snprintf(text, sizeof text, "element <= %g m^2", element_area);
  run.setting = text;
  run.size = std::to_string(r.elements.size()) + " elements";
  run.h.assign(scene.faces.size(), 0.0);
  run.direct.assign(scene.faces.size(), 0.0);
  for (const shadow::FaceRadiosity& f : r.faces) {
    run.h[f.face_id] = f.irradiance;
    run.direct[f.face_id] = f.direct_irradiance;
  }
  std::snprintf(text, sizeof text, "%zu patches, %zu shots, unshot %.2g%%, error estimate %.2g", r.patches, r.shots,
                100 * r.unshot_fraction, r.error_estimate);
  run.note = text;
  return run;
}

shadow::PathTracerResult trace(const shadow::Scene& scene, std::uint64_t samples, std::uint64_t seed,
                               const RadiosityCompareOptions& o, double& wall, double& cpu) {
  shadow::PathTracerOptions po;
  po.samples = samples;
  po.seed = seed;
  po.threads = o.threads;
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  shadow::PathTracerResult r = shadow::path_trace_faces(scene, po);
  wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  cpu = cpu_seconds() - c0;
  return r;
}

Run tracer_run(const shadow::Scene& scene, std::uint64_t samples, const RadiosityCompareOptions& o) {
  Run run;
  const shadow::PathTracerResult r = trace(scene, samples, o.seed, o, run.wall, run.cpu);
  run.method = "path tracer";
  run.setting = std::to_string(samples) + " paths/face";
  run.size = std::to_string(r.paths) + " paths";
  run.h.assign(scene.faces.size(), 0.0);
  run.se.assign(scene.faces.size(), 0.0);
  for (const shadow::IrradianceEstimate& e : r.estimates) {
    run.h[e.face_id] = e.irradiance;
    run.se[e.face_id] = e.standard_error;
  }
  char text[128];
  std::snprintf(text, sizeof text, "%.3g Mrays", 1e-6 * static_cast<double>(r.rays));
  run.note = text;
  return run;
}

/// The power (W) that reaches the faces directly from the lights, and all of it: sum of H A.
void print_powers(const shadow::PathTracerResult& ref, const std::vector<Run>& runs) {
  double direct = 0, direct_var = 0, total = 0, total_var = 0;
  for (const shadow::IrradianceEstimate& r : ref.estimates) {
    direct += r.direct_irradiance * r.area;
    direct_var += std::pow(r.direct_standard_error * r.area, 2);
    total += r.irradiance * r.area;
    total_var += std::pow(r.standard_error * r.area, 2);
  }
  std::printf("\nreference: direct power %.5g ± %.2g W, all incident power %.5g ± %.2g W\n", direct, std::sqrt(direct_var),
              total, std::sqrt(total_var));
  for (const Run& run : runs) {
    if (run.direct.empty()) continue;
    double d = 0, t = 0;
    for (const shadow::IrradianceEstimate& r : ref.estimates) {
      d += run.direct[r.face_id] * r.area;
      t += run.h[r.face_id] * r.area;
    }
    std::printf("radiosity, %s: direct power %.5g W, all incident power %.5g W\n", run.setting.c_str(), d, t);
  }
}

void print_tables(const shadow::Scene& scene, const shadow::PathTracerResult& ref, const std::vector<Run>& runs) {
  print_powers(ref, runs);
  std::printf("\n| method | setting | size | wall (s) | CPU (s) | RMS rel. error | worst rel. error | worst |error|/sigma | notes |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const Run& run : runs) {
    const Errors e = errors_of(run, ref);
    std::printf("| %s | %s | %s | %.3g | %.3g | %.2e | %.2e | %.1f | %s |\n", run.method.c_str(), run.setting.c_str(),
                run.size.c_str(), run.wall, run.cpu, e.rms, e.worst, e.worst_sigma, run.note.c_str());
  }
  const Run* finest = nullptr;
  for (const Run& run : runs)
    if (!run.direct.empty()) finest = &run;
  std::printf("\nPer face, irradiance H (W/m^2); the reference with its standard error and its direct share "
              "(next-event estimation), the last radiosity run's direct share (exact shadows):\n\n"
              "| face | area (m^2) | reference | direct | direct (rad.) |");
  for (const Run& run : runs) std::printf(" %s %s |", run.method == "radiosity" ? "rad." : "PT", run.setting.c_str());
  std::printf("\n|---|---|---|---|---|");
  for (std::size_t i = 0; i < runs.size(); ++i) std::printf("---|");
  std::printf("\n");
  for (const shadow::IrradianceEstimate& r : ref.estimates) {
    if (r.paths == 0) continue;
    std::printf("| %s | %.3g | %.4g ± %.2g | %.4g |", mesh_face(scene, r.face_id).c_str(), r.area, r.irradiance,
                r.standard_error, r.direct_irradiance);
    if (finest) std::printf(" %.4g |", finest->direct[r.face_id]);
    else std::printf(" - |");
    for (const Run& run : runs) std::printf(" %.4g |", run.h[r.face_id]);
    std::printf("\n");
  }
}

void write_csv(const std::string& path, const shadow::Scene& scene, const shadow::PathTracerResult& ref,
               const std::vector<Run>& runs) {
  std::ofstream out(path);
  out.precision(10);
  out << "method,setting,wall_s,cpu_s,face_id,face,area,irradiance,standard_error,reference,reference_standard_error\n";
  for (const Run& run : runs)
    for (const shadow::IrradianceEstimate& r : ref.estimates) {
      if (r.paths == 0) continue;
      out << run.method << ",\"" << run.setting << "\"," << run.wall << ',' << run.cpu << ',' << r.face_id << ",\""
          << mesh_face(scene, r.face_id) << "\"," << r.area << ',' << run.h[r.face_id] << ','
          << (run.se.empty() ? 0.0 : run.se[r.face_id]) << ',' << r.irradiance << ',' << r.standard_error << '\n';
    }
  if (!out) throw shadow::InputError({path, ""}, "cannot write the CSV file");
}

}  // namespace

CLI::App* add_radiosity_compare_command(CLI::App& app, RadiosityCompareOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "radiosity-compare",
      "Radiosity at several element sizes and the path tracer at several path counts against a long path-traced reference");
  cmd->add_option("--scene", o.scene, "Scene file (default: examples/cornell_room.json)");
  cmd->add_option("--element-areas", o.element_areas, "Radiosity runs: max element area (m^2) of each")
      ->delimiter(',')->check(CLI::NonNegativeNumber);
  cmd->add_option("--tolerance", o.tolerance, "Radiosity: unshot fraction to stop at")->check(CLI::PositiveNumber);
  cmd->add_option("--patch-area", o.patch_area, "Radiosity: largest shooting patch (m^2); 0: 16 elements")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--samples", o.samples, "Path-tracer runs: paths per face of each")->delimiter(',')->check(CLI::PositiveNumber);
  cmd->add_option("--reference-samples", o.reference_samples, "Paths per face of the reference")->check(CLI::PositiveNumber);
  cmd->add_option("--seed", o.seed, "Seed of the tracer runs (the reference uses seed + 1)");
  cmd->add_option("--threads", o.threads, "Threads for every method")->check(CLI::PositiveNumber);
  cmd->add_option("--csv", o.csv_path, "Write one row per run and face to this file");
  cmd->add_flag("--no-radiosity", o.no_radiosity, "Only the path-tracer runs against the reference");
  cmd->add_flag("--quick", o.quick, "Smoke run: element sizes, path counts and reference replaced by 4 m^2, 16 and 64 paths, 4,096");
  return cmd;
}

int run_radiosity_compare(const RadiosityCompareOptions& options) {
  RadiosityCompareOptions o = options;
  if (o.no_radiosity) o.element_areas.clear();
  if (o.quick) {
    if (!o.no_radiosity) o.element_areas = {4.0};
    o.samples = {16, 64};
    o.reference_samples = std::min<std::uint64_t>(o.reference_samples, 4096);
  }
  const std::string file = o.scene.empty() ? std::string(LIBSHADOW_SOURCE_DIR) + "/examples/cornell_room.json" : o.scene;
  try {
    const shadow::Scene scene = shadow::load_scene(file);
    double wall = 0, cpu = 0;
    const shadow::PathTracerResult ref = trace(scene, o.reference_samples, o.seed + 1, o, wall, cpu);
    std::printf("radiosity-compare: %s, %zu faces, %u threads\n", file.c_str(), scene.faces.size(), o.threads);
    std::printf("reference: path tracer, %llu paths per face (seed %llu, Russian roulette, no depth limit), "
                "%.3g Mrays, %.3g s wall, %.3g s CPU\n",
                static_cast<unsigned long long>(o.reference_samples), static_cast<unsigned long long>(o.seed + 1),
                1e-6 * static_cast<double>(ref.rays), wall, cpu);
    std::fflush(stdout);
    std::vector<Run> runs;
    for (double a : o.element_areas) {
      runs.push_back(radiosity_run(scene, a, o));
      std::fprintf(stderr, "radiosity %g m^2: %.3g s\n", a, runs.back().wall);
    }
    for (std::uint64_t n : o.samples) runs.push_back(tracer_run(scene, n, o));
    print_tables(scene, ref, runs);
    if (!o.csv_path.empty()) write_csv(o.csv_path, scene, ref, runs);
  } catch (const shadow::InputError& e) {
    std::fprintf(stderr, "shadow-bench: error: %s\n", e.what());
    return 2;
  }
  return 0;
}

}  // namespace bench
