// SPDX-License-Identifier: GPL-3.0-or-later
// NREL's Solar Position Algorithm (Reda & Andreas 2004, NREL/TP-560-34302), written from the
// paper's method and tables: Earth's heliocentric position from the truncated VSOP87 periodic
// terms (Table A4.2), nutation from the IAU 1980 series (Table A4.3), then the apparent
// geocentric and topocentric sun, refraction last. Step numbers below are the paper's sections.
#include "sun/spa.hpp"

#include <cmath>
#include <cstddef>

namespace shadow::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = kPi / 180.0;

double rad(double degrees) { return degrees * kRad; }
double deg(double radians) { return radians / kRad; }

/// `degrees` reduced to [0, 360).
double limit360(double degrees) {
  double r = std::fmod(degrees, 360.0);
  if (r < 0) r += 360.0;
  return r >= 360.0 ? 0.0 : r;  // -1e-18 + 360 rounds to 360
}

/// One periodic term A cos(B + C * JME) of Table A4.2.
struct Term {
  double a, b, c;
};

// ---- Table A4.2: Earth periodic terms ----------------------------------------------------------

constexpr Term L0[] = {
    {175347046, 0, 0}, {3341656, 4.6692568, 6283.07585}, {34894, 4.6261, 12566.1517},
    {3497, 2.7441, 5753.3849}, {3418, 2.8289, 3.5231}, {3136, 3.6277, 77713.7715},
    {2676, 4.4181, 7860.4194}, {2343, 6.1352, 3930.2097}, {1324, 0.7425, 11506.7698},
    {1273, 2.0371, 529.691}, {1199, 1.1096, 1577.3435}, {990, 5.233, 5884.927},
    {902, 2.045, 26.298}, {857, 3.508, 398.149}, {780, 1.179, 5223.694},
    {753, 2.533, 5507.553}, {505, 4.583, 18849.228}, {492, 4.205, 775.523},
    {357, 2.92, 0.067}, {317, 5.849, 11790.629}, {284, 1.899, 796.298},
    {271, 0.315, 10977.079}, {243, 0.345, 5486.778}, {206, 4.806, 2544.314},
    {205, 1.869, 5573.143}, {202, 2.458, 6069.777}, {156, 0.833, 213.299},
    {132, 3.411, 2942.463}, {126, 1.083, 20.775}, {115, 0.645, 0.98},
    {103, 0.636, 4694.003}, {102, 0.976, 15720.839}, {102, 4.267, 7.114},
    {99, 6.21, 2146.17}, {98, 0.68, 155.42}, {86, 5.98, 161000.69},
    {85, 1.3, 6275.96}, {85, 3.67, 71430.7}, {80, 1.81, 17260.15},
    {79, 3.04, 12036.46}, {75, 1.76, 5088.63}, {74, 3.5, 3154.69},
    {74, 4.68, 801.82}, {70, 0.83, 9437.76}, {62, 3.98, 8827.39},
    {61, 1.82, 7084.9}, {57, 2.78, 6286.6}, {56, 4.39, 14143.5},
    {56, 3.47, 6279.55}, {52, 0.19, 12139.55}, {52, 1.33, 1748.02},
    {51, 0.28, 5856.48}, {49, 0.49, 1194.45}, {41, 5.37, 8429.24},
    {41, 2.4, 19651.05}, {39, 6.17, 10447.39}, {37, 6.04, 10213.29},
    {37, 2.57, 1059.38}, {36, 1.71, 2352.87}, {36, 1.78, 6812.77},
    {33, 0.59, 17789.85}, {30, 0.44, 83996.85}, {30, 2.74, 1349.87},
    {25, 3.16, 4690.48}};
