// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz target: bytes -> a small scene (1-5 faces of 3-8 vertices with small dyadic coordinates,
// one directional or point light) -> validate_scene (an InputError ends the input) -> the exact
// engine and the fast path, areas only and with polygons. Aborts when an invariant breaks:
//   0 <= lit_area <= area, lit_area + shadow_area == area within rounding,
//   the fragments of each (face, light) cover the face (areas sum to it within 1e-9 relative),
//   and the fast lit area lies within its lit_area_error_bound (+ rounding) of the exact one;
//   the exact sun-hours map under the light as one instant of one hour (its cells cut from each
//   lit region's boundary, exact_lit_boundary) gives every face's 1-hour cells exactly the lit
//   area and its 0-hour cells exactly the shadow area, as the engine measured them (both exact,
//   rounded once: bit for bit).
#include <shadow/shadow.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {

/// Reads the input byte by byte; past its end every byte is 0 (short inputs still decode).
struct Bytes {
  const std::uint8_t* p;
  std::size_t n;
  std::uint8_t next() {
    if (n == 0) return 0;
    --n;
    return *p++;
  }
  /// A coordinate in quarters: -32 .. 31.75, exactly representable (as are the products the
  /// engine forms of a few of them), so the exact answer is the one the scene means.
  double coordinate() { return static_cast<std::int8_t>(next()) / 4.0; }
};

const shadow::Scene* current = nullptr;  // for the report on a violation

[[noreturn]] void violation(const std::string& what) {
  std::fprintf(stderr, "fuzz_engine: invariant violated: %s\n", what.c_str());
  if (current) {
    for (std::size_t f = 0; f < current->faces.size(); ++f) {
      std::fprintf(stderr, "  face %zu:", f);
      for (const glm::dvec3& v : current->faces[f].vertices) std::fprintf(stderr, " (%g %g %g)", v.x, v.y, v.z);
      std::fprintf(stderr, "\n");
    }
    for (const shadow::Light& l : current->lights) {
      const glm::dvec3 v = l.type == shadow::LightType::Point ? l.position : l.to_light;
      std::fprintf(stderr, "  light %s (%g %g %g)\n", l.type == shadow::LightType::Point ? "point" : "directional",
                   v.x, v.y, v.z);
    }
  }
  std::abort();
}

std::string where(const char* run, const shadow::FaceLighting& l) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s: face %zu light %zu (area %.17g lit %.17g shadow %.17g bound %.3g)", run,
                l.face_id, l.light_id, l.area, l.lit_area, l.shadow_area, l.lit_area_error_bound);
  return buf;
}

/// Rounding allowance: `k` roundings of a value of magnitude `area`.
double ulps(double area, double k) { return k * 1.12e-16 * area; }

void check_result(const char* run, const shadow::ShadowResult& r, bool polygons) {
  for (const shadow::FaceLighting& l : r.lighting) {
    if (!std::isfinite(l.area) || !std::isfinite(l.lit_area) || !std::isfinite(l.shadow_area) ||
        !std::isfinite(l.lit_area_error_bound) || l.lit_area_error_bound < 0)
      violation(where(run, l) + ": not finite or negative bound");
    if (!(l.lit_area >= 0 && l.lit_area <= l.area)) violation(where(run, l) + ": lit area outside [0, area]");
    // Exact: lit and shadow are each the exact value rounded once. Fast: each within the bound.
    const double slack = ulps(l.area, 4) + 2 * l.lit_area_error_bound;
    if (!(std::abs(l.lit_area + l.shadow_area - l.area) <= slack)) violation(where(run, l) + ": lit + shadow != area");
  }
  if (!polygons) return;
  std::map<std::pair<std::size_t, std::size_t>, std::pair<double, double>> sums;  // (all, lit)
  for (const shadow::Fragment& f : r.fragments) {
    if (!std::isfinite(f.area) || f.area < 0) violation(std::string(run) + ": a fragment's area is not finite or negative");
    auto& s = sums[{f.face_id, f.light_id}];
    s.first += f.area;
    if (f.lit) s.second += f.area;
  }
  for (const shadow::FaceLighting& l : r.lighting) {
    if (l.area == 0) continue;
    const auto it = sums.find({l.face_id, l.light_id});
    const double all = it == sums.end() ? 0.0 : it->second.first;
    const double lit = it == sums.end() ? 0.0 : it->second.second;
    const double tolerance = 1e-9 * l.area + l.lit_area_error_bound;
    if (!(std::abs(all - l.area) <= tolerance))
      violation(where(run, l) + ": fragments sum to " + std::to_string(all) + ", not the face area");
    if (!(std::abs(lit - l.lit_area) <= tolerance))
      violation(where(run, l) + ": lit fragments sum to " + std::to_string(lit) + ", not the lit area");
  }
}

