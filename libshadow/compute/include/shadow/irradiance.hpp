// SPDX-License-Identifier: GPL-3.0-or-later
/// @file irradiance.hpp
/// @brief Solar irradiation over a weather year on every receiving face: direct from the sun
/// through each face's exact sunlit fraction, sky diffuse (isotropic or Perez 1990) through
/// each face's exact view of the sky patches, and ground-reflected. See docs/irradiance.md.
///
/// Conventions: a weather record covers the hour that ends at its stamp (EPW); the sun of the
/// record is the sun at the middle of that hour (start + 30 min, UTC), from solar_position()
/// (NREL SPA) at the weather file's site. Irradiance in W/m2 is the hour's mean, so the hour's
/// irradiation in Wh/m2 is the same number; totals are in kWh/m2.
#pragma once

#include <shadow/radiosity.hpp>
#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun_hours.hpp>
#include <shadow/weather.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace shadow {

/// The sky's diffuse radiance distribution.
enum class SkyModel {
  Isotropic,  ///< uniform sky: a face gets DHI x its sky view factor
  Perez       ///< Perez et al. 1990, all-sites coefficients: isotropic, circumsolar and horizon band
};

/// One patch of the sky hemisphere, seen as a directional light at its centre.
struct SkyPatch {
  double altitude = 0.0;     ///< degrees above the horizon of the patch's centre
  double azimuth = 0.0;      ///< degrees clockwise from true north of its centre
  double solid_angle = 0.0;  ///< steradians
  bool horizon = false;      ///< in the lowest band of Tregenza's sky (altitude < 12 degrees)
  glm::dvec3 to_patch{0.0, 0.0, 1.0};  ///< unit vector toward the centre, model coordinates
};

/// Tregenza's 145 patches (`count` 145) or Reinhart's subdivisions of them (577: each patch
/// cut 2 x 2; 2305: 4 x 4): 7m bands of height 90 / (7m + 0.5) degrees with m x (30, 30, 24,
/// 24, 18, 12, 6) patches, and a polar cap. Solid angles add up to 2 pi.
/// @throws InputError for another count (place `sky_patches`)
std::vector<SkyPatch> sky_patches(int count, double north_axis_degrees = 0.0);

/// The patches of the ground: sky_patches(count) mirrored below the horizon (altitudes and the
/// z of `to_patch` negated, the polar cap at the nadir). Each is a directional light pointing up
/// from below; a face's exact lit fraction under it is the share of the face that sees no face
/// in that direction. `horizon` marks the band just below the horizon.
/// @throws InputError for another count than 145, 577 or 2305 (place `sky_patches`)
std::vector<SkyPatch> ground_patches(int count, double north_axis_degrees = 0.0);

/// Which faces are the ground (per face id, 1 or 0): the faces of the meshes of Scene::ground
/// when the scene names them, else of the meshes named `ground` and of CityJSON city objects of
/// type TINRelief, LandUse, Road, Railway or TransportSquare; and always every face of kind
/// `GroundSurface` (a CityJSON building's ground plate rests on the ground). Below the horizon,
/// a face that sees a ground face (or no face at all) sees the ground; any other face hides it.
std::vector<unsigned char> ground_faces(const Scene& scene);

/// Kasten and Young's (1989) relative optical air mass at a zenith angle in degrees: finite up
/// to 90 degrees, NaN beyond.
double relative_airmass(double zenith_degrees);

/// Extraterrestrial normal irradiance (W/m2) on day `day_of_year` (1..366): 1366.1 W/m2 times
/// Spencer's (1971) eccentricity correction.
double extraterrestrial_normal(int day_of_year);

/// Perez 1990's brightness coefficients for one hour.
struct PerezSky {
  double f1 = 0.0;      ///< circumsolar brightening (>= 0)
  double f2 = 0.0;      ///< horizon brightening (may be negative)
  int bin = 0;          ///< clearness bin 1..8 (0: no diffuse, or the sun below the horizon)
  double epsilon = 0.0; ///< sky clearness
  double delta = 0.0;   ///< sky brightness
};

