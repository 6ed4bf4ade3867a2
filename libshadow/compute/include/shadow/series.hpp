// SPDX-License-Identifier: GPL-3.0-or-later
/// @file series.hpp
/// @brief Sun series: the scene's suns as one job, sun hours, results per named surface (the
/// files they make are written by shadow/series_files.hpp and shadow/output.hpp). See docs/series.md.
///
/// Integration rule: each instant stands for its step (the step it starts, or with
/// SunPeriod::energyplus_times the step it ends or the middle of which it is). For a `sun` period,
/// sun_hours = sum over instants of lit_fraction x step_minutes / 60. For explicit `times`,
/// each instant counts for the median gap between consecutive times (a single time counts for
/// one hour); report.json says which weight was used (`hours_per_instant`).
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun.hpp>

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace shadow {

/// The scene's sun instants above the horizon, as the lights of a series.
struct SunSeries {
  std::vector<Light> lights;          ///< one directional light per instant above the horizon
  std::vector<UtcSeconds> times;      ///< their UTC instants, in time order
  std::vector<std::size_t> instants;  ///< their indices in Scene::sun_instants
  std::size_t all_instants = 0;       ///< every instant of the period, below the horizon too
  double hours_per_instant = 1.0;     ///< the integration weight (see the file comment)
  bool explicit_times = false;        ///< the period was given as `times`
};

/// The series of `scene.sun` (every instant whose light_id names a scene light).
/// @throws InputError when the scene has no `sun` block, or an instant names a light that is
/// not a directional light of the scene
SunSeries sun_series(const Scene& scene);

/// The hours each instant of `period` stands for: step_minutes / 60, or for explicit times the
/// median gap between consecutive sorted times (1 for fewer than two times).
double hours_per_instant(const SunPeriod& period);

/// Sun hours per row of `series`: sum over instants of lit_fraction x hours_per_instant.
std::vector<double> sun_hours(const SeriesResult& series, double hours_per_instant);

/// Bound on |sun_hours - exact sun hours| per row (fast path; 0 for exact): the sum over
/// instants of lit_area_error_bound / area x hours_per_instant, for faces of positive area.
std::vector<double> sun_hours_error_bound(const SeriesResult& series, double hours_per_instant);

/// Results per named surface (named_surfaces(): faces sharing a name add up).
struct SurfaceSeries {
  std::vector<NamedSurface> surfaces;  ///< receiving named surfaces, in the order of their first face
  std::vector<double> area;            ///< per surface: the sum of its faces' areas
  /// Row-major (surface * instants + instant): sum of the faces' lit areas / sum of their areas
  /// (0 for a surface of zero area).
  std::vector<double> lit_fraction;
  std::vector<double> sun_hours;  ///< per surface: sum over instants of lit_fraction x hours
  std::size_t instants = 0;
};

/// Aggregates `series` (computed on `scene`) per named surface.
SurfaceSeries surface_series(const Scene& scene, const SeriesResult& series, double hours_per_instant);

/// Sun hours per object (scene_objects(): a CityJSON top-level city object with its parts, an
/// EnergyPlus zone, any other mesh): `sun_hours_by_object.csv` and report.json's
/// `series.objects`. Over an object's receiving faces (the rows of the series in its meshes):
/// sunlit_area_hours = sum over faces and instants of lit_area x hours_per_instant (m2 h), and
/// sun_hours = sunlit_area_hours / area, the area-weighted mean of the faces' sun hours (0 for an
/// object of zero area).
struct ObjectSunHours {
  std::vector<SceneObject> objects;        ///< objects with at least one receiving face, in scene order
  std::vector<std::size_t> faces;          ///< per object: its receiving faces
  std::vector<double> area;                ///< per object: the sum of their areas (m2)
  std::vector<double> sun_hours;           ///< per object: the area-weighted mean sun hours (h)
  std::vector<double> sunlit_area_hours;   ///< per object: sum of lit area x hours (m2 h)
};

/// Aggregates `series` (computed on `scene`) per object (scene_objects(scene, true, per_mesh):
/// `per_mesh` gives one row per receiving mesh instead, parts not rolled up).
ObjectSunHours object_sun_hours(const Scene& scene, const SeriesResult& series, double hours_per_instant,
                                bool per_mesh = false);

}  // namespace shadow