/// The sun-hours map of every face under the scene's light as one instant of one hour against
/// the engine's exact areas: the cells of 1 hour are the lit region, those of 0 hours the rest.
void check_sun_hours_map(const shadow::Scene& scene, const shadow::ShadowResult& exact) {
  const shadow::ShadowEngine engine(scene, 1);
  std::vector<std::size_t> faces(scene.faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) faces[f] = f;
  shadow::SunHoursOptions options;
  options.threads = 1;
  const shadow::SunHoursMap map = shadow::compute_sun_hours_map(engine, faces, {{scene.lights[0], 1.0}}, options);
  for (const shadow::FaceLighting& l : exact.lighting) {
    if (l.area == 0) continue;
    const shadow::SunHoursFace* face = nullptr;
    for (const shadow::SunHoursFace& m : map.faces)
      if (m.face_id == l.face_id) face = &m;
    if (face == nullptr) violation(where("sun-hours map", l) + ": face missing from the map");
    double lit = 0, dark = 0;
    for (const shadow::SunHoursArea& a : face->areas) {
      if (a.sun_hours == 1.0) lit = a.area;
      else if (a.sun_hours == 0.0) dark = a.area;
      else violation(where("sun-hours map", l) + ": hours other than 0 and 1");
    }
    if (lit != l.lit_area || face->hour_area != l.lit_area)
      violation(where("sun-hours map", l) + ": 1-hour cells " + std::to_string(lit) + ", integral " +
                std::to_string(face->hour_area) + ", not the lit area");
    if (dark != l.shadow_area)
      violation(where("sun-hours map", l) + ": 0-hour cells " + std::to_string(dark) + ", not the shadow area");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // LIBSHADOW_FUZZ_VERBOSE=1: say whether each input was rejected or checked (corpus upkeep).
  static const bool verbose = std::getenv("LIBSHADOW_FUZZ_VERBOSE") != nullptr;
  Bytes in{data, size};
  const std::uint8_t header = in.next();
  const bool point = (header & 1) != 0;
  const int face_count = 1 + (header >> 1) % 5;

  shadow::Scene scene;
  const glm::dvec3 light{in.coordinate(), in.coordinate(), in.coordinate()};
  scene.lights.push_back(point ? shadow::point_light("lamp", light) : shadow::directional_light("sun", light));
  std::vector<shadow::Polygon3> faces;
  for (int f = 0; f < face_count; ++f) {
    const std::uint8_t shape = in.next();
    const int vertex_count = 3 + shape % 6;
    const int kind = (shape / 6) % 5;  // z, x or y = c; free 3D; a sloped plane
    const double c = in.coordinate();
    const int a = static_cast<std::int8_t>(in.next()) % 3, b = static_cast<std::int8_t>(in.next()) % 3;
    shadow::Polygon3 polygon;
    for (int v = 0; v < vertex_count; ++v) {
      const double u = in.coordinate(), w = in.coordinate();
      switch (kind) {
        case 0: polygon.emplace_back(u, w, c); break;
        case 1: polygon.emplace_back(c, u, w); break;
        case 2: polygon.emplace_back(u, c, w); break;
        case 3: polygon.emplace_back(u, w, in.coordinate()); break;  // triangles: any plane
        default: polygon.emplace_back(u, w, (a * u + b * w) / 4 + c); break;  // exact: dyadic
      }
    }
    faces.push_back(std::move(polygon));
  }
  shadow::add_mesh(scene, "fuzz", faces);
  try {
    shadow::validate_scene(scene);
  } catch (const shadow::InputError& e) {
    // Non-planar, self-intersecting, zero light direction, ...: rejected, as it should be.
    if (verbose) std::fprintf(stderr, "fuzz_engine: rejected: %s\n", e.what());
    return 0;
  }
  current = &scene;

  shadow::ShadowOptions options;
  options.threads = 1;
  options.planes = false;
  const char* names[2][2] = {{"exact areas", "exact polygons"}, {"fast areas", "fast polygons"}};
  shadow::ShadowResult results[2][2];
  for (int fast = 0; fast < 2; ++fast) {
    for (int polygons = 0; polygons < 2; ++polygons) {
      options.arithmetic = fast ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
      options.polygons = polygons != 0;
      results[fast][polygons] = shadow::compute_shadows(scene, options);  // no InputError after validation
      check_result(names[fast][polygons], results[fast][polygons], polygons != 0);
    }
  }
  for (int polygons = 0; polygons < 2; ++polygons) {
    const auto& exact = results[0][polygons].lighting;
    const auto& fast = results[1][polygons].lighting;
    if (exact.size() != fast.size() || exact.size() != results[0][1 - polygons].lighting.size())
      violation("exact and fast (or areas and polygons) have different numbers of entries");
    for (std::size_t k = 0; k < exact.size(); ++k) {
      const shadow::FaceLighting& e = exact[k];
      const shadow::FaceLighting& f = fast[k];
      if (e.face_id != f.face_id || e.light_id != f.light_id || e.area != f.area)
        violation(where("fast", f) + ": a different entry than exact's");
      if (e.lit_area_error_bound != 0) violation(where("exact", e) + ": exact result with a non-zero bound");
      if (e.lit_area != results[0][1 - polygons].lighting[k].lit_area)
        violation(where("exact", e) + ": areas-only and polygon runs differ");
      if (!(std::abs(f.lit_area - e.lit_area) <= f.lit_area_error_bound + ulps(e.area, 2)))
        violation(where(names[1][polygons], f) + ": farther than its bound from exact " +
                  std::to_string(e.lit_area));
    }
  }
  check_sun_hours_map(scene, results[0][0]);
  if (verbose)
    std::fprintf(stderr, "fuzz_engine: checked %zu faces, %zu fragments\n", scene.faces.size(),
                 results[0][1].fragments.size());
  current = nullptr;
  return 0;
}