/// F1 and F2 of Perez et al. 1990 (all-sites composite coefficients) from the diffuse
/// horizontal and direct normal irradiance (W/m2), the sun's zenith (degrees), the
/// extraterrestrial normal irradiance and the relative air mass. bin 0 (F1 = F2 = 0, the sky
/// isotropic) when dhi <= 0 or the zenith is not below 90 degrees.
PerezSky perez_sky(double dhi, double dni, double zenith_degrees, double dni_extra, double airmass);

/// The parts of Perez's sky diffuse irradiance on an unobstructed plane of tilt `tilt_degrees`
/// whose normal makes `cos_incidence` with the sun (W/m2).
struct PerezParts {
  double isotropic = 0.0;    ///< dhi (1 - F1) (1 + cos tilt) / 2
  double circumsolar = 0.0;  ///< dhi F1 max(0, cos incidence) / max(cos 85 deg, cos zenith)
  double horizon = 0.0;      ///< dhi F2 sin tilt
  /// max(0, isotropic + circumsolar + horizon): pvlib's `perez` on the same inputs.
  [[nodiscard]] double total() const;
};
PerezParts perez_diffuse(double tilt_degrees, double cos_incidence, double zenith_degrees, double dhi,
                         const PerezSky& sky);

/// Options of compute_irradiance.
struct IrradianceOptions {
  SkyModel sky = SkyModel::Perez;
  int sky_patches = 145;  ///< 145, 577 or 2305
  /// Ground reflectance; NaN: the weather file's mean albedo when it has one, else 0.2.
  double ground_reflectance = std::numeric_limits<double>::quiet_NaN();
  std::size_t first_record = 0;  ///< the period: weather records [first_record, end_record)
  std::size_t end_record = std::numeric_limits<std::size_t>::max();
  double north_axis = 0.0;  ///< degrees clockwise from true north to the model's +y
  double delta_t = 69.0;    ///< TT - UT1 (s) for the SPA
  /// The series computations (threads, exact or fast, tiles); its progress is not used.
  SeriesOptions series;
  /// Called from the calling thread: stage ("sky patches" then "sun") and its progress.
  std::function<void(const std::string& stage, const Progress&)> progress;
};

/// The sky of one hour of the period, shared by every face.
struct IrradianceHour {
  std::size_t record = 0;           ///< index of the weather record
  std::size_t sun = none;           ///< column of `IrradianceResult::sun`, or none (night, no light)
  double dni = 0.0, dhi = 0.0, ghi = 0.0;  ///< W/m2 (0 where the file says missing)
  double zenith = 90.0;             ///< the sun's zenith at mid-hour (degrees)
  glm::dvec3 to_sun{0.0, 0.0, 1.0}; ///< unit vector toward the sun, model coordinates
  PerezSky perez;                   ///< F1 = F2 = 0 for the isotropic sky
  bool missing = false;             ///< DNI or DHI missing in the file: that one counts 0 (both: the hour)
  static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
};

/// A face's irradiance in one hour (W/m2, the hour's mean).
struct FaceIrradiance {
  double direct = 0.0;
  double sky_diffuse = 0.0;
  double ground_reflected = 0.0;
  double direct_unshaded = 0.0;       ///< DNI max(0, cos incidence): the face alone in the world
  double sky_diffuse_unshaded = 0.0;  ///< the same sky on the face without obstructions
  /// Perez's horizon band where it is negative (some hours with a low sun), times the share of the horizon
  /// hidden from the face: by this much the shaded sky diffuse may exceed the unshaded. The
  /// model's own: hiding a horizon darker than the isotropic sky takes its negative term away.
  double sky_diffuse_horizon_allowance = 0.0;
  [[nodiscard]] double total() const { return direct + sky_diffuse + ground_reflected; }
};