constexpr Term L1[] = {
    {628331966747, 0, 0}, {206059, 2.678235, 6283.07585}, {4303, 2.6351, 12566.1517},
    {425, 1.59, 3.523}, {119, 5.796, 26.298}, {109, 2.966, 1577.344},
    {93, 2.59, 18849.23}, {72, 1.14, 529.69}, {68, 1.87, 398.15},
    {67, 4.41, 5507.55}, {59, 2.89, 5223.69}, {56, 2.17, 155.42},
    {45, 0.4, 796.3}, {36, 0.47, 775.52}, {29, 2.65, 7.11},
    {21, 5.34, 0.98}, {19, 1.85, 5486.78}, {19, 4.97, 213.3},
    {17, 2.99, 6275.96}, {16, 0.03, 2544.31}, {16, 1.43, 2146.17},
    {15, 1.21, 10977.08}, {12, 2.83, 1748.02}, {12, 3.26, 5088.63},
    {12, 5.27, 1194.45}, {12, 2.08, 4694}, {11, 0.77, 553.57},
    {10, 1.3, 6286.6}, {10, 4.24, 1349.87}, {9, 2.7, 242.73},
    {9, 5.64, 951.72}, {8, 5.3, 2352.87}, {6, 2.65, 9437.76},
    {6, 4.67, 4690.48}};
constexpr Term L2[] = {
    {52919, 0, 0}, {8720, 1.0721, 6283.0758}, {309, 0.867, 12566.152},
    {27, 0.05, 3.52}, {16, 5.19, 26.3}, {16, 3.68, 155.42},
    {10, 0.76, 18849.23}, {9, 2.06, 77713.77}, {7, 0.83, 775.52},
    {5, 4.66, 1577.34}, {4, 1.03, 7.11}, {4, 3.44, 5573.14},
    {3, 5.14, 796.3}, {3, 6.05, 5507.55}, {3, 1.19, 242.73},
    {3, 6.12, 529.69}, {3, 0.31, 398.15}, {3, 2.28, 553.57},
    {2, 4.38, 5223.69}, {2, 3.75, 0.98}};
constexpr Term L3[] = {
    {289, 5.844, 6283.076}, {35, 0, 0}, {17, 5.49, 12566.15}, {3, 5.2, 155.42},
    {1, 4.72, 3.52}, {1, 5.3, 18849.23}, {1, 5.97, 242.73}};
constexpr Term L4[] = {{114, 3.142, 0}, {8, 4.13, 6283.08}, {1, 3.84, 12566.15}};
constexpr Term L5[] = {{1, 3.14, 0}};

constexpr Term B0[] = {
    {280, 3.199, 84334.662}, {102, 5.422, 5507.553}, {80, 3.88, 5223.69},
    {44, 3.7, 2352.87}, {32, 4, 1577.34}};
constexpr Term B1[] = {{9, 3.9, 5507.55}, {6, 1.73, 5223.69}};

constexpr Term R0[] = {
    {100013989, 0, 0}, {1670700, 3.0984635, 6283.07585}, {13956, 3.05525, 12566.1517},
    {3084, 5.1985, 77713.7715}, {1628, 1.1739, 5753.3849}, {1576, 2.8469, 7860.4194},
    {925, 5.453, 11506.77}, {542, 4.564, 3930.21}, {472, 3.661, 5884.927},
    {346, 0.964, 5507.553}, {329, 5.9, 5223.694}, {307, 0.299, 5573.143},
    {243, 4.273, 11790.629}, {212, 5.847, 1577.344}, {186, 5.022, 10977.079},
    {175, 3.012, 18849.228}, {110, 5.055, 5486.778}, {98, 0.89, 6069.78},
    {86, 5.69, 15720.84}, {86, 1.27, 161000.69}, {65, 0.27, 17260.15},
    {63, 0.92, 529.69}, {57, 2.01, 83996.85}, {56, 5.24, 71430.7},
    {49, 3.25, 2544.31}, {47, 2.58, 775.52}, {45, 5.54, 9437.76},
    {43, 6.01, 6275.96}, {39, 5.36, 4694}, {38, 2.39, 8827.39},
    {37, 0.83, 19651.05}, {37, 4.9, 12139.55}, {36, 1.67, 12036.46},
    {35, 1.84, 2942.46}, {33, 0.24, 7084.9}, {32, 0.18, 5088.63},
    {32, 1.78, 398.15}, {28, 1.21, 6286.6}, {28, 1.9, 6279.55},
    {26, 4.59, 10447.39}};
constexpr Term R1[] = {
    {103019, 1.10749, 6283.07585}, {1721, 1.0644, 12566.1517}, {702, 3.142, 0},
    {32, 1.02, 18849.23}, {31, 2.84, 5507.55}, {25, 1.32, 5223.69},
    {18, 1.42, 1577.34}, {10, 5.91, 10977.08}, {9, 1.42, 6275.96},
    {9, 0.27, 5486.78}};
