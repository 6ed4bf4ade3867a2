// SPDX-License-Identifier: GPL-3.0-or-later
// The receivers' order along a curve through the scene (core/spatial_order.hpp, internal
// header): a permutation, stable where places tie, the radix sort the same as a comparison sort,
// a convex solid's faces together, and neighbours in the order near in space. Seeded. That the
// order changes no result is the engines' tests' business (every receiver alone; the golden
// digests).
#include "core/spatial_order.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

namespace {

using shadow::core::ConvexSolid;
using shadow::core::CullScene;
using shadow::core::morton_code;
using shadow::core::spatial_order;

/// A cull scene of one-vertex faces at `places` (all the order reads of a face).
CullScene faces_at(const std::vector<glm::dvec3>& places, double diameter) {
  CullScene cull;
  cull.diameter = diameter;
  cull.vertices.resize(places.size());
  cull.faces.resize(places.size());
  for (std::size_t f = 0; f < places.size(); ++f) {
    cull.vertices[f] = places[f];
    cull.faces[f].first = f;
    cull.faces[f].count = 1;
  }
  return cull;
}

/// Random places in a city-shaped box (wide and flat), in random order.
std::vector<glm::dvec3> random_places(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> across(-2000, 2000), up(0, 40);
  std::vector<glm::dvec3> places(n);
  for (glm::dvec3& p : places) p = {across(rng), across(rng), up(rng)};
  return places;
}

/// The order by a comparison sort of the same 32-bit keys: what the radix passes must equal.
std::vector<std::size_t> by_comparison(const std::vector<glm::dvec3>& places, double diameter) {
  std::vector<std::size_t> order(places.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return morton_code(places[a], diameter) >> 31 < morton_code(places[b], diameter) >> 31;
  });
  return order;
}

TEST(SpatialOrder, MortonCodesGrowWithEachCoordinate) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(-100, 100);
  for (int trial = 0; trial < 2000; ++trial) {
    const glm::dvec3 p(at(rng), at(rng), at(rng));
    for (int a = 0; a < 3; ++a) {
      glm::dvec3 q = p;
      q[a] += std::abs(at(rng));
      EXPECT_LE(morton_code(p, 100), morton_code(q, 100));
    }
  }
  // Outside the frame's reach, or not finite: clamped to its ends, never undefined.
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(morton_code({-1e300, -inf, std::nan("")}, 1.0), 0u);
  EXPECT_EQ(morton_code({1e300, 1e300, 1e300}, 1.0), (std::uint64_t{1} << 63) - 1);
}

TEST(SpatialOrder, IsThePermutationOfAStableSortOfThePlaces) {
  // Below and above the radix sort's threshold, with many ties (a coarse lattice of places).
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{1000}, std::size_t{50000}}) {
    std::vector<glm::dvec3> places = random_places(n, static_cast<unsigned>(n) + 3);
    for (std::size_t f = 0; f < n; f += 3) places[f] = glm::round(places[f] / 500.0) * 500.0;
    const CullScene cull = faces_at(places, 4000);
    for (const unsigned threads : {1u, 2u, 3u}) {
      const std::vector<std::size_t> order =
          spatial_order(cull, {}, {}, n, [](std::size_t r) { return r; }, threads);
      EXPECT_EQ(order, by_comparison(places, 4000)) << n << " faces, " << threads << " threads";
    }
  }
}

TEST(SpatialOrder, KeepsAConvexSolidsFacesTogetherInTheirOrder) {
  // 3,000 boxes of 6 faces (18,000: the radix path), the boxes in random order; each face's own
  // vertex at a corner of its box, so only the solid's place keeps them together.
  std::mt19937 rng(11);
  const std::vector<glm::dvec3> corners = random_places(3000, 5);
  std::vector<ConvexSolid> solids(corners.size());
  std::vector<glm::dvec3> places;
  std::vector<int> solid_of;
  for (std::size_t s = 0; s < corners.size(); ++s) {
    solids[s].vertices = {corners[s], corners[s] + glm::dvec3(10, 10, 10)};
    for (int k = 0; k < 6; ++k) {
      places.push_back(corners[s] + glm::dvec3(std::uniform_real_distribution<double>(0, 10)(rng)));
      solid_of.push_back(static_cast<int>(s));
    }
  }
  const CullScene cull = faces_at(places, 4000);
  const std::vector<std::size_t> order =
      spatial_order(cull, solid_of, solids, places.size(), [](std::size_t r) { return r; }, 2);
  for (std::size_t i = 0; i < order.size(); i += 6)
    for (std::size_t k = 1; k < 6; ++k) EXPECT_EQ(order[i + k], order[i] + k) << "at " << i;
}

TEST(SpatialOrder, ConsecutiveReceiversAreNearEachOther) {
  // Places in random order: consecutive ones about 2,000 apart; along the curve, a few tens.
  const std::vector<glm::dvec3> places = random_places(100000, 9);
  const CullScene cull = faces_at(places, 4000);
  const std::vector<std::size_t> order =
      spatial_order(cull, {}, {}, places.size(), [](std::size_t r) { return r; }, 2);
  double given = 0, along = 0;
  for (std::size_t i = 1; i < places.size(); ++i) {
    given += glm::distance(places[i - 1], places[i]);
    along += glm::distance(places[order[i - 1]], places[order[i]]);
  }
  EXPECT_LT(along, given / 20);
}

TEST(SpatialOrder, ReadsTheReceiversThroughFaceOf) {
  // Receivers 0..n-1 that are faces n-1..0: the order of rows, by their faces' places.
  const std::vector<glm::dvec3> places = random_places(6000, 13);
  const CullScene cull = faces_at(places, 4000);
  const std::size_t n = places.size();
  const std::vector<std::size_t> rows = spatial_order(cull, {}, {}, n, [&](std::size_t r) { return n - 1 - r; }, 2);
  std::vector<glm::dvec3> reversed(places.rbegin(), places.rend());
  EXPECT_EQ(rows, by_comparison(reversed, 4000));
}

}  // namespace
