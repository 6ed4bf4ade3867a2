// SPDX-License-Identifier: GPL-3.0-or-later
// The fixed-width steps of the integer charts (exact/fixed_width.hpp, internal) against GMP:
// conversions both ways, the gcd, projections, plane values, plane crossings and the chart
// box's cuts, the intervals of fixed-width integers (exact/rational_points.hpp's
// interval_of_integer against interval_of of the same GMP rational), on random operands of every size up to the bounds (rapidcheck, seeded in
// tests/CMakeLists.txt) and on extreme ones (zero, one, the largest accepted, the smallest
// refused); and the fallback: an operand past a bound is refused (the caller then takes GMP),
// never wrapped.
#include "exact/fixed_width.hpp"
#include "exact/rational_points.hpp"

#include <gmpxx.h>
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace {

namespace fx = shadow::exact::fixed;
using fx::i128;
using fx::u128;

mpz_class to_mpz(i128 v) {
  const bool neg = v < 0;
  const u128 m = fx::magnitude(v);
  mpz_class hi(static_cast<unsigned long>(m >> 64)), lo(static_cast<unsigned long>(m));
  mpz_class r = (hi << 64) + lo;
  return neg ? mpz_class(-r) : r;
}

/// A random signed integer of exactly `bits` bits (0 bits: zero).
i128 of_bits(int bits, std::uint64_t lo, std::uint64_t hi, bool negative) {
  if (bits == 0) return 0;
  u128 m = (static_cast<u128>(hi) << 64) | lo;
  if (bits < 128) m &= (u128{1} << bits) - 1;
  m |= u128{1} << (bits - 1);
  const auto v = static_cast<i128>(m);
  return negative ? -v : v;
}

rc::Gen<i128> integer_of_at_most(int max_bits) {
  return rc::gen::apply(
      [](int bits, std::uint64_t lo, std::uint64_t hi, bool negative) { return of_bits(bits, lo, hi, negative); },
      rc::gen::inRange(0, max_bits + 1), rc::gen::arbitrary<std::uint64_t>(), rc::gen::arbitrary<std::uint64_t>(),
      rc::gen::arbitrary<bool>());
}

TEST(FixedWidth, ConversionsAtTheEdges) {
  const i128 top = (i128{1} << 126) - 1;  // the largest accepted magnitude
  for (i128 v : {i128{0}, i128{1}, i128{-1}, i128{INT64_MAX}, i128{INT64_MIN}, top, -top, i128{1} << 64}) {
    mpz_class z;
    fx::set_mpz(z.get_mpz_t(), v);
    EXPECT_EQ(z, to_mpz(v));
    i128 back = 12345;
    ASSERT_TRUE(fx::to_i128(z.get_mpz_t(), back));
    EXPECT_TRUE(back == v);
  }
  i128 out = 0;
  mpz_class z = mpz_class(1) << 126;  // 2^126: refused, as is everything larger
  EXPECT_FALSE(fx::to_i128(z.get_mpz_t(), out));
  z = -z;
  EXPECT_FALSE(fx::to_i128(z.get_mpz_t(), out));
  z = mpz_class(1) << 200;
  EXPECT_FALSE(fx::to_i128(z.get_mpz_t(), out));
  EXPECT_EQ(fx::bit_width(i128{0}), 0);
  EXPECT_EQ(fx::bit_width(i128{-1}), 1);
  EXPECT_EQ(fx::bit_width(top), 126);
  EXPECT_EQ(fx::bit_width(u128{1} << 127), 128);
}

/// interval_of_integer(v) is interval_of of v as a GMP rational, endpoint for endpoint.
void expect_interval_of_integer_is_gmps(i128 v) {
  const mpq_class q(to_mpz(v));
  const shadow::exact::IA want = shadow::exact::interval_of(q);
  const shadow::exact::IA got = shadow::exact::interval_of_integer(v);
  EXPECT_EQ(got.inf(), want.inf()) << static_cast<double>(v);
  EXPECT_EQ(got.sup(), want.sup()) << static_cast<double>(v);
  EXPECT_LE(got.inf(), static_cast<long double>(v));
}

TEST(FixedWidth, IntervalOfAnIntegerAtTheEdges) {
  const i128 p53 = i128{1} << 53;
  for (i128 v : {i128{0}, i128{1}, p53 - 1, p53, p53 + 1, 2 * p53 - 1, 2 * p53 + 1, i128{INT64_MAX},
                 (i128{1} << 126) - 1, (i128{1} << 126) + 12345, static_cast<i128>((u128{1} << 127) - 1)}) {
    expect_interval_of_integer_is_gmps(v);
    expect_interval_of_integer_is_gmps(-v);
  }
}

RC_GTEST_PROP(FixedWidth, IntervalOfAnIntegerIsGmps, ()) {
  const i128 v = *integer_of_at_most(127);
  const mpq_class q(to_mpz(v));
  const shadow::exact::IA want = shadow::exact::interval_of(q);
  const shadow::exact::IA got = shadow::exact::interval_of_integer(v);
  RC_ASSERT(got.inf() == want.inf());
  RC_ASSERT(got.sup() == want.sup());
}

TEST(FixedWidth, GcdAtTheEdges) {
  EXPECT_TRUE(fx::gcd(0, 0) == 0);
  EXPECT_TRUE(fx::gcd(0, 7) == 7);
  EXPECT_TRUE(fx::gcd(7, 0) == 7);
  EXPECT_TRUE(fx::gcd(u128{1} << 120, u128{3} << 60) == (u128{1} << 60));
  const u128 big = (u128{1} << 126) - 1;
  EXPECT_TRUE(fx::gcd(big, big) == big);
  EXPECT_TRUE(fx::gcd(big, 1) == 1);
}

RC_GTEST_PROP(FixedWidth, GcdIsGmps, ()) {
  const i128 a = *integer_of_at_most(127), b = *integer_of_at_most(127);
  const mpz_class g = gcd(to_mpz(a), to_mpz(b));
  RC_ASSERT(to_mpz(static_cast<i128>(fx::gcd(fx::magnitude(a), fx::magnitude(b)))) == g);
}

RC_GTEST_PROP(FixedWidth, ConversionsRoundTrip, ()) {
  const i128 v = *integer_of_at_most(126);
  mpz_class z = 99;  // overwritten whatever it held
  fx::set_mpz(z.get_mpz_t(), v);
  RC_ASSERT(z == to_mpz(v));
  i128 back = 0;
  RC_ASSERT(fx::to_i128(z.get_mpz_t(), back));
  RC_ASSERT(back == v);
}

RC_GTEST_PROP(FixedWidth, ProjectionIsGmpsOrRefused, ()) {
  const i128 y = *integer_of_at_most(100), l = *integer_of_at_most(100);
  const i128 s = *integer_of_at_most(100), d = *integer_of_at_most(100);
  i128 out = 0;
  const bool fits = fx::bit_width(y) + fx::bit_width(l) <= 125 && fx::bit_width(s) + fx::bit_width(d) <= 125;
  RC_ASSERT(fx::projection(y, l, s, d, out) == fits);
  if (fits) RC_ASSERT(to_mpz(out) == to_mpz(y) * to_mpz(l) - to_mpz(s) * to_mpz(d));
}

RC_GTEST_PROP(FixedWidth, PlaneValueIsGmpsOrRefused, ()) {
  const i128 n[3] = {*integer_of_at_most(70), *integer_of_at_most(70), *integer_of_at_most(70)};
  const i128 y[3] = {*integer_of_at_most(70), *integer_of_at_most(70), *integer_of_at_most(70)};
  const i128 o = *integer_of_at_most(126);
  i128 out = 0;
  bool fits = fx::bit_width(o) <= 124;
  for (int k = 0; k < 3; ++k) fits = fits && fx::bit_width(n[k]) + fx::bit_width(y[k]) <= 124;
  RC_ASSERT(fx::plane_value(n, o, y, out) == fits);
  if (fits)
    RC_ASSERT(to_mpz(out) == to_mpz(o) + to_mpz(n[0]) * to_mpz(y[0]) + to_mpz(n[1]) * to_mpz(y[1]) +
                                 to_mpz(n[2]) * to_mpz(y[2]));
}

/// The crossing's fraction as GMP makes it: L (Sa B - Sb A) / (Sa - Sb), canonicalised.
mpq_class gmp_crossing(i128 l, i128 sa, i128 sb, i128 a, i128 b) {
  mpq_class q(to_mpz(l) * (to_mpz(sa) * to_mpz(b) - to_mpz(sb) * to_mpz(a)), to_mpz(sa) - to_mpz(sb));
  q.canonicalize();
  return q;
}

void expect_crossing(i128 l, i128 sa, i128 sb, i128 a, i128 b) {
  mpq_class got(7, 3);  // overwritten
  ASSERT_TRUE(fx::crossing(l, sa, sb, a, b, mpq_numref(got.get_mpq_t()), mpq_denref(got.get_mpq_t())));
  const mpq_class want = gmp_crossing(l, sa, sb, a, b);
  EXPECT_EQ(mpz_class(got.get_num()), mpz_class(want.get_num()));  // the same canonical pair
  EXPECT_EQ(mpz_class(got.get_den()), mpz_class(want.get_den()));
}

RC_GTEST_PROP(FixedWidth, CrossingIsGmpsCanonicalFraction, ()) {
  const u128 lm = fx::magnitude(*integer_of_at_most(62));
  const i128 l = lm == 0 ? 1 : static_cast<i128>(lm);  // L > 0 (scaled_chart.hpp chooses D's sign so)
  // Sa and Sb of opposite signs, with a common factor now and then (both reduction steps).
  const i128 factor = *rc::gen::element<i128>(1, 2, 3, 6, 1024, 999983);
  const i128 sa0 = *integer_of_at_most(50);
  RC_PRE(sa0 != 0);
  const i128 sa = sa0 * factor;
  const i128 sb_magnitude = static_cast<i128>(fx::magnitude(*integer_of_at_most(50)) | 1) * factor;
  const i128 sb = sa > 0 ? -sb_magnitude : sb_magnitude;
  const i128 a = *integer_of_at_most(62), b = *integer_of_at_most(62);
  mpq_class got;
  RC_ASSERT(fx::crossing(l, sa, sb, a, b, mpq_numref(got.get_mpq_t()), mpq_denref(got.get_mpq_t())));
  const mpq_class want = gmp_crossing(l, sa, sb, a, b);
  RC_ASSERT(mpz_class(got.get_num()) == mpz_class(want.get_num()));
  RC_ASSERT(mpz_class(got.get_den()) == mpz_class(want.get_den()));
}

TEST(FixedWidth, CrossingAtTheEdges) {
  const i128 big = (i128{1} << 62) - 1;
  expect_crossing(1, 1, -1, 0, 0);                  // zero: 0 / 1
  expect_crossing(5, 3, -3, 7, 7);                  // a vertical edge: the denominator divides
  expect_crossing(6, 4, -2, 1, 5);                  // l shares a factor with the denominator
  expect_crossing(big, big, -big, big, -big);       // the largest operands of 62 bits
  expect_crossing(big, -big, 1, -big, big);         // and of opposite signs
  expect_crossing(INT64_MAX, 2, -1, big, big - 1);  // l of 63 bits
}

TEST(FixedWidth, CrossingRefusesWhatWouldOverflow) {
  mpz_class n, d;
  const i128 wide = i128{1} << 70;
  // sa b past 2^125: refused (GMP takes it), not wrapped.
  EXPECT_FALSE(fx::crossing(3, wide, -1, 1, i128{1} << 60, n.get_mpz_t(), d.get_mpz_t()));
  // l of 64 bits: refused.
  EXPECT_FALSE(fx::crossing(i128{1} << 63, 1, -1, 1, 2, n.get_mpz_t(), d.get_mpz_t()));
  // Just inside: operands of 62 and 63 bits (125 together) are accepted and exact.
  expect_crossing(3, (i128{1} << 62) - 1, -1, 1, (i128{1} << 63) - 1);
}

/// The cut's fraction as GMP makes it: (ao (bc - m) + bo (m - ac)) / (bc - ac), canonicalised.
mpq_class gmp_cut(i128 ao, i128 bo, i128 ac, i128 bc, i128 m) {
  const mpz_class n = to_mpz(ao) * (to_mpz(bc) - to_mpz(m)) + to_mpz(bo) * (to_mpz(m) - to_mpz(ac));
  mpq_class q(n, to_mpz(bc) - to_mpz(ac));
  q.canonicalize();
  return q;
}

bool cut_is_gmps(i128 ao, i128 bo, i128 ac, i128 bc, i128 m) {
  mpq_class got(5, 7);
  mpz_class t = 3;
  if (!fx::cut(ao, bo, ac, bc, m, mpq_numref(got.get_mpq_t()), mpq_denref(got.get_mpq_t()), t.get_mpz_t())) return false;
  const mpq_class want = gmp_cut(ao, bo, ac, bc, m);
  return mpz_class(got.get_num()) == mpz_class(want.get_num()) && mpz_class(got.get_den()) == mpz_class(want.get_den());
}

RC_GTEST_PROP(FixedWidth, CutIsGmpsCanonicalFraction, ()) {
  // Operands of every size up to the bound, with a shared factor now and then (both gcds).
  const i128 factor = *rc::gen::element<i128>(1, 2, 12, 1 << 20, 999983);
  const int bits = *rc::gen::inRange(1, 105);
  const i128 ao = *integer_of_at_most(125), bo = *integer_of_at_most(125);
  const i128 ac = *integer_of_at_most(bits) * factor, bc = *integer_of_at_most(bits) * factor;
  const i128 m = *integer_of_at_most(bits) * factor;
  RC_PRE(ac != bc);
  RC_ASSERT(cut_is_gmps(ao, bo, ac, bc, m));
}

TEST(FixedWidth, CutAtTheEdges) {
  const i128 top = (i128{1} << 125) - 1;  // the largest accepted operand
  EXPECT_TRUE(cut_is_gmps(0, 0, 0, 1, 0));
  EXPECT_TRUE(cut_is_gmps(3, 3, -1, 1, 0));           // along a line x = 3
  EXPECT_TRUE(cut_is_gmps(0, 10, 0, 4, 2));           // halfway: 5 / 1
  EXPECT_TRUE(cut_is_gmps(1, 2, 0, 3, 1));            // 4 / 3
  EXPECT_TRUE(cut_is_gmps(top, -top, -top, top, 0));  // the widest differences, 2^126 - 2
  EXPECT_TRUE(cut_is_gmps(-top, top, top, -top, 1));  // the other way round
  EXPECT_TRUE(cut_is_gmps(top, top - 1, 1, top, top - 7));
  mpq_class q;
  mpz_class t;
  // An operand of 126 bits: refused (the caller's GMP path takes it), never wrapped.
  EXPECT_FALSE(fx::cut(i128{1} << 125, 0, 0, 1, 0, mpq_numref(q.get_mpq_t()), mpq_denref(q.get_mpq_t()), t.get_mpz_t()));
  EXPECT_FALSE(fx::cut(0, 0, -(i128{1} << 125), 1, 0, mpq_numref(q.get_mpq_t()), mpq_denref(q.get_mpq_t()), t.get_mpz_t()));
}

}  // namespace
