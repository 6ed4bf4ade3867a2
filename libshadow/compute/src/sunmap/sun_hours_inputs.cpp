// SPDX-License-Identifier: GPL-3.0-or-later
// The sun-hours map's inputs and summaries (shadow/sun_hours.hpp): which faces and instants a
// scene asks for, the levels given on the command line, the level areas reported, and a
// threshold map added to a map computed without one.
#include "sunmap/sun_hours_inputs.hpp"

#include "core/lights.hpp"

#include <shadow/error.hpp>
#include <shadow/series.hpp>
#include <shadow/sun_hours.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace shadow {

namespace sunmap {

/// The instants' weights, their lights and weights checked.
std::vector<double> checked_hours(const std::vector<SunHoursInstant>& instants) {
  std::vector<double> hours(instants.size());
  for (std::size_t i = 0; i < instants.size(); ++i) {
    const std::string path = "instants[" + std::to_string(i) + "]";
    shadow::detail::check_light(instants[i].light, "", path + ".light");
    const double w = instants[i].hours;
    if (!std::isfinite(w) || w < 0)
      throw InputError({"", path + ".hours"}, "hours must be finite and >= 0, got " + std::to_string(w));
    hours[i] = w;
  }
  return hours;
}

namespace {

/// The fraction of denominator at most kMaxDenominator that rounds to `w` (>= 0, finite), else w.
/// Such a fraction p/q is within half an ulp of w, far less than 1 / (2 q^2), so it is one of
/// w's continued-fraction convergents (Legendre): those are tried in turn.
mpq_class exact_weight(double w) {
  constexpr unsigned long kMaxDenominator = 1000000;
  const mpq_class value(w);
  if (w == 0.0 || value.get_den() == 1) return value;
  // Strictly inside the rounding interval of w: rounds to w whatever the tie rule.
  const mpq_class below(std::nextafter(w, 0.0)), above(std::nextafter(w, HUGE_VAL));
  const mpq_class lo = (below + value) / 2, hi = (value + above) / 2;
  mpz_class h0 = 1, h1 = 0, k0 = 0, k1 = 1;  // convergents h/k: (h0/k0) the latest, (h1/k1) the one before
  mpq_class x = value;
  for (int steps = 0; steps < 64; ++steps) {
    mpz_class a;
    mpz_fdiv_q(a.get_mpz_t(), x.get_num_mpz_t(), x.get_den_mpz_t());
    const mpz_class h = a * h0 + h1, k = a * k0 + k1;
    if (k > kMaxDenominator) break;
    const mpq_class candidate(h, k);  // (in lowest terms: convergents are)
    if (lo < candidate && candidate < hi) return candidate;
    h1 = h0, k1 = k0, h0 = h, k0 = k;
    x -= a;
    if (x == 0) break;
    x = 1 / x;
  }
  return value;
}

}  // namespace

std::vector<mpq_class> exact_hours(const std::vector<double>& hours) {
  std::vector<mpq_class> exact;
  exact.reserve(hours.size());
  for (double w : hours) exact.push_back(exact_weight(w));
  return exact;
}

/// The face ids checked, ascending, repeats dropped.
std::vector<std::size_t> checked_faces(const Scene& scene, const std::vector<std::size_t>& faces_in) {
  std::vector<std::size_t> faces;
  for (std::size_t k = 0; k < faces_in.size(); ++k) {
    if (faces_in[k] >= scene.faces.size())
      throw InputError({"", "sun-hours map faces[" + std::to_string(k) + "]"},
                       "face id " + std::to_string(faces_in[k]) + " is out of range (the scene has " +
                           std::to_string(scene.faces.size()) + " faces)");
    faces.push_back(faces_in[k]);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

/// Checks and sorts the levels: ascending, repeats dropped.
std::vector<double> checked_levels(const std::vector<double>& levels) {
  for (std::size_t k = 0; k < levels.size(); ++k)
    if (!std::isfinite(levels[k]) || levels[k] < 0)
      throw InputError({"", "levels[" + std::to_string(k) + "]"},
                       "a level must be finite and >= 0 hours, got " + std::to_string(levels[k]));
  std::vector<double> out = levels;
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace sunmap

std::vector<double> sun_hours_level_areas(const SunHoursMap& map) {
  std::vector<double> out(map.levels.size(), 0.0);
  for (const SunHoursFace& f : map.faces)
    for (std::size_t k = 0; k < f.level_areas.size() && k < out.size(); ++k) out[k] += f.level_areas[k];
  return out;
}

double sun_hours_map_area(const SunHoursMap& map) {
  double area = 0.0;
  for (const SunHoursFace& f : map.faces) area += f.area;
  return area;
}

std::string sun_hours_levels_summary(const SunHoursMap& map, const std::string& indent) {
  if (map.levels.empty()) return {};
  const double area = sun_hours_map_area(map);
  const std::vector<double> at_least = sun_hours_level_areas(map);
  std::string out;
  char line[256];
  for (std::size_t k = 0; k < map.levels.size(); ++k) {
    std::snprintf(line, sizeof line, "%sat least %g h of sun: area %.6g of %.6g (%.1f%%)\n", indent.c_str(), map.levels[k],
                  at_least[k], area, area > 0 ? 100.0 * at_least[k] / area : 0.0);
    out += line;
  }
  std::snprintf(line, sizeof line, "%sthreshold map: %zu cells (sun_hours_levels.vtp)\n", indent.c_str(), map.level_cells.size());
  out += line;
  return out;
}

std::vector<double> parse_sun_hours_levels(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::string where = what + " item " + std::to_string(out.size() + 1);
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used == 0 || item.find_first_not_of(" \t", used) != std::string::npos)
      throw InputError({"", where}, "expected a number of hours, got \"" + item + "\"");
    if (!std::isfinite(value) || value < 0)
      throw InputError({"", where}, "a level must be finite and >= 0 hours, got \"" + item + "\"");
    out.push_back(value);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<std::size_t> sun_hours_map_faces(const Scene& scene) {
  std::vector<std::size_t> faces;
  for (std::size_t k = 0; k < scene.sun_hours_map.size(); ++k) {
    const std::size_t m = scene.sun_hours_map[k];
    if (m >= scene.meshes.size())  // a scene built in code: load_scene only stores valid indices
      throw InputError({scene.source.string(), "sun_hours_map[" + std::to_string(k) + "]"},
                       "mesh index " + std::to_string(m) + " is out of range (the scene has " +
                           std::to_string(scene.meshes.size()) + " meshes)");
    const Mesh& mesh = scene.meshes[m];
    for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count; ++f) faces.push_back(f);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

std::vector<std::size_t> sun_hours_map_faces(const Scene& scene, const std::vector<std::string>& mesh_names,
                                             const std::string& what) {
  Scene chosen;
  chosen.meshes = scene.meshes;
  // A mesh's name, or type:<T> for every mesh of a CityJSON object type (select_meshes).
  for (std::size_t k = 0; k < mesh_names.size(); ++k)
    for (std::size_t m : select_meshes(scene, mesh_names[k], {"", what})) chosen.sun_hours_map.push_back(m);
  return sun_hours_map_faces(chosen);
}

std::vector<SunHoursInstant> sun_hours_instants(const Scene& scene) {
  std::vector<SunHoursInstant> out;
  if (!scene.sun) return out;
  const double step_hours = hours_per_instant(*scene.sun);  // the series' rule (shadow/series.hpp)
  for (const SunInstant& instant : scene.sun_instants) {
    if (instant.light_id == SunInstant::none || instant.light_id >= scene.lights.size()) continue;
    out.push_back({scene.lights[instant.light_id], step_hours});
  }
  return out;
}

std::vector<SunHoursInstant> sun_hours_instants(const SunSeries& suns) {
  std::vector<SunHoursInstant> out;
  out.reserve(suns.lights.size());
  for (const Light& light : suns.lights) out.push_back({light, suns.hours_per_instant});
  return out;
}

void add_sun_hours_levels(SunHoursMap& map, const ShadowEngine& engine, const std::vector<std::size_t>& faces,
                          const std::vector<SunHoursInstant>& instants, const std::vector<double>& levels,
                          unsigned threads) {
  SunHoursOptions options;
  options.threads = threads;
  options.levels = levels;
  options.full = false;
  SunHoursMap with = compute_sun_hours_map(engine, faces, instants, options);
  if (with.faces.size() != map.faces.size())
    throw std::invalid_argument("add_sun_hours_levels: the map has other faces than those given");
  for (std::size_t k = 0; k < map.faces.size(); ++k) {
    if (with.faces[k].face_id != map.faces[k].face_id)
      throw std::invalid_argument("add_sun_hours_levels: the map has other faces than those given");
    map.faces[k].level_areas = std::move(with.faces[k].level_areas);
  }
  map.levels = std::move(with.levels);
  map.level_cells = std::move(with.level_cells);
  map.level_regions = with.level_regions;
}

}  // namespace shadow
