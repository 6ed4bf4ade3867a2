// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench hard-cases: the hard cases of the design notes (grazing sun, shared and
// coincident faces, interpenetration, slivers, georeferenced coordinates, point lights on a
// plane, surrounded, with geometry behind them) through every method. Each case names one face
// whose answer is known in closed form (where one exists): the exact engine must match it, and
// the table shows what the baselines make of it.
#include "bench_compare.hpp"

#include <shadow/baselines.hpp>
#include <shadow/shadow.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

namespace bench {
namespace {

using shadow::Polygon3;

struct HardCase {
  std::string name;
  std::string what;          // what makes it hard
  std::function<shadow::Scene()> build;
  std::size_t face = 0;      // the face of interest
  double expected = NAN;     // its exact lit fraction, when known in closed form
  double ray_spacing = 0.05;
  bool also_without_recentring = false;  // georeferenced: show float32 at the raw coordinates
};

Polygon3 reversed(Polygon3 p) {
  std::reverse(p.begin(), p.end());
  return p;
}

std::vector<HardCase> hard_cases() {
  std::vector<HardCase> out;
  {
    // Sun 0.5 degrees above the horizon from the east: a 2 m box casts a 229 m shadow.
    const glm::dvec3 sun = shadow::sun_direction(0.5, 90);
    const double ground = 310.0 * 20.0;
    const double shadow_area = 1.0 + 2.0 * sun.x / sun.z;  // footprint + roof swept to -x
    out.push_back({"sun 0.5 deg", "grazing sun, shadow 115 box heights long",
                   [sun] {
                     shadow::Scene s;
                     shadow::add_mesh(s, "ground", {shadow::rectangle_z(-300, -10, 10, 10, 0)});
                     shadow::add_mesh(s, "box", shadow::box_faces({0, 0, 0}, {1, 1, 2}));
                     s.lights.push_back(shadow::directional_light("sun", sun));
                     return s;
                   },
                   0, (ground - shadow_area) / ground});
  }
  out.push_back({"sun parallel to a wall", "n . d = 0 exactly: zero-area shadow, edge-on wall",
                 [] {
                   shadow::Scene s;
                   shadow::add_mesh(s, "ground", {shadow::rectangle_z(-5, -5, 5, 5, 0)});
                   const Polygon3 wall{{0, 0, 0}, {2, 2, 0}, {2, 2, 3}, {0, 0, 3}};
                   shadow::add_mesh(s, "wall", {wall, reversed(wall)});
                   s.lights.push_back(shadow::directional_light("sun", {1, 1, 1}));
                   return s;
                 },
                 0, 1.0});
  out.push_back({"stacked boxes", "shared edges, coincident faces (box on box on ground)",
                 [] {
                   shadow::Scene s;
                   shadow::add_mesh(s, "ground", {shadow::rectangle_z(-5, -5, 5, 5, 0)});
                   shadow::add_mesh(s, "lower", shadow::box_faces({0, 0, 0}, {2, 2, 2}));
                   shadow::add_mesh(s, "upper", shadow::box_faces({0, 0, 2}, {2, 2, 3}));
                   s.lights.push_back(shadow::directional_light("sun", shadow::sun_direction(40, 135)));
                   return s;
                 },
                 1, 0.0});  // the lower box's top lies under the upper box's bottom
  out.push_back({"crossing boxes", "interpenetrating solids, overhead sun",
                 [] {
                   shadow::Scene s;
                   shadow::add_mesh(s, "ground", {shadow::rectangle_z(-6, -6, 6, 6, 0)});
                   shadow::add_mesh(s, "a", shadow::box_faces({-3, -0.5, 1}, {3, 0.5, 2}));
                   shadow::add_mesh(s, "b", shadow::box_faces({-0.5, -3, 0.5}, {0.5, 3, 2.5}));
                   s.lights.push_back(shadow::directional_light("sun", {0, 0, 1}));
                   return s;
                 },
                 0, (144.0 - 11.0) / 144.0});  // the cross-shaped union of footprints: 6 + 6 - 1
  out.push_back({"sliver", "an 8 m x 1 mm strip: a shadow far below any grid",
                 [] {
                   shadow::Scene s;
                   shadow::add_mesh(s, "ground", {shadow::rectangle_z(-5, -5, 5, 5, 0)});
                   shadow::add_mesh(s, "strip", {shadow::rectangle_z(-4, 0, 4, 0.001, 1)});
                   s.lights.push_back(shadow::directional_light("sun", {0, 0, 1}));
                   return s;
                 },
                 0, (100.0 - 8.0 * 0.001) / 100.0});
  out.push_back({"city-100 at 1e6", "georeferenced: coordinates near 1e6 with centimetre features",
                 [] {
                   shadow::Scene s = shadow::make_city(100, 500.0 * std::sqrt(0.1), 2026);
                   for (shadow::Face& f : s.faces)
                     for (glm::dvec3& v : f.vertices) v += glm::dvec3(1e6, 1e6, 0);
                   s.lights.push_back(shadow::directional_light("sun", shadow::sun_direction(40, 135)));
                   return s;
                 },
                 0, NAN, 0.1, true});
  out.push_back({"lamp on the ground plane", "point light in a receiver's plane: edge-on ground",
                 [] {
                   shadow::Scene s;
                   shadow::add_mesh(s, "ground", {shadow::rectangle_z(-5, -5, 5, 5, 0)});
                   shadow::add_mesh(s, "box", shadow::box_faces({1, 1, 0}, {2, 2, 1}));
                   s.lights.push_back(shadow::point_light("lamp", {0, 0, 0}));
                   return s;
                 },
                 6, 1.0});  // the box's west wall (x = 1) faces the lamp, nothing in between
  out.push_back({"room, lamp surrounded", "geometry on every side of a point light",
                 [] { return shadow::make_furnished_room(12, 11); }, 1, NAN, 0.01});
  out.push_back({"geometry behind lamp / below ground", "casters beyond the light or behind the receiver",
                 [] {
                   shadow::Scene s;
                   shadow::add_mesh(s, "ground", {shadow::rectangle_z(-5, -5, 5, 5, 0)});
                   shadow::add_mesh(s, "above", shadow::box_faces({-1, -1, 4}, {1, 1, 5}));
                   shadow::add_mesh(s, "below", shadow::box_faces({-1, -1, -2}, {1, 1, -1}));
                   s.lights.push_back(shadow::point_light("lamp", {0.1, 0.2, 3}));
                   return s;
                 },
                 0, 1.0});
  return out;
}

}  // namespace

std::vector<std::pair<std::string, shadow::Scene>> hard_case_scenes() {
  std::vector<std::pair<std::string, shadow::Scene>> out;
  for (const HardCase& c : hard_cases()) out.emplace_back(c.name, c.build());
  return out;
}

int run_hard_cases(unsigned threads, const std::string& csv_path, bool quick) {
  using Clock = std::chrono::steady_clock;
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    csv.precision(12);
    csv << "case,method,parameter,face,face_lit_fraction,expected,total_lit_rel_error,face_fraction_mean_abs_error,"
           "face_fraction_max_abs_error,seconds\n";
  }
  std::printf("| case | method | parameter | face lit fraction | expected | total lit rel. error | face error mean | face error max | time (s) |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  int wrong = 0;
  for (const HardCase& hc : hard_cases()) {
    shadow::Scene scene = hc.build();
    shadow::validate_scene(scene);
    std::vector<shadow::FaceLighting> exact;
    auto report = [&](const std::string& method, const std::string& parameter,
                      const std::vector<shadow::FaceLighting>& got, double seconds) {
      double face_fraction = NAN;
      for (const shadow::FaceLighting& fl : got)
        if (fl.face_id == hc.face) face_fraction = fl.lit_fraction;
      const Errors e = compare(got, exact);
      const double rel = e.total_rel, mean = e.mean_abs, worst = e.max_abs;
      std::printf("| %s | %s | %s | %.10f | %s | %.2e | %.2e | %.2e | %.3f |\n", hc.name.c_str(), method.c_str(),
                  parameter.c_str(), face_fraction,
                  std::isnan(hc.expected) ? "-" : std::to_string(hc.expected).c_str(), rel, mean, worst, seconds);
      std::fflush(stdout);
      if (csv.is_open())
        csv << '"' << hc.name << "\"," << method << ',' << parameter << ',' << hc.face << ',' << face_fraction << ','
            << hc.expected << ',' << rel << ',' << mean << ',' << worst << ',' << seconds << '\n';
    };
    {
      const auto t0 = Clock::now();
      shadow::ShadowOptions options;
      options.threads = threads;
      options.polygons = false;
      exact = shadow::compute_shadows(scene, options).lighting;
      const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
      report("exact", "-", exact, seconds);
      for (const shadow::FaceLighting& fl : exact)
        if (fl.face_id == hc.face && !std::isnan(hc.expected) &&
            std::abs(fl.lit_fraction - hc.expected) > 1e-12 * std::max(1.0, std::abs(hc.expected))) {
          std::fprintf(stderr, "hard-cases: %s: exact lit fraction %.17g, expected %.17g\n", hc.name.c_str(),
                       fl.lit_fraction, hc.expected);
          ++wrong;
        }
    }
    {
      // The fast path: each face's lit area must lie within its certified bound of the exact one.
      const auto t0 = Clock::now();
      shadow::ShadowOptions options;
      options.threads = threads;
      options.polygons = false;
      options.arithmetic = shadow::Arithmetic::Fast;
      const std::vector<shadow::FaceLighting> fast = shadow::compute_shadows(scene, options).lighting;
      report("fast", "-", fast, std::chrono::duration<double>(Clock::now() - t0).count());
      for (std::size_t e = 0; e < fast.size() && e < exact.size(); ++e)
        if (std::abs(fast[e].lit_area - exact[e].lit_area) > fast[e].lit_area_error_bound) {
          std::fprintf(stderr, "hard-cases: %s: fast lit area of face %zu off by %.3g, beyond its bound %.3g\n",
                       hc.name.c_str(), fast[e].face_id, std::abs(fast[e].lit_area - exact[e].lit_area),
                       fast[e].lit_area_error_bound);
          ++wrong;
        }
    }
    for (bool recentre : {true, false}) {
      if (!recentre && !hc.also_without_recentring) continue;
      const std::string suffix = recentre ? "" : " (raw float32)";
      // The shadow map here works in double up to the stored float depth, so raw coordinates
      // would only show through the depth: the raw-float32 row is the rays' (Embree's vertices).
      for (int resolution : quick ? std::vector<int>{256, 1024} : std::vector<int>{1024, 4096}) {
        if (!recentre) break;
        shadow::ShadowMapOptions options;
        options.resolution = resolution;
        options.threads = threads;
        options.recentre = recentre;
        const auto t0 = Clock::now();
        const shadow::BaselineResult b = shadow::shadow_map_lighting(scene, options);
        report("shadow-map" + suffix, std::to_string(resolution), b.lighting,
               std::chrono::duration<double>(Clock::now() - t0).count());
      }
      shadow::RaySamplingOptions options;
      options.spacing = hc.ray_spacing;
      options.threads = threads;
      options.recentre = recentre;
      const auto t0 = Clock::now();
      const shadow::BaselineResult b = shadow::ray_sampling_lighting(scene, options);
      char parameter[32];
      std::snprintf(parameter, sizeof parameter, "%g m", hc.ray_spacing);
      report("ray-sampling" + suffix, parameter, b.lighting, std::chrono::duration<double>(Clock::now() - t0).count());
    }
  }
  return wrong == 0 ? 0 : 1;
}

}  // namespace bench