constexpr Term R2[] = {
    {4359, 5.7846, 6283.0758}, {124, 5.579, 12566.152}, {12, 3.14, 0},
    {9, 3.63, 77713.77}, {6, 1.87, 5573.14}, {3, 5.47, 18849.23}};
constexpr Term R3[] = {{145, 4.273, 6283.076}, {7, 3.92, 12566.15}};
constexpr Term R4[] = {{4, 2.56, 6283.08}};

// ---- Table A4.3: nutation in longitude and obliquity -------------------------------------------

/// Multipliers of X0..X4 (mean elongation of the moon, mean anomalies of the sun and the moon,
/// the moon's argument of latitude, longitude of its ascending node) and the coefficients
/// a, b (longitude) and c, d (obliquity), in 0.0001 arc seconds.
struct NutationTerm {
  int y[5];
  double a, b, c, d;
};

constexpr NutationTerm kNutation[] = {
    {{0, 0, 0, 0, 1}, -171996, -174.2, 92025, 8.9},
    {{-2, 0, 0, 2, 2}, -13187, -1.6, 5736, -3.1},
    {{0, 0, 0, 2, 2}, -2274, -0.2, 977, -0.5},
    {{0, 0, 0, 0, 2}, 2062, 0.2, -895, 0.5},
    {{0, 1, 0, 0, 0}, 1426, -3.4, 54, -0.1},
    {{0, 0, 1, 0, 0}, 712, 0.1, -7, 0},
    {{-2, 1, 0, 2, 2}, -517, 1.2, 224, -0.6},
    {{0, 0, 0, 2, 1}, -386, -0.4, 200, 0},
    {{0, 0, 1, 2, 2}, -301, 0, 129, -0.1},
    {{-2, -1, 0, 2, 2}, 217, -0.5, -95, 0.3},
    {{-2, 0, 1, 0, 0}, -158, 0, 0, 0},
    {{-2, 0, 0, 2, 1}, 129, 0.1, -70, 0},
    {{0, 0, -1, 2, 2}, 123, 0, -53, 0},
    {{2, 0, 0, 0, 0}, 63, 0, 0, 0},
    {{0, 0, 1, 0, 1}, 63, 0.1, -33, 0},
    {{2, 0, -1, 2, 2}, -59, 0, 26, 0},
    {{0, 0, -1, 0, 1}, -58, -0.1, 32, 0},
    {{0, 0, 1, 2, 1}, -51, 0, 27, 0},
    {{-2, 0, 2, 0, 0}, 48, 0, 0, 0},
    {{0, 0, -2, 2, 1}, 46, 0, -24, 0},
    {{2, 0, 0, 2, 2}, -38, 0, 16, 0},
    {{0, 0, 2, 2, 2}, -31, 0, 13, 0},
    {{0, 0, 2, 0, 0}, 29, 0, 0, 0},
    {{-2, 0, 1, 2, 2}, 29, 0, -12, 0},
    {{0, 0, 0, 2, 0}, 26, 0, 0, 0},
    {{-2, 0, 0, 2, 0}, -22, 0, 0, 0},
    {{0, 0, -1, 2, 1}, 21, 0, -10, 0},
    {{0, 2, 0, 0, 0}, 17, -0.1, 0, 0},
    {{2, 0, -1, 0, 1}, 16, 0, -8, 0},
    {{-2, 2, 0, 2, 2}, -16, 0.1, 7, 0},
    {{0, 1, 0, 0, 1}, -15, 0, 9, 0},
    {{-2, 0, 1, 0, 1}, -13, 0, 7, 0},
    {{0, -1, 0, 0, 1}, -12, 0, 6, 0},
    {{0, 0, 2, -2, 0}, 11, 0, 0, 0},
    {{2, 0, -1, 2, 1}, -10, 0, 5, 0},
    {{2, 0, 1, 2, 2}, -8, 0, 3, 0},
    {{0, 1, 0, 2, 2}, 7, 0, -3, 0},
    {{-2, 1, 1, 0, 0}, -7, 0, 0, 0},
    {{0, -1, 0, 2, 2}, -7, 0, 3, 0},
    {{2, 0, 0, 2, 1}, -7, 0, 3, 0},
    {{2, 0, 1, 0, 0}, 6, 0, 0, 0},
    {{-2, 0, 2, 2, 2}, 6, 0, -3, 0},
    {{-2, 0, 1, 2, 1}, 6, 0, -3, 0},
    {{2, 0, -2, 0, 1}, -6, 0, 3, 0},
    {{2, 0, 0, 0, 1}, -6, 0, 3, 0},
    {{0, -1, 1, 0, 0}, 5, 0, 0, 0},
    {{-2, -1, 0, 2, 1}, -5, 0, 3, 0},
    {{-2, 0, 0, 0, 1}, -5, 0, 3, 0},
    {{0, 0, 2, 2, 1}, -5, 0, 3, 0},
    {{-2, 0, 2, 0, 1}, 4, 0, 0, 0},
    {{-2, 1, 0, 2, 1}, 4, 0, 0, 0},
    {{0, 0, 1, -2, 0}, 4, 0, 0, 0},
    {{-1, 0, 1, 0, 0}, -4, 0, 0, 0},
    {{-2, 1, 0, 0, 0}, -4, 0, 0, 0},
    {{1, 0, 0, 0, 0}, -4, 0, 0, 0},
    {{0, 0, 1, 2, 0}, 3, 0, 0, 0},
    {{0, 0, -2, 2, 2}, -3, 0, 0, 0},
    {{-1, -1, 1, 0, 0}, -3, 0, 0, 0},
    {{0, 1, 1, 0, 0}, -3, 0, 0, 0},
    {{0, -1, 1, 2, 2}, -3, 0, 0, 0},
    {{2, -1, -1, 2, 2}, -3, 0, 0, 0},
    {{0, 0, 3, 2, 2}, -3, 0, 0, 0},
    {{2, -1, 0, 2, 2}, -3, 0, 0, 0}};