/// Irradiation of every receiving face over the period.
struct IrradianceResult {
  std::vector<std::size_t> faces;      ///< receiving faces, ascending: the rows
  std::vector<double> area;            ///< per row: exact area rounded once (m2)
  std::vector<glm::dvec3> normal;      ///< per row: unit normal (Newell)
  std::vector<double> sky_view_factor; ///< per row: the form factor to the visible sky
  std::vector<double> horizon_view;    ///< per row: visible share of the horizon band (0..1)
  /// per row: the form factor to the visible ground (`ground_view_factor`): the ground patches
  /// in front of the face, each weighted by cos x solid angle and by the share of the face that
  /// sees no face or a ground face (ground_faces()) in its direction, scaled so that an
  /// unobstructed face gets exactly (1 - cos tilt) / 2 (0 for a roof, 0.5 for a wall). A ground
  /// face itself gets (1 - cos tilt) / 2 (what lies below its horizon is taken as more ground),
  /// a face of kind GroundSurface 0 (it rests on the ground), and so does a face looking straight
  /// down that lies no higher than the lowest point of the ground faces (a box's bottom on the
  /// ground plane).
  std::vector<double> ground_view;
  /// per row: 1 when the face is ground (ground_faces()).
  std::vector<unsigned char> on_ground;
  /// Per row, kWh/m2 over the period: direct, sky diffuse, ground-reflected, their total, and
  /// the unshaded sky diffuse (for EnergyPlus's diffuse shading ratio).
  std::vector<double> direct, sky_diffuse, ground_reflected, total, sky_diffuse_unshaded, direct_unshaded;
  /// Per row, the fast path's bounds (0 when exact): on |direct - exact direct| (kWh/m2), the sum
  /// over hours of DNI cos(incidence) x lit_area_error_bound / area; and on |sky_view_factor -
  /// exact|, the patches' bounds weighted as the view factor weighs their lit fractions.
  std::vector<double> direct_error_bound, sky_view_factor_error_bound;
  /// per row, the fast path's bound on |ground_view - exact| (0 when exact), as for the sky.
  std::vector<double> ground_view_factor_error_bound;
  /// Per row and month (row * 12 + month - 1), kWh/m2: the same four components.
  std::vector<double> monthly_direct, monthly_sky_diffuse, monthly_ground_reflected, monthly_total;
  std::vector<IrradianceHour> hours;  ///< the period's hours in time order
  std::vector<Light> sun_lights;      ///< the suns of the hours with a sun (columns of `sun`)
  SeriesResult sun;                   ///< their exact (or fast) lit fractions
  std::vector<SkyPatch> patches;
  SeriesResult sky;                   ///< the patches' lit fractions
  std::vector<SkyPatch> ground_patches;  ///< ground_patches(): the sky's patches mirrored
  /// The ground patches' lit fractions with the ground faces casting no shadow (a second engine
  /// on the scene without them when it has any): its rows are the receiving faces that are not
  /// ground (a subset of `faces`, ascending).
  SeriesResult ground;
  SkyModel sky_model = SkyModel::Perez;
  double ground_reflectance = 0.2;
  std::size_t missing_hours = 0;  ///< hours of the period with DNI or DHI missing (that value counted as 0)
  double seconds_sky = 0.0, seconds_ground = 0.0, seconds_sun = 0.0, seconds_sums = 0.0;  ///< time per stage
  /// Energy conservation over every face and hour (W/m2): the largest excess of shaded over
  /// unshaded direct and sky diffuse (<= 0 up to rounding; the sky diffuse's beyond its
  /// FaceIrradiance::sky_diffuse_horizon_allowance), and the smallest component (>= 0).
  double max_direct_excess = 0.0, max_diffuse_excess = 0.0, min_component = 0.0;
  /// The largest excess of shaded over unshaded sky diffuse that Perez's negative horizon band
  /// explains (W/m2; allowed, reported so that it is seen).
  double max_horizon_band_excess = 0.0;
  /// The energy check holds: the excesses above within rounding, no component negative.
  [[nodiscard]] bool energy_check_ok() const {
    return max_direct_excess <= 1e-9 && max_diffuse_excess <= 1e-6 && min_component >= 0.0;
  }
  /// Per row, kWh/m2 over the period: what the scene's own faces reflect onto the face (empty
  /// unless add_scene_reflections ran; it is then part of `total`, not of the monthly totals).
  std::vector<double> scene_reflected;
  /// The radiosity solution behind scene_reflected.
  struct Reflections {
    std::size_t elements = 0, shots = 0;
    double unshot_fraction = 0.0, error_estimate = 0.0, default_reflectance = 0.0, seconds = 0.0;
    bool hierarchical = false;  ///< solved by hierarchical radiosity (large scenes; shots are then 0)
    std::size_t iterations = 0, near_links = 0, far_links = 0;  ///< the hierarchical solution's
  } reflections;
  /// The month (1..12) of each hour (hours[h]).
  [[nodiscard]] int month_of(std::size_t h, const Weather& weather) const { return weather.month[hours[h].record]; }
};

