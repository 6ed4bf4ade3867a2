// SPDX-License-Identifier: GPL-3.0-or-later
// The sky of shadow/irradiance.hpp: Tregenza's and Reinhart's patches, the relative air mass,
// the extraterrestrial irradiance and Perez et al. 1990's sky diffuse model.
#include <shadow/irradiance.hpp>

#include <shadow/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace shadow {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

/// Perez, Ineichen, Seals, Michalsky and Stewart (1990), "Modeling daylight availability and
/// irradiance components from direct and global irradiance", Solar Energy 44(5), table 6: the
/// all-sites composite coefficients f11 f12 f13 f21 f22 f23 per clearness bin.
constexpr std::array<std::array<double, 6>, 8> kPerez1990 = {{
    {-0.008, 0.588, -0.062, -0.060, 0.072, -0.022},
    {0.130, 0.683, -0.151, -0.019, 0.066, -0.029},
    {0.330, 0.487, -0.221, 0.055, -0.064, -0.026},
    {0.568, 0.187, -0.295, 0.109, -0.152, -0.014},
    {0.873, -0.392, -0.362, 0.226, -0.462, 0.001},
    {1.132, -1.237, -0.412, 0.288, -0.823, 0.056},
    {1.060, -1.600, -0.359, 0.264, -1.127, 0.131},
    {0.678, -0.327, -0.250, 0.156, -1.377, 0.251},
}};

/// Upper edges of clearness bins 1..7 (bin 8 is open above).
constexpr std::array<double, 7> kEpsilonEdges = {1.065, 1.23, 1.5, 1.95, 2.8, 4.5, 6.2};

/// Tregenza's patches per band, from the horizon up (the cap comes on top).
constexpr std::array<int, 7> kTregenzaBand = {30, 30, 24, 24, 18, 12, 6};

}  // namespace

std::vector<SkyPatch> sky_patches(int count, double north_axis_degrees) {
  int m = 0;
  if (count == 145) m = 1;
  if (count == 577) m = 2;
  if (count == 2305) m = 4;
  if (m == 0)
    throw InputError({"", "sky_patches"}, std::to_string(count) + " sky patches: use 145 (Tregenza), 577 or 2305 (Reinhart)");
  // Reinhart's subdivision: 7m bands of equal height and a cap of half that height, so that
  // m = 1 is Tregenza's 12-degree bands with a 6-degree cap.
  const double band = 90.0 / (7.0 * m + 0.5);
  std::vector<SkyPatch> patches;
  patches.reserve(static_cast<std::size_t>(count));
  for (int b = 0; b < 7 * m; ++b) {
    const int per_band = kTregenzaBand[static_cast<std::size_t>(b / m)] * m;
    const double low = b * band, high = (b + 1) * band;
    const double width = 360.0 / per_band;
    const double solid = width * kDeg * (std::sin(high * kDeg) - std::sin(low * kDeg));
    for (int k = 0; k < per_band; ++k) {
      SkyPatch p;
      p.altitude = 0.5 * (low + high);
      p.azimuth = k * width;
      p.solid_angle = solid;
      p.horizon = b < m;  // Tregenza's lowest band, 0..12 degrees
      p.to_patch = sun_to_light(p.altitude, p.azimuth, north_axis_degrees);
      patches.push_back(p);
    }
  }
  SkyPatch cap;
  cap.altitude = 90.0;
  cap.solid_angle = 2.0 * kPi * (1.0 - std::cos(0.5 * band * kDeg));
  cap.to_patch = {0.0, 0.0, 1.0};
  patches.push_back(cap);
  return patches;
}

double relative_airmass(double zenith_degrees) {
  // Kasten and Young (1989), Applied Optics 28(22).
  if (!(zenith_degrees <= 90.0)) return std::nan("");
  return 1.0 / (std::cos(zenith_degrees * kDeg) + 0.50572 * std::pow(96.07995 - zenith_degrees, -1.6364));
}

double extraterrestrial_normal(int day_of_year) {
  // Spencer (1971): the Earth-Sun distance factor from the day angle.
  const double b = 2.0 * kPi * (day_of_year - 1) / 365.0;
  const double factor = 1.00011 + 0.034221 * std::cos(b) + 0.00128 * std::sin(b) + 0.000719 * std::cos(2.0 * b) +
                        0.000077 * std::sin(2.0 * b);
  return 1366.1 * factor;
}

PerezSky perez_sky(double dhi, double dni, double zenith_degrees, double dni_extra, double airmass) {
  PerezSky sky;
  if (!(dhi > 0.0) || !(zenith_degrees < 90.0) || !(dni_extra > 0.0) || !std::isfinite(airmass)) return sky;
  const double z = zenith_degrees * kDeg;
  const double kz3 = 1.041 * z * z * z;  // kappa for the zenith in radians
  sky.epsilon = ((dhi + std::max(0.0, dni)) / dhi + kz3) / (1.0 + kz3);
  sky.delta = dhi * airmass / dni_extra;
  std::size_t bin = 0;
  while (bin < kEpsilonEdges.size() && sky.epsilon >= kEpsilonEdges[bin]) ++bin;
  const std::array<double, 6>& f = kPerez1990[bin];
  sky.bin = static_cast<int>(bin) + 1;
  sky.f1 = std::max(0.0, f[0] + f[1] * sky.delta + f[2] * z);
  sky.f2 = f[3] + f[4] * sky.delta + f[5] * z;
  return sky;
}

double PerezParts::total() const { return std::max(0.0, isotropic + circumsolar + horizon); }

PerezParts perez_diffuse(double tilt_degrees, double cos_incidence, double zenith_degrees, double dhi,
                         const PerezSky& sky) {
  PerezParts parts;
  const double tilt = tilt_degrees * kDeg;
  parts.isotropic = dhi * (1.0 - sky.f1) * 0.5 * (1.0 + std::cos(tilt));
  const double b = std::max(std::cos(85.0 * kDeg), std::cos(zenith_degrees * kDeg));
  parts.circumsolar = dhi * sky.f1 * std::max(0.0, cos_incidence) / b;
  parts.horizon = dhi * sky.f2 * std::sin(tilt);
  return parts;
}

}  // namespace shadow
