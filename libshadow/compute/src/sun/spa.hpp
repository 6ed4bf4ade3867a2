// SPDX-License-Identifier: GPL-3.0-or-later
// NREL's Solar Position Algorithm step by step (Reda & Andreas 2004, NREL/TP-560-34302): the
// intermediate quantities are kept so that tests can check each against published examples
// (the SPA paper's Table A5.1, Meeus's Astronomical Algorithms examples).
#pragma once

#include <shadow/sun.hpp>

namespace shadow::detail {

/// Every quantity of the SPA, named as in the paper; angles in degrees.
struct SpaSteps {
  double jd = 0;             ///< Julian day (UT)
  double jde = 0;            ///< Julian ephemeris day (TT)
  double L = 0;              ///< Earth heliocentric longitude, [0, 360)
  double B = 0;              ///< Earth heliocentric latitude
  double R = 0;              ///< Earth-Sun distance, astronomical units
  double theta = 0;          ///< geocentric longitude
  double beta = 0;           ///< geocentric latitude
  double delta_psi = 0;      ///< nutation in longitude
  double delta_epsilon = 0;  ///< nutation in obliquity
  double epsilon = 0;        ///< true obliquity of the ecliptic
  double lambda = 0;         ///< apparent sun longitude
  double nu = 0;             ///< apparent sidereal time at Greenwich, [0, 360)
  double alpha = 0;          ///< geocentric right ascension, [0, 360)
  double delta = 0;          ///< geocentric declination
  double H = 0;              ///< observer local hour angle, [0, 360)
  double alpha_prime = 0;    ///< topocentric right ascension
  double delta_prime = 0;    ///< topocentric declination
  double H_prime = 0;        ///< topocentric local hour angle
  double e0 = 0;             ///< topocentric elevation without refraction
  double delta_e = 0;        ///< refraction correction (0 below the horizon limit)
  double zenith = 0;         ///< topocentric zenith angle
  double azimuth = 0;        ///< topocentric azimuth, clockwise from north, [0, 360)
};

/// The SPA for Julian day `jd` (UT, fractional), `delta_t` seconds TT - UT.
SpaSteps spa(const SolarSite& site, double jd, double delta_t);

/// The geocentric part only (up to alpha, delta and nu; H and later are left 0).
SpaSteps spa_geocentric(double jd, double delta_t);

/// Geometric elevation below which no refraction is applied: the sun's upper limb on the
/// refracted horizon (semi-diameter 0.26667 + refraction at the horizon 0.5667 degrees).
inline constexpr double kNoRefractionBelow = -(0.26667 + 0.5667);

}  // namespace shadow::detail