/// The irradiance of row `row` in hour `h` of `result` (W/m2).
FaceIrradiance face_irradiance(const IrradianceResult& result, std::size_t row, std::size_t h);

/// Irradiation over `weather`'s records in the options' period on every receiving face of the
/// engine's scene: the sky patches once (one series of lights), the ground patches once (one
/// more series, on a second engine without the ground faces when the scene has any), the sun of every hour with
/// diffuse or direct light and the sun above the horizon (one series), then the sums.
/// @throws InputError for a bad option (sky_patches, ground_reflectance outside [0, 1], an
/// empty period)
IrradianceResult compute_irradiance(const ShadowEngine& engine, const Scene& scene, const Weather& weather,
                                    const IrradianceOptions& options = {});

/// Options of add_scene_reflections.
struct ReflectionOptions {
  /// The reflectance of faces whose material gives none (no reflectance, colour or emittance).
  double default_reflectance = 0.2;
  double max_element_area = 0.0;  ///< radiosity elements (m^2); 0: the faces' triangles
  double tolerance = 1e-3;        ///< the unshot fraction to stop at
  unsigned threads = 0;
  std::function<void(const RadiosityProgress&)> progress;
};

/// The scene's own reflections over the period (`shadow irradiance --reflections`): one
/// radiosity solution (shadow/radiosity.hpp) whose sources are each receiving face's total
/// irradiation over the period, its faces reflecting their material's reflectance (or the
/// default); ground faces (ground_faces()) reflect nothing there, their reflection being the
/// ground-reflected component already. Radiosity is linear in its sources, so the solution's incident minus source on each
/// face is the period's reflected irradiation: it goes into result.scene_reflected and is added
/// to result.total. Faces that are not receivers have no source (their irradiation is unknown).
/// @throws InputError for a default reflectance outside [0, 1)
void add_scene_reflections(const Scene& scene, IrradianceResult& result, const ReflectionOptions& options = {});

/// The direct irradiation map (`shadow irradiance --map`): the exact sun-hours map of `faces`
/// (receiving faces of `result`; others are left out) in which each hour's sun weighs
/// DNI x cos(incidence) / 1000, so that each cell's `sun_hours` is its direct irradiation in
/// kWh/m2 over the period: every face cut along the exact boundaries of the beam's shadows of
/// every hour. Faces are mapped in groups of equal normal (the weights depend on it); cells come
/// ordered by face id, region ids numbered across the groups. Over a face, the area-weighted mean
/// of its cells equals result.direct of its row up to rounding.
/// @throws InputError as compute_sun_hours_map
SunHoursMap irradiation_map(const ShadowEngine& engine, const IrradianceResult& result,
                            const std::vector<std::size_t>& faces, const SunHoursOptions& options = {});

}  // namespace shadow
