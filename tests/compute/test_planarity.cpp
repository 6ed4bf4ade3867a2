// SPDX-License-Identifier: GPL-3.0-or-later
// How far a face is from planar (validation/planarity.hpp, internal header), the one measure
// validation and the CityJSON reader decide planarity by: faces in a plane x_k = c measure 0
// without the sums (a shortcut), the same as the sums give; every other face is measured by the
// sums, compared here with a long double formulation of the test's own (the distance of each
// vertex from the plane through the centroid with the Newell normal). Seeded.
#include "validation/planarity.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using shadow::detail::plane_deviation;

/// The farthest vertex's distance from the plane through the centroid with the Newell normal,
/// in long double relative to the first vertex: what plane_deviation measures where its sums run.
long double reference_worst(const std::vector<glm::dvec3>& v) {
  using R = long double;
  const std::size_t n = v.size();
  R normal[3] = {0, 0, 0}, centroid[3] = {0, 0, 0};
  auto rel = [&](std::size_t i, int a) { return R(v[i][a]) - v[0][a]; };
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      normal[a] += (rel(i, b) - rel(j, b)) * (rel(i, c) + rel(j, c));
      centroid[a] += rel(i, a);
    }
  }
  const R length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  if (!(length > 0)) return 0;
  R worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    R d = 0;
    for (int a = 0; a < 3; ++a) d += (rel(i, a) - centroid[a] / R(n)) * normal[a];
    worst = std::max(worst, std::fabs(d / length));
  }
  return worst;
}

/// A random simple polygon (a star around its centre) of `n` vertices in the plane through
/// `origin` spanned by `u` and `w`.
std::vector<glm::dvec3> star(std::mt19937_64& random, int n, glm::dvec3 origin, glm::dvec3 u, glm::dvec3 w,
                             double size) {
  std::uniform_real_distribution<double> radius(0.3 * size, size);
  std::vector<glm::dvec3> v;
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * i / n;
    const double r = radius(random);
    v.push_back(origin + r * std::cos(angle) * u + r * std::sin(angle) * w);
  }
  return v;
}

TEST(Planarity, FacesInAnAxisPlaneMeasureZeroAsTheSumsDo) {
  std::mt19937_64 random(21);
  std::uniform_real_distribution<double> far(-1e6, 1e6);
  for (int trial = 0; trial < 3000; ++trial) {
    const int k = trial % 3;
    glm::dvec3 u(0.0), w(0.0);
    u[(k + 1) % 3] = 1;
    w[(k + 2) % 3] = 1;
    const double size = std::pow(10.0, trial % 13 - 6);
    std::vector<glm::dvec3> face = star(random, 3 + trial % 7, {far(random), far(random), far(random)}, u, w, size);
    for (glm::dvec3& p : face) p[k] = face[0][k];  // exactly in x_k = c
    const auto d = plane_deviation(face, 1e-6);
    EXPECT_EQ(d.worst, 0.0) << trial;
    EXPECT_EQ(static_cast<double>(reference_worst(face)), 0.0) << trial;
    EXPECT_GT(d.diameter, 0.0);
    EXPECT_GE(d.allowed, 1e-6 * d.diameter);
  }
}

TEST(Planarity, OtherFacesAreMeasuredByTheSums) {
  // Tilted planes, and axis planes with one vertex moved off by an ulp or by a millionth: the
  // sums run, as the reference's.
  std::mt19937_64 random(22);
  std::uniform_real_distribution<double> unit(-1, 1), far(-1e4, 1e4);
  int nonzero = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<glm::dvec3> face;
    if (trial % 2 == 0) {
      const glm::dvec3 n = glm::normalize(glm::dvec3(unit(random), unit(random), unit(random)));
      const glm::dvec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
      face = star(random, 3 + trial % 9, {far(random), far(random), far(random)}, u, glm::cross(n, u), 10.0);
    } else {
      face = star(random, 4 + trial % 5, {far(random), far(random), far(random)}, {1, 0, 0}, {0, 1, 0}, 10.0);
      for (glm::dvec3& p : face) p.z = face[0].z;
      face[1].z = trial % 4 == 1 ? std::nextafter(face[1].z, 1e300) : face[1].z + 1e-6;
    }
    const auto d = plane_deviation(face, 1e-6);
    EXPECT_EQ(d.worst, static_cast<double>(reference_worst(face))) << trial;
    nonzero += d.worst > 0;
  }
  EXPECT_GT(nonzero, 2000);  // the sums ran (a lifted vertex, a tilted plane's rounding)
}

}  // namespace
