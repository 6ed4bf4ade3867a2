// SPDX-License-Identifier: GPL-3.0-or-later
// Measures the fast path against the exact engine (docs/numeric-contract.md, "The fast path"):
// the same scene and light computed exactly and fast, alternately in one run (the machines are
// shared and noisy: compare the ratios), with the largest lit-area error against the exact
// result and the largest reported bound. Not a test and not the benchmark.
//
//   fast-vs-exact [--boxes N] [--extent M] [--repeats R] [--room] [--elevation E...]
//                 [--threads T...] [--areas-only] [--rotate DEGREES]
#include <shadow/shadow.hpp>

#include <CLI/CLI.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

struct Run {
  double seconds = 0;
  shadow::ShadowResult result;
};

Run timed(const shadow::ShadowEngine& engine, const shadow::Light& light, shadow::ShadowOptions options) {
  const auto start = std::chrono::steady_clock::now();
  Run run;
  run.result = engine.compute(light, 0, options);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fast-vs-exact: the fast path's speed and error against the exact engine"};
  std::size_t boxes = 1000;
  double extent = 500;
  int repeats = 3;
  bool room = false;
  bool areas_only = false;
  double rotate = 0;
  std::vector<double> elevations{40, 5};
  std::vector<unsigned> thread_counts{1, 2};
  app.add_option("--boxes", boxes, "Boxes in the city")->default_val(1000);
  app.add_option("--extent", extent, "Side of the city (m)")->default_val(500);
  app.add_option("--repeats", repeats, "Alternating exact/fast runs per case (fastest kept)")->default_val(3);
  app.add_flag("--room", room, "The furnished room under its ceiling lamp instead of the city");
  app.add_option("--elevation", elevations, "Sun elevations (degrees), azimuth 135")->default_str("40 5");
  app.add_option("--threads", thread_counts, "Thread counts")->default_str("1 2");
  app.add_flag("--areas-only", areas_only, "Only the runs without polygons");
  app.add_option("--rotate", rotate,
                 "Rotate the scene (and lights) by this angle about (0.3, 0.2, 1): faces are then "
                 "planar only within tolerance");
  CLI11_PARSE(app, argc, argv);

  shadow::Scene scene = room ? shadow::make_furnished_room(12, 2026) : shadow::make_city(boxes, extent, 2026);
  std::vector<std::pair<std::string, shadow::Light>> lights;
  if (room) {
    lights.emplace_back("lamp", scene.lights.at(0));
  } else {
    for (double e : elevations)
      lights.emplace_back("sun " + std::to_string(static_cast<int>(std::lround(e))),
                          shadow::directional_light("sun", shadow::sun_direction(e, 135)));
  }
  if (rotate != 0) {
    const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), glm::radians(rotate), glm::normalize(glm::dvec3(0.3, 0.2, 1.0))));
    for (shadow::Face& f : scene.faces)
      for (glm::dvec3& v : f.vertices) v = r * v;
    for (auto& named : lights) {
      named.second.to_light = r * named.second.to_light;
      named.second.position = r * named.second.position;
    }
    shadow::validate_scene(scene);
  }
  const shadow::ShadowEngine engine(scene, 2);
  std::printf("| light | threads | polygons | exact (s) | fast (s) | speed-up | max abs error | max bound | max error/bound | sum abs error / lit area | sum bound / lit area | mean abs lit-fraction error | fallbacks | collapsed |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& [name, light] : lights) {
    for (unsigned threads : thread_counts) {
      for (bool polygons : {false, true}) {
        if (polygons && areas_only) continue;
        shadow::ShadowOptions options;
        options.threads = threads;
        options.polygons = polygons;
        double best_exact = 1e300, best_fast = 1e300;
        shadow::ShadowResult exact, fast;
        for (int r = 0; r < repeats; ++r) {
          options.arithmetic = shadow::Arithmetic::Exact;
          Run e = timed(engine, light, options);
          options.arithmetic = shadow::Arithmetic::Fast;
          Run f = timed(engine, light, options);
          best_exact = std::min(best_exact, e.seconds);
          best_fast = std::min(best_fast, f.seconds);
          exact = std::move(e.result);
          fast = std::move(f.result);
        }
        double max_error = 0, max_bound = 0, max_ratio = 0, sum_error = 0, lit = 0, sum_bound = 0;
        double fraction_error = 0;
        std::size_t faces = 0;
        for (std::size_t a = 0; a < exact.lighting.size(); ++a) {
          const double err = std::abs(fast.lighting[a].lit_area - exact.lighting[a].lit_area);
          const double bound = fast.lighting[a].lit_area_error_bound;
          max_error = std::max(max_error, err);
          max_bound = std::max(max_bound, bound);
          if (err > 0) max_ratio = std::max(max_ratio, bound > 0 ? err / bound : 1e300);
          sum_error += err;
          sum_bound += bound;
          lit += exact.lighting[a].lit_area;
          if (exact.lighting[a].area > 0) {
            fraction_error += std::abs(fast.lighting[a].lit_fraction - exact.lighting[a].lit_fraction);
            ++faces;
          }
        }
        std::printf("| %s | %u | %s | %.3f | %.3f | %.2f | %.3g | %.3g | %.3g | %.3g | %.3g | %.3g | %llu | %llu |\n",
                    name.c_str(), threads, polygons ? "yes" : "no", best_exact, best_fast,
                    best_exact / best_fast, max_error, max_bound, max_ratio, lit > 0 ? sum_error / lit : 0.0,
                    lit > 0 ? sum_bound / lit : 0.0, faces ? fraction_error / static_cast<double>(faces) : 0.0,
                    static_cast<unsigned long long>(fast.stats.fast_exact_fallbacks),
                    static_cast<unsigned long long>(fast.stats.fast_collapsed));
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
