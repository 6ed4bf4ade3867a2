// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench golden: the areas of the benchmark scenes, the hard cases and the default example,
// bit for bit, exact and fast, reduced to one digest line per case.
//
// A restructuring or an optimisation must not move a single bit of an area: record the digests
// before the change (`--output before.tsv`), check after it (`--check before.tsv`), and, where a
// case differs, dump every value of both builds (`--write-dir`) and diff them.
#include "bench_compare.hpp"

#include <shadow/shadow.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace bench {
namespace {

struct GoldenCase {
  std::string name;
  shadow::Scene scene;
  bool planes = false;  // also the plane shadows
};

/// FNV-1a, 64 bits: a digest that does not depend on the platform's std::hash.
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

/// Every area of a result, one line per (face, light) and per plane shadow, as hex floats.
std::string canonical(const shadow::ShadowResult& result) {
  std::string out;
  char line[256];
  for (const shadow::FaceLighting& f : result.lighting) {
    std::snprintf(line, sizeof line, "face %zu light %zu area %a lit %a shadow %a fraction %a faces %d bound %a\n",
                  f.face_id, f.light_id, f.area, f.lit_area, f.shadow_area, f.lit_fraction,
                  f.faces_light ? 1 : 0, f.lit_area_error_bound);
    out += line;
  }
  for (const shadow::PlaneShadow& p : result.plane_shadows) {
    std::snprintf(line, sizeof line, "plane %zu light %zu area %a window %a reaches %d\n", p.plane_id, p.light_id,
                  p.area, p.window_half_size, p.reaches_window ? 1 : 0);
    out += line;
  }
  return out;
}

shadow::Scene rotated(shadow::Scene scene, double degrees) {
  const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), glm::radians(degrees), glm::normalize(glm::dvec3(0.3, 0.2, 1.0))));
  for (shadow::Face& f : scene.faces)
    for (glm::dvec3& v : f.vertices) v = r * v;
  for (shadow::Light& l : scene.lights) {
    l.to_light = r * l.to_light;
    l.position = r * l.position;
  }
  return scene;
}

std::vector<GoldenCase> golden_cases(const std::string& source_dir, bool quick) {
  std::vector<GoldenCase> out;
  auto city = [](std::size_t boxes) {
    shadow::Scene s = shadow::make_city(boxes, 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0), 2026);
    s.lights.push_back(shadow::directional_light("sun 40", shadow::sun_direction(40, 135)));
    s.lights.push_back(shadow::directional_light("sun 5", shadow::sun_direction(5, 135)));
    return s;
  };
  out.push_back({"city-100", city(100)});
  out.push_back({"city-100 rotated 20", rotated(city(100), 20)});
  {
    shadow::Scene s = city(100);
    s.planes.push_back({"ground", {0, 0, 0}, {0, 0, 1}});
    out.push_back({"city-100 ground plane", s, true});
  }
  if (!quick) out.push_back({"city-1000", city(1000)});
  out.push_back({"room-12", shadow::make_furnished_room(12, 11)});
  {
    shadow::Scene s = shadow::make_sphere_field(quick ? 10 : 50, 60, 7);
    s.lights.push_back(shadow::directional_light("sun 40", shadow::sun_direction(40, 135)));
    out.push_back({quick ? "spheres-10" : "spheres-50", s});
  }
  for (auto& [name, scene] : hard_case_scenes()) out.push_back({"hard: " + name, scene, !scene.planes.empty()});
  out.push_back({"examples/default", shadow::load_scene(source_dir + "/examples/default/scene.json"), true});
  return out;
}

}  // namespace

int run_golden(const std::string& source_dir, const std::string& output_path, const std::string& check_path,
               const std::string& write_dir, bool quick, unsigned threads) {
  std::map<std::string, std::string> expected;
  if (!check_path.empty()) {
    std::ifstream in(check_path);
    if (!in) {
      std::cerr << "shadow-bench golden: cannot read " << check_path << "\n";
      return 2;
    }
    std::string line;
    while (std::getline(in, line)) {
      const std::size_t tab = line.find('\t', line.find('\t') + 1);  // key: case \t method
      if (tab != std::string::npos) expected[line.substr(0, tab)] = line.substr(tab + 1);
    }
  }
  std::ofstream output;
  if (!output_path.empty()) output.open(output_path);
  int differences = 0, compared = 0;
  for (GoldenCase& c : golden_cases(source_dir, quick)) {
    shadow::validate_scene(c.scene);
    const shadow::ShadowEngine engine(c.scene, threads);
    for (shadow::Arithmetic arithmetic : {shadow::Arithmetic::Exact, shadow::Arithmetic::Fast}) {
      shadow::ShadowOptions options;
      options.threads = threads;
      options.polygons = false;
      options.arithmetic = arithmetic;
      shadow::ShadowResult result = engine.compute(options);
      if (c.planes && arithmetic == shadow::Arithmetic::Exact) result.plane_shadows = engine.compute_planes(options);
      const std::string text = canonical(result);
      double lit = 0;
      for (const shadow::FaceLighting& f : result.lighting) lit += f.lit_area;
      const char* method = arithmetic == shadow::Arithmetic::Exact ? "exact" : "fast";
      char value[128];
      std::snprintf(value, sizeof value, "%zu\t%016" PRIx64 "\t%.17g", result.lighting.size(), fnv1a(text), lit);
      const std::string key = c.name + "\t" + method;
      std::printf("%s\t%s\n", key.c_str(), value);
      if (output.is_open()) output << key << '\t' << value << '\n';
      if (!write_dir.empty()) {
        std::string file = c.name + "-" + method + ".txt";
        for (char& ch : file)
          if (ch == ' ' || ch == '/' || ch == ':') ch = '_';
        std::ofstream(write_dir + "/" + file) << text;
      }
      if (!check_path.empty()) {
        auto it = expected.find(key);
        ++compared;
        if (it == expected.end()) {
          std::printf("  MISSING in %s\n", check_path.c_str());
          ++differences;
        } else if (it->second != value) {
          std::printf("  DIFFERS: expected %s\n", it->second.c_str());
          ++differences;
        }
      }
    }
  }
  if (!check_path.empty()) {
    std::printf("golden: %d of %d cases differ from %s\n", differences, compared, check_path.c_str());
    return differences == 0 ? 0 : 1;
  }
  return 0;
}

}  // namespace bench
