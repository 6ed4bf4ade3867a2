// SPDX-License-Identifier: GPL-3.0-or-later
// The threshold map's packed exact boundaries (sunmap/packed_boundaries.hpp): whatever is
// packed unpacks to the same exact points and tags (the level areas depend on it to the last
// bit), a point where segments meet is packed once, and the rough forms are the curves' own
// doubles (the strips, tiles and plans are made from them).
#include "sunmap/packed_boundaries.hpp"

#include <gtest/gtest.h>

#include <gmpxx.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace shadow::sunmap {
namespace {

using exact::Kernel;
using exact::Point2;

/// A point holding its exact value, as the canonical boundaries make theirs.
Point2 leaf(const mpq_class& x, const mpq_class& y) { return Point2(Kernel::Exact_kernel::Point_2(x, y)); }

/// A random rational: small integers, zero, negative numbers, and numerators and denominators
/// of up to some 600 bits (crossings of shadow edges have a few hundred).
mpq_class random_rational(std::mt19937_64& rng) {
  switch (rng() % 6) {
    case 0: return mpq_class(0);
    case 1: return mpq_class(static_cast<long>(rng() % 2001) - 1000);
    default: {
      const auto big = [&](int limbs) {
        mpz_class z(0);
        for (int k = 0; k < limbs; ++k) z = (z << 64) + mpz_class(std::to_string(rng()));
        return z;
      };
      mpq_class q(big(1 + static_cast<int>(rng() % 10)), big(1 + static_cast<int>(rng() % 9)) + 1);
      q.canonicalize();
      return rng() % 2 ? q : mpq_class(-q);
    }
  }
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_rough(const RoughSegment& a, const RoughSegment& b) {
  EXPECT_TRUE(same_bits(a.xa, b.xa) && same_bits(a.ya, b.ya) && same_bits(a.xb, b.xb) && same_bits(a.yb, b.yb));
  EXPECT_TRUE(same_bits(a.xlo, b.xlo) && same_bits(a.xhi, b.xhi));
  EXPECT_EQ(a.instant, b.instant);
  EXPECT_EQ(a.left, b.left);
}

TEST(PackedBoundaries, UnpackTheSameExactPointsTagsAndRoughForms) {
  std::mt19937_64 rng(20261202);
  PackedBoundaries packed;
  std::vector<Curve> all;
  for (long instant = 0; instant < 40; ++instant) {
    // One instant's boundary: a chain whose segments meet end to end, run
    // either way (a segment's source may be its larger end), tagged either side.
    std::vector<Point2> points;
    const std::size_t n = 2 + rng() % 12;
    for (std::size_t k = 0; k < n; ++k) points.push_back(leaf(random_rational(rng), random_rational(rng)));
    std::vector<Curve> curves;
    for (std::size_t k = 0; k + 1 < n; ++k) {
      if (points[k] == points[k + 1]) continue;
      const long tag = rng() % 2 ? instant + 1 : -(instant + 1);
      curves.emplace_back(Kernel::Segment_2(points[k], points[k + 1]), tag);
    }
    packed.add(curves);
    all.insert(all.end(), curves.begin(), curves.end());
  }
  ASSERT_EQ(packed.size(), all.size());
  ASSERT_GT(all.size(), 100u);

  // A random subset, in a random order, as a strip takes them.
  std::vector<std::size_t> which(all.size());
  for (std::size_t k = 0; k < which.size(); ++k) which[k] = k;
  std::shuffle(which.begin(), which.end(), rng);
  which.resize(which.size() * 2 / 3);
  std::vector<Curve> out;
  packed.unpack(which, out);
  ASSERT_EQ(out.size(), which.size());
  for (std::size_t j = 0; j < which.size(); ++j) {
    const Curve& a = all[which[j]];
    const Curve& b = out[j];
    EXPECT_EQ(b.data(), a.data());
    EXPECT_EQ(packed.instant(which[j]), static_cast<std::size_t>(std::labs(a.data()) - 1));
    // The same exact rationals, end for end (not merely the same segment reversed).
    EXPECT_TRUE(CGAL::exact(b.source()) == CGAL::exact(a.source()));
    EXPECT_TRUE(CGAL::exact(b.target()) == CGAL::exact(a.target()));
    expect_same_rough(rough_segment(b), rough_segment(a));
  }
  // Every rough form, on one and on several threads.
  for (unsigned threads : {1u, 3u}) {
    const std::vector<RoughSegment> rough = packed.rough(threads);
    ASSERT_EQ(rough.size(), all.size());
    for (std::size_t k = 0; k < all.size(); ++k) expect_same_rough(rough[k], rough_segment(all[k]));
  }
}

TEST(PackedBoundaries, ChunksPackedApartAndAddedInOrderAreTheCurvesAdded) {
  // The map packs each face-instant pair's boundary in its own work item (in any order, on any
  // thread) and adds the chunks to the face's in instant order: the same store as adding the
  // curves themselves in that order, point for point and limb for limb.
  std::mt19937_64 rng(20261203);
  std::vector<std::vector<Curve>> instants(30);
  for (std::size_t i = 0; i < instants.size(); ++i) {
    const std::size_t n = rng() % 9;  // some instants leave no boundary
    Point2 previous = leaf(random_rational(rng), random_rational(rng));
    for (std::size_t k = 0; k < n; ++k) {
      const Point2 p = leaf(random_rational(rng), random_rational(rng));
      if (p == previous) continue;
      instants[i].emplace_back(Kernel::Segment_2(previous, p), rng() % 2 ? long(i + 1) : -long(i + 1));
      previous = p;
    }
  }
  PackedBoundaries direct;
  for (const std::vector<Curve>& c : instants) direct.add(c);
  // Packed in a shuffled order, as the threads finish them.
  std::vector<std::size_t> order(instants.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<PackedBoundaries::Chunk> chunks(instants.size());
  for (std::size_t i : order) chunks[i] = PackedBoundaries::pack(instants[i]);
  PackedBoundaries chunked;
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    EXPECT_EQ(chunks[i].size(), instants[i].size());
    chunked.add(std::move(chunks[i]));
    EXPECT_EQ(chunks[i].size(), 0u);  // taken
  }
  ASSERT_EQ(chunked.size(), direct.size());
  ASSERT_GT(direct.size(), 50u);
  EXPECT_EQ(chunked.bytes(), direct.bytes());
  std::vector<std::size_t> every(direct.size());
  for (std::size_t k = 0; k < every.size(); ++k) every[k] = k;
  std::vector<Curve> a, b;
  direct.unpack(every, a);
  chunked.unpack(every, b);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(b[k].data(), a[k].data());
    EXPECT_EQ(chunked.instant(k), direct.instant(k));
    EXPECT_TRUE(CGAL::exact(b[k].source()) == CGAL::exact(a[k].source()));
    EXPECT_TRUE(CGAL::exact(b[k].target()) == CGAL::exact(a[k].target()));
  }
  const std::vector<RoughSegment> ra = direct.rough(1), rb = chunked.rough(2);
  ASSERT_EQ(rb.size(), ra.size());
  for (std::size_t k = 0; k < ra.size(); ++k) expect_same_rough(rb[k], ra[k]);
  // And both are the curves themselves (add(curves) is add(pack(curves)) now: the offsets of
  // the chunks after the first are checked against the source, not only against each other).
  std::size_t k = 0;
  for (const std::vector<Curve>& curves : instants)
    for (const Curve& c : curves) {
      EXPECT_EQ(b[k].data(), c.data());
      EXPECT_TRUE(CGAL::exact(b[k].source()) == CGAL::exact(c.source()));
      EXPECT_TRUE(CGAL::exact(b[k].target()) == CGAL::exact(c.target()));
      expect_same_rough(rb[k], rough_segment(c));
      ++k;
    }
  EXPECT_EQ(k, b.size());
}

TEST(PackedBoundaries, HoldsAFractionOfTheCurvesMemory) {
  // Segments whose ends have numerators of up to 4 limbs and 2-limb denominators (the order of a
  // shadow crossing's): 14 limbs and an offset a point, 32 bytes a segment, some 150 bytes in all
  // (a Curve and its share of lazy points and GMP numbers: about 575).
  std::mt19937_64 rng(7);
  PackedBoundaries packed;
  std::vector<Curve> curves;
  const mpz_class den = (mpz_class(1) << 100) + 12345;
  Point2 previous = leaf(mpq_class(1, 3), mpq_class(2, 3));
  for (int k = 0; k < 1000; ++k) {
    const mpz_class num = (mpz_class(std::to_string(rng())) << 130) + k;
    mpq_class x(num, den), y(num + 1, den);
    x.canonicalize(), y.canonicalize();
    const Point2 p = leaf(x, y);
    curves.emplace_back(Kernel::Segment_2(previous, p), 1);
    previous = p;
  }
  packed.add(curves);
  EXPECT_EQ(packed.size(), 1000u);
  EXPECT_LT(packed.bytes(), 1000u * 200u);  // each point once (twice would be some 270 bytes)
  EXPECT_GT(packed.bytes(), 1000u * 80u);  // the limbs are there, not references to the curves'
}

}  // namespace
}  // namespace shadow::sunmap
