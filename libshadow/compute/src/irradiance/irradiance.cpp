// SPDX-License-Identifier: GPL-3.0-or-later
// compute_irradiance (shadow/irradiance.hpp): the sky patches as one series of directional
// lights (each face's view of the sky, once for the period), the sun of every hour as another
// (each face's exact sunlit fraction), then per face and hour the direct, sky diffuse and
// ground-reflected irradiance summed over the period. docs/irradiance.md.
#include <shadow/irradiance.hpp>

#include <shadow/error.hpp>

#include "geometry/newell_normal.hpp"
#include "irradiance/ground_view.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <chrono>
#include <cmath>
#include <string>

namespace shadow {

namespace {

constexpr double kPi = 3.14159265358979323846;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

SeriesOptions with_progress(const IrradianceOptions& options, const char* stage) {
  SeriesOptions series = options.series;
  if (options.progress) {
    const auto& report = options.progress;
    series.progress = [report, stage](const Progress& p) { report(stage, p); };
  } else {
    series.progress = nullptr;
  }
  return series;
}

/// Each row's unit normal (Newell's, relative to the first vertex).
std::vector<glm::dvec3> row_normals(const Scene& scene, const std::vector<std::size_t>& faces) {
  std::vector<glm::dvec3> normals;
  normals.reserve(faces.size());
  for (std::size_t f : faces) {
    const std::vector<glm::dvec3>& v = scene.faces[f].vertices;
    const glm::dvec3 n = v.empty() ? glm::dvec3(0.0) : geometry::newell_normal(v, v.front());
    const double length = glm::length(n);
    normals.push_back(length > 0.0 ? n / length : glm::dvec3(0.0, 0.0, 1.0));
  }
  return normals;
}

/// Each row's sky view factor and visible share of the horizon band, from the patches' lit
/// fractions: sum of lit fraction x cos x solid angle, scaled so that an unobstructed face gets
/// exactly (1 + cos tilt) / 2 (the patch centres' sum is not exactly that).
void view_factors(IrradianceResult& r) {
  const std::size_t rows = r.faces.size();
  r.sky_view_factor.assign(rows, 0.0);
  r.horizon_view.assign(rows, 0.0);
  r.sky_view_factor_error_bound.assign(rows, 0.0);
  const bool fast = r.sky.arithmetic == Arithmetic::Fast;
  for (std::size_t row = 0; row < rows; ++row) {
    double seen = 0.0, open = 0.0, horizon_seen = 0.0, horizon_open = 0.0, bound = 0.0;
    for (std::size_t p = 0; p < r.patches.size(); ++p) {
      const double c = glm::dot(r.normal[row], r.patches[p].to_patch);
      if (!(c > 0.0)) continue;
      const double weight = c * r.patches[p].solid_angle;
      const double lit = r.sky.lit_fraction[r.sky.at(row, p)];
      seen += lit * weight;
      open += weight;
      if (fast && r.area[row] > 0.0) bound += r.sky.lit_area_error_bound[r.sky.at(row, p)] / r.area[row] * weight;
      if (r.patches[p].horizon) {
        horizon_seen += lit * weight;
        horizon_open += weight;
      }
    }
    const double cos_tilt = std::clamp(r.normal[row].z, -1.0, 1.0);
    r.sky_view_factor[row] = open > 0.0 ? 0.5 * (1.0 + cos_tilt) * (seen / open) : 0.0;
    r.horizon_view[row] = horizon_open > 0.0 ? horizon_seen / horizon_open : 0.0;
    r.sky_view_factor_error_bound[row] = open > 0.0 ? 0.5 * (1.0 + cos_tilt) * (bound / open) : 0.0;
  }
}

/// The period's hours: the sun at mid-hour, the weather's irradiance, Perez's coefficients.
void sky_of_hours(IrradianceResult& r, const Weather& weather, const IrradianceOptions& options, std::size_t first,
                  std::size_t end) {
  SolarSite site;
  site.latitude = weather.location.latitude;
  site.longitude = weather.location.longitude;
  site.elevation = weather.location.elevation;
  // The standard atmosphere's pressure at the site's elevation, for refraction.
  site.pressure = 1013.25 * std::pow(1.0 - 2.25577e-5 * std::max(0.0, site.elevation), 5.25588);
  for (std::size_t rec = first; rec < end; ++rec) {
    IrradianceHour h;
    h.record = rec;
    const SunPosition sun = solar_position(site, weather.start_utc[rec] + 1800, options.north_axis, options.delta_t);
    h.zenith = sun.zenith;
    h.to_sun = sun.to_light;
    // A missing value counts 0, the other of the two kept (as EnergyPlus's weather manager
    // does): an hour with only its diffuse measured still lights the faces with it. Both
    // missing: the hour adds nothing, whatever its global horizontal value says.
    double dni = weather.direct_normal[rec], dhi = weather.diffuse_horizontal[rec];
    h.missing = std::isnan(dni) || std::isnan(dhi);
    if (h.missing) ++r.missing_hours;
    if (std::isnan(dni) && std::isnan(dhi)) {
      r.hours.push_back(h);
      continue;
    }
    if (std::isnan(dni)) dni = 0.0;
    if (std::isnan(dhi)) dhi = 0.0;
    const double cos_zenith = std::cos(sun.zenith * kPi / 180.0);
    h.dhi = dhi;
    h.dni = sun.elevation > 0.0 ? dni : 0.0;  // no beam from a sun below the horizon at mid-hour
    h.ghi = std::isnan(weather.global_horizontal[rec]) ? h.dni * std::max(0.0, cos_zenith) + dhi
                                                       : weather.global_horizontal[rec];
    if (options.sky == SkyModel::Perez && sun.elevation > 0.0) {
      // The record's own calendar year (a file from July to June runs through two).
      const std::int64_t local = weather.start_utc[rec] + std::llround(weather.location.time_zone_hours * 3600.0);
      const std::int64_t day = local >= 0 ? local / 86400 : -((-local + 86399) / 86400);
      const int doy = static_cast<int>(day - days_from_civil(civil_from_days(day).year, 1, 1)) + 1;
      h.perez = perez_sky(dhi, h.dni, sun.zenith, extraterrestrial_normal(doy), relative_airmass(sun.zenith));
    }
    if (sun.elevation > 0.0 && (h.dni > 0.0 || h.perez.f1 > 0.0)) {
      h.sun = r.sun_lights.size();
      Light light;
      light.name = "sun " + std::to_string(rec);
      light.to_light = sun.to_light;
      r.sun_lights.push_back(light);
    }
    r.hours.push_back(h);
  }
}

/// The period's sums per row and month, and the energy checks.
void sum_rows(IrradianceResult& r, const Weather& weather) {
  const std::size_t rows = r.faces.size();
  for (auto* v : {&r.direct, &r.sky_diffuse, &r.ground_reflected, &r.total, &r.sky_diffuse_unshaded, &r.direct_unshaded})
    v->assign(rows, 0.0);
  for (auto* v : {&r.monthly_direct, &r.monthly_sky_diffuse, &r.monthly_ground_reflected, &r.monthly_total})
    v->assign(rows * 12, 0.0);
  for (std::size_t row = 0; row < rows; ++row) {
    double direct = 0.0, diffuse = 0.0, reflected = 0.0, diffuse_open = 0.0, direct_open = 0.0;
    for (std::size_t h = 0; h < r.hours.size(); ++h) {
      const FaceIrradiance e = face_irradiance(r, row, h);
      direct += e.direct;  // Wh/m2: each hour's mean W/m2 times one hour
      diffuse += e.sky_diffuse;
      reflected += e.ground_reflected;
      diffuse_open += e.sky_diffuse_unshaded;
      direct_open += e.direct_unshaded;
      const std::size_t m = row * 12 + static_cast<std::size_t>(r.month_of(h, weather) - 1);
      r.monthly_direct[m] += e.direct / 1000.0;
      r.monthly_sky_diffuse[m] += e.sky_diffuse / 1000.0;
      r.monthly_ground_reflected[m] += e.ground_reflected / 1000.0;
      r.monthly_total[m] += e.total() / 1000.0;
      r.max_direct_excess = std::max(r.max_direct_excess, e.direct - e.direct_unshaded);
      const double diffuse_excess = e.sky_diffuse - e.sky_diffuse_unshaded;
      r.max_diffuse_excess = std::max(r.max_diffuse_excess, diffuse_excess - e.sky_diffuse_horizon_allowance);
      r.max_horizon_band_excess =
          std::max(r.max_horizon_band_excess, std::min(diffuse_excess, e.sky_diffuse_horizon_allowance));
      r.min_component = std::min({r.min_component, e.direct, e.sky_diffuse, e.ground_reflected});
    }
    r.direct[row] = direct / 1000.0;
    r.sky_diffuse[row] = diffuse / 1000.0;
    r.ground_reflected[row] = reflected / 1000.0;
    r.total[row] = (direct + diffuse + reflected) / 1000.0;
    r.sky_diffuse_unshaded[row] = diffuse_open / 1000.0;
    r.direct_unshaded[row] = direct_open / 1000.0;
  }
  r.direct_error_bound.assign(rows, 0.0);
  if (r.sun.arithmetic != Arithmetic::Fast || r.sun_lights.empty()) return;
  for (std::size_t row = 0; row < rows; ++row) {
    if (!(r.area[row] > 0.0)) continue;
    double bound = 0.0;
    for (const IrradianceHour& h : r.hours) {
      if (h.sun == IrradianceHour::none) continue;
      const double c = glm::dot(r.normal[row], h.to_sun);
      if (c > 0.0) bound += h.dni * c * (r.sun.lit_area_error_bound[r.sun.at(row, h.sun)] / r.area[row]);
    }
    r.direct_error_bound[row] = bound / 1000.0;
  }
}

}  // namespace

FaceIrradiance face_irradiance(const IrradianceResult& r, std::size_t row, std::size_t h) {
  FaceIrradiance e;
  const IrradianceHour& hour = r.hours[h];
  const glm::dvec3& n = r.normal[row];
  const double cos_incidence = glm::dot(n, hour.to_sun);
  const double lit = hour.sun == IrradianceHour::none ? 0.0 : r.sun.lit_fraction[r.sun.at(row, hour.sun)];
  if (cos_incidence > 0.0 && hour.sun != IrradianceHour::none) {
    e.direct_unshaded = hour.dni * cos_incidence;
    if (lit > 0.0) e.direct = hour.dni * cos_incidence * lit;
  }
  const double cos_tilt = std::clamp(n.z, -1.0, 1.0);
  if (r.sky_model == SkyModel::Isotropic || hour.perez.bin == 0) {
    e.sky_diffuse_unshaded = hour.dhi * 0.5 * (1.0 + cos_tilt);
    e.sky_diffuse = hour.dhi * r.sky_view_factor[row];
  } else {
    const double tilt = std::acos(cos_tilt) * 180.0 / kPi;
    const PerezParts parts = perez_diffuse(tilt, cos_incidence, hour.zenith, hour.dhi, hour.perez);
    e.sky_diffuse_unshaded = parts.total();
    // The isotropic part through the sky view, the circumsolar part through the sun's lit
    // fraction, the horizon band through the visible share of the horizon patches.
    const double shaded = hour.dhi * (1.0 - hour.perez.f1) * r.sky_view_factor[row] + parts.circumsolar * lit +
                          parts.horizon * r.horizon_view[row];
    e.sky_diffuse = std::max(0.0, shaded);
    if (parts.horizon < 0.0) e.sky_diffuse_horizon_allowance = -parts.horizon * std::max(0.0, 1.0 - r.horizon_view[row]);
  }
  e.ground_reflected = r.ground_reflectance * hour.ghi * r.ground_view[row];
  return e;
}

IrradianceResult compute_irradiance(const ShadowEngine& engine, const Scene& scene, const Weather& weather,
                                    const IrradianceOptions& options) {
  IrradianceResult r;
  r.sky_model = options.sky;
  r.patches = sky_patches(options.sky_patches, options.north_axis);
  double rho = options.ground_reflectance;
  if (std::isnan(rho)) rho = std::isnan(weather.mean_albedo()) ? 0.2 : weather.mean_albedo();
  if (!(rho >= 0.0 && rho <= 1.0))
    throw InputError({"", "ground_reflectance"}, std::to_string(rho) + " is not in [0, 1]");
  r.ground_reflectance = rho;
  const std::size_t first = std::min(options.first_record, weather.hours());
  const std::size_t end = std::min(options.end_record, weather.hours());
  if (first >= end) throw InputError({weather.source, "period"}, "the period holds no hour of the weather file");

  auto start = Clock::now();
  std::vector<Light> patch_lights;
  for (std::size_t p = 0; p < r.patches.size(); ++p) {
    Light light;
    light.name = "sky patch " + std::to_string(p);
    light.to_light = r.patches[p].to_patch;
    patch_lights.push_back(light);
  }
  r.sky = engine.compute_series(patch_lights, with_progress(options, "sky patches"));
  r.faces = r.sky.faces;
  r.area = r.sky.area;
  r.normal = row_normals(scene, r.faces);
  view_factors(r);
  r.seconds_sky = seconds_since(start);

  start = Clock::now();
  r.ground_patches = ground_patches(options.sky_patches, options.north_axis);
  irradiance_detail::ground_views(r, engine, scene, with_progress(options, "ground patches"));
  r.seconds_ground = seconds_since(start);

  start = Clock::now();
  sky_of_hours(r, weather, options, first, end);
  if (!r.sun_lights.empty()) r.sun = engine.compute_series(r.sun_lights, with_progress(options, "sun"));
  r.seconds_sun = seconds_since(start);

  start = Clock::now();
  sum_rows(r, weather);
  r.seconds_sums = seconds_since(start);
  return r;
}

SunHoursMap irradiation_map(const ShadowEngine& engine, const IrradianceResult& r, const std::vector<std::size_t>& faces,
                            const SunHoursOptions& options) {
  std::map<std::size_t, std::size_t> row_of;
  for (std::size_t row = 0; row < r.faces.size(); ++row) row_of[r.faces[row]] = row;
  // Faces of one normal share the weights of the hours.
  std::map<std::array<double, 3>, std::vector<std::size_t>> groups;
  for (std::size_t f : faces) {
    const auto it = row_of.find(f);
    if (it == row_of.end()) continue;
    const glm::dvec3& n = r.normal[it->second];
    groups[{n.x, n.y, n.z}].push_back(f);
  }
  SunHoursMap map;
  for (const auto& [normal, group] : groups) {
    std::vector<SunHoursInstant> instants;
    for (const IrradianceHour& h : r.hours) {
      if (h.sun == IrradianceHour::none) continue;
      const double c = normal[0] * h.to_sun.x + normal[1] * h.to_sun.y + normal[2] * h.to_sun.z;
      if (!(c > 0.0) || !(h.dni > 0.0)) continue;  // no beam on the face: the hour adds nothing
      instants.push_back({r.sun_lights[h.sun], h.dni * c / 1000.0});
    }
    SunHoursMap part;
    if (instants.empty()) {
      // No beam at all: the faces are one cell each, at 0, from a map of no instant.
      part = compute_sun_hours_map(engine, group, {}, options);
    } else {
      part = compute_sun_hours_map(engine, group, instants, options);
    }
    for (SunHoursCell& cell : part.cells) {
      cell.region_id += map.regions;
      map.cells.push_back(std::move(cell));
    }
    for (const SunHoursFace& face : part.faces) map.faces.push_back(face);
    map.regions += part.regions;
    map.total_hours = std::max(map.total_hours, part.total_hours);
  }
  std::stable_sort(map.cells.begin(), map.cells.end(),
                   [](const SunHoursCell& a, const SunHoursCell& b) { return a.face_id < b.face_id; });
  std::sort(map.faces.begin(), map.faces.end(),
            [](const SunHoursFace& a, const SunHoursFace& b) { return a.face_id < b.face_id; });
  return map;
}

}  // namespace shadow