template <std::size_t N>
double series(const Term (&terms)[N], double jme) {
  double sum = 0;
  for (const Term& t : terms) sum += t.a * std::cos(t.b + t.c * jme);
  return sum;
}

/// (s0 + s1 x + s2 x^2 + ...) / 1e8, Horner's rule.
double polynomial_1e8(const double* s, int n, double x) {
  double sum = 0;
  for (int i = n - 1; i >= 0; --i) sum = sum * x + s[i];
  return sum / 1e8;
}

double poly3(double a, double b, double c, double d, double x) {  // a + b x + c x^2 + d x^3
  return a + x * (b + x * (c + x * d));
}

}  // namespace

SpaSteps spa_geocentric(double jd, double delta_t) {
  SpaSteps s;
  // 3.1: Julian day, ephemeris day, centuries and millennia.
  s.jd = jd;
  s.jde = jd + delta_t / 86400.0;
  const double jc = (jd - 2451545.0) / 36525.0;
  const double jce = (s.jde - 2451545.0) / 36525.0;
  const double jme = jce / 10.0;

  // 3.2: Earth's heliocentric longitude, latitude and radius.
  const double l[] = {series(L0, jme), series(L1, jme), series(L2, jme),
                      series(L3, jme), series(L4, jme), series(L5, jme)};
  s.L = limit360(deg(polynomial_1e8(l, 6, jme)));
  const double b[] = {series(B0, jme), series(B1, jme)};
  s.B = deg(polynomial_1e8(b, 2, jme));
  const double r[] = {series(R0, jme), series(R1, jme), series(R2, jme), series(R3, jme),
                      series(R4, jme)};
  s.R = polynomial_1e8(r, 5, jme);

  // 3.3: geocentric longitude and latitude.
  s.theta = limit360(s.L + 180.0);
  s.beta = -s.B;

  // 3.4: nutation in longitude and obliquity.
  const double x[5] = {
      poly3(297.85036, 445267.111480, -0.0019142, 1.0 / 189474.0, jce),
      poly3(357.52772, 35999.050340, -0.0001603, -1.0 / 300000.0, jce),
      poly3(134.96298, 477198.867398, 0.0086972, 1.0 / 56250.0, jce),
      poly3(93.27191, 483202.017538, -0.0036825, 1.0 / 327270.0, jce),
      poly3(125.04452, -1934.136261, 0.0020708, 1.0 / 450000.0, jce)};
  double dpsi = 0, deps = 0;
  for (const NutationTerm& t : kNutation) {
    double arg = 0;
    for (int j = 0; j < 5; ++j) arg += x[j] * t.y[j];
    arg = rad(arg);
    dpsi += (t.a + t.b * jce) * std::sin(arg);
    deps += (t.c + t.d * jce) * std::cos(arg);
  }
  s.delta_psi = dpsi / 36000000.0;
  s.delta_epsilon = deps / 36000000.0;

  // 3.5: true obliquity of the ecliptic (U in units of 10,000 years).
  const double u = jme / 10.0;
  constexpr double kObliquity[] = {84381.448, -4680.93, -1.55, 1999.25, -51.38, -249.67,
                                   -39.05,    7.12,     27.87, 5.79,    2.45};
  double eps0 = 0;
  for (int i = 10; i >= 0; --i) eps0 = eps0 * u + kObliquity[i];
  s.epsilon = eps0 / 3600.0 + s.delta_epsilon;

  // 3.6 - 3.7: aberration correction and apparent sun longitude.
  const double delta_tau = -20.4898 / (3600.0 * s.R);
  s.lambda = s.theta + s.delta_psi + delta_tau;

  // 3.8: apparent sidereal time at Greenwich.
  const double nu0 = limit360(280.46061837 + 360.98564736629 * (jd - 2451545.0) +
                              jc * jc * (0.000387933 - jc / 38710000.0));
  s.nu = limit360(nu0 + s.delta_psi * std::cos(rad(s.epsilon)));

  // 3.9 - 3.10: geocentric right ascension and declination.
  const double lam = rad(s.lambda), eps = rad(s.epsilon), bet = rad(s.beta);
  s.alpha = limit360(deg(std::atan2(std::sin(lam) * std::cos(eps) - std::tan(bet) * std::sin(eps),
                                    std::cos(lam))));
  s.delta = deg(std::asin(std::sin(bet) * std::cos(eps) +
                          std::cos(bet) * std::sin(eps) * std::sin(lam)));
  return s;
}

