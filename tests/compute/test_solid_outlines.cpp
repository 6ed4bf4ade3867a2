// SPDX-License-Identifier: GPL-3.0-or-later
// The convex solids' outlines seen from a light (core/solid_outlines.hpp, internal header),
// checked by a formulation of their own: seen from the light, every other vertex of the solid
// lies strictly to the left of every outline edge (a triple product in long double, no light-space
// frame), so the outline is the projected hull, counter-clockwise. Solids seen edge-on or
// straight down an edge get none. Seeded.
#include "core/solid_outlines.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>
#include <vector>

namespace {

using shadow::core::ConvexSolid;
using shadow::core::SolidOutlines;

/// An axis-aligned box [x0, x1] x [y0, y1] x [z0, z1] (its vertices; outlines read no edges).
ConvexSolid box(double x0, double y0, double z0, double x1, double y1, double z1) {
  ConvexSolid s;
  for (double z : {z0, z1})
    for (double y : {y0, y1})
      for (double x : {x0, x1}) s.vertices.push_back({x, y, z});
  return s;
}

/// The box turned about the z axis by `angle` about the origin, then about the x axis by `tilt`.
ConvexSolid turned(ConvexSolid s, double angle, double tilt) {
  for (glm::dvec3& p : s.vertices) {
    const double x = std::cos(angle) * p.x - std::sin(angle) * p.y, y = std::sin(angle) * p.x + std::cos(angle) * p.y;
    p = {x, std::cos(tilt) * y - std::sin(tilt) * p.z, std::sin(tilt) * y + std::cos(tilt) * p.z};
  }
  return s;
}

/// The outlines of `solids` seen from `to_light`, in a frame across it made here.
SolidOutlines outlines_from(const std::vector<ConvexSolid>& solids, const glm::dvec3& to_light, unsigned threads = 1) {
  const glm::dvec3 d = glm::normalize(to_light);
  const glm::dvec3 u = glm::normalize(glm::cross(d, std::abs(d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  return SolidOutlines(solids, u, glm::cross(d, u), threads);
}

/// Seen from the light (towards -to_light), `y` lies strictly left of a -> b.
bool left_of(const glm::dvec3& to_light, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& y) {
  const long double ux = static_cast<long double>(b.x) - a.x, uy = static_cast<long double>(b.y) - a.y,
                    uz = static_cast<long double>(b.z) - a.z;
  const long double wx = static_cast<long double>(y.x) - a.x, wy = static_cast<long double>(y.y) - a.y,
                    wz = static_cast<long double>(y.z) - a.z;
  const long double cx = uy * wz - uz * wy, cy = uz * wx - ux * wz, cz = ux * wy - uy * wx;
  return to_light.x * cx + to_light.y * cy + to_light.z * cz > 0;
}

/// Every outline of `outlines` is the hull of its solid's vertices seen from the light,
/// counter-clockwise; returns how many solids have one.
std::size_t check_outlines(const std::vector<ConvexSolid>& solids, const glm::dvec3& to_light,
                           const SolidOutlines& outlines) {
  std::size_t found = 0;
  for (std::size_t s = 0; s < solids.size(); ++s) {
    const SolidOutlines::Outline o = outlines.outline(s);
    if (o.size == 0) continue;
    ++found;
    const std::vector<glm::dvec3>& v = solids[s].vertices;
    EXPECT_GE(o.size, 3u);
    for (std::size_t c = 0; c < o.size; ++c) {
      const std::size_t a = o.data[c], b = o.data[(c + 1) % o.size];
      for (std::size_t y = 0; y < v.size(); ++y)
        if (y != a && y != b) EXPECT_TRUE(left_of(to_light, v[a], v[b], v[y])) << "solid " << s << " corner " << c << " vertex " << y;
    }
  }
  return found;
}

TEST(SolidOutlines, AreTheProjectedHullsCounterClockwiseSeenFromTheLight) {
  std::mt19937_64 rng(20261206);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<ConvexSolid> solids;
  for (int i = 0; i < 200; ++i) {
    const double x = 100 * unit(rng), y = 100 * unit(rng), w = 1 + 20 * unit(rng), d = 1 + 20 * unit(rng),
                 h = 1 + 60 * unit(rng);
    ConvexSolid s = box(x, y, 0, x + w, y + d, h);
    if (i % 2 == 1) s = turned(s, 6.3 * unit(rng), 0.5 * unit(rng));
    solids.push_back(s);
  }
  std::size_t found = 0, total = 0;
  for (int k = 0; k < 40; ++k) {
    const double elevation = 0.02 + 1.5 * unit(rng), azimuth = 6.3 * unit(rng);
    const glm::dvec3 to_light(std::cos(elevation) * std::sin(azimuth), std::cos(elevation) * std::cos(azimuth),
                              std::sin(elevation));
    const SolidOutlines outlines = outlines_from(solids, to_light, 1 + static_cast<unsigned>(k % 3));
    found += check_outlines(solids, to_light, outlines);
    total += solids.size();
  }
  // A box seen from a general direction shows 6 corners, its 2 other vertices inside: nearly all get one.
  EXPECT_GT(found, total * 99 / 100);
}

TEST(SolidOutlines, NoneWhereVerticesProjectOntoTheOutlinesEdgesOrCorners) {
  const std::vector<ConvexSolid> solids{box(0, 0, 0, 10, 20, 30)};
  // Straight down: each top corner covers a bottom one.
  EXPECT_EQ(outlines_from(solids, {0, 0, 1}).outline(0).size, 0u);
  // Along the faces x = 0 and x = 10 (edge-on): their vertices lie on two of the outline's edges.
  EXPECT_EQ(outlines_from(solids, {0, 1, 1}).outline(0).size, 0u);
  // A general direction: six corners.
  const glm::dvec3 general(0.3, -0.4, 0.8);
  const SolidOutlines outlines = outlines_from(solids, general);
  EXPECT_EQ(outlines.outline(0).size, 6u);
  EXPECT_EQ(check_outlines(solids, general, outlines), 1u);
  // Tied to the solids they were found for (their vertex indices mean nothing for others).
  const std::vector<ConvexSolid> copy = solids;
  EXPECT_TRUE(outlines.of(&solids));
  EXPECT_FALSE(outlines.of(&copy));
  EXPECT_FALSE(SolidOutlines().of(nullptr));
  // Out of range, and no solids.
  EXPECT_EQ(outlines.outline(1).size, 0u);
  EXPECT_EQ(SolidOutlines().outline(0).size, 0u);
  EXPECT_EQ(outlines_from({}, general).outline(0).size, 0u);
}

TEST(SolidOutlines, TinySolidsGetNoneWhereRoundingIsNoLongerRelative) {
  // The exact engine takes its hulls from the outlines, so they must stay certain at every
  // scale: a box some 1e-90 across still gets one (its squares are normal doubles), one of
  // some 1e-150 does not (they would not be), nor one of 2^-1000.
  const glm::dvec3 general(0.3, -0.4, 0.8);
  for (const int e : {-300, -500, -1000}) {
    const double s = std::ldexp(1.0, e);
    const std::vector<ConvexSolid> solids{box(0, 0, 0, 10 * s, 20 * s, 30 * s)};
    const SolidOutlines outlines = outlines_from(solids, general);
    EXPECT_EQ(outlines.outline(0).size, e == -300 ? 6u : 0u) << "2^" << e;
    if (e == -300) EXPECT_EQ(check_outlines(solids, general, outlines), 1u);
  }
}

TEST(SolidOutlines, TheSameOnEveryThreadCount) {
  std::vector<ConvexSolid> solids;
  for (int i = 0; i < 3000; ++i) solids.push_back(turned(box(i % 50, i / 50, 0, i % 50 + 0.7, i / 50 + 0.4, 1 + i % 7), 0.01 * i, 0.0));
  const glm::dvec3 to_light(0.2, 0.5, 0.3);
  const SolidOutlines one = outlines_from(solids, to_light, 1), three = outlines_from(solids, to_light, 3);
  for (std::size_t s = 0; s < solids.size(); ++s) {
    const SolidOutlines::Outline a = one.outline(s), b = three.outline(s);
    ASSERT_EQ(a.size, b.size);
    for (std::size_t c = 0; c < a.size; ++c) EXPECT_EQ(a.data[c], b.data[c]);
  }
}

}  // namespace