SpaSteps spa(const SolarSite& site, double jd, double delta_t) {
  SpaSteps s = spa_geocentric(jd, delta_t);
  // 3.11: observer local hour angle.
  s.H = limit360(s.nu + site.longitude - s.alpha);

  // 3.12: topocentric right ascension and declination (parallax of the sun).
  const double xi = rad(8.794 / (3600.0 * s.R));
  const double phi = rad(site.latitude);
  const double u = std::atan(0.99664719 * std::tan(phi));
  const double x = std::cos(u) + site.elevation / 6378140.0 * std::cos(phi);
  const double y = 0.99664719 * std::sin(u) + site.elevation / 6378140.0 * std::sin(phi);
  const double h = rad(s.H), dl = rad(s.delta);
  const double delta_alpha = std::atan2(-x * std::sin(xi) * std::sin(h),
                                        std::cos(dl) - x * std::sin(xi) * std::cos(h));
  s.alpha_prime = s.alpha + deg(delta_alpha);
  const double dp = std::atan2((std::sin(dl) - y * std::sin(xi)) * std::cos(delta_alpha),
                               std::cos(dl) - x * std::sin(xi) * std::cos(h));
  s.delta_prime = deg(dp);

  // 3.13: topocentric local hour angle.
  s.H_prime = s.H - deg(delta_alpha);
  const double hp = rad(s.H_prime);

  // 3.14: topocentric zenith angle, refraction only while the sun can be seen.
  s.e0 = deg(std::asin(std::sin(phi) * std::sin(dp) + std::cos(phi) * std::cos(dp) * std::cos(hp)));
  s.delta_e = 0;
  if (s.e0 >= kNoRefractionBelow)
    s.delta_e = site.pressure / 1010.0 * 283.0 / (273.0 + site.temperature) * 1.02 /
                (60.0 * std::tan(rad(s.e0 + 10.3 / (s.e0 + 5.11))));
  s.zenith = 90.0 - (s.e0 + s.delta_e);

  // 3.15: topocentric azimuth, from north (the paper's astronomers' azimuth + 180).
  const double gamma = deg(std::atan2(std::sin(hp), std::cos(hp) * std::sin(phi) -
                                                        std::tan(dp) * std::cos(phi)));
  s.azimuth = limit360(gamma + 180.0);
  return s;
}

}  // namespace shadow::detail
