// SPDX-License-Identifier: GPL-3.0-or-later
// Fixed-width integer steps of the areas route's integer charts (exact/scaled_chart.hpp) and of
// the planar face areas (exact_faces.cpp), with GMP as the fallback. Include only from
// src/exact/*.cpp or tests.
//
// A scaled chart's projection is Y_k L - S D_k and its plane crossing L (S_a B_k - S_b A_k) /
// (S_a - S_b), all integers (the top of scaled_chart.hpp). Their sizes are bounded by the
// scene's and the light's bit spans (kChartSpanBits, kDirectionSpanBits: up to 430 bits), far
// beyond 128; but in a city of metres with millimetre-exact doubles and a sun direction of
// doubles they are some 60 bits each (Y, S, L, D) and the projections some 120 (measured:
// docs/benchmarks.md, "Eighth look"). Each step here first checks, from the operands' bit
// counts, that every product and sum it forms stays below 2^126 (so nothing overflows a signed
// __int128), and returns false when one would not: the caller then takes its GMP path. Both
// give the same integers and the same canonical fractions.
#pragma once

#include <gmp.h>

#include <cstdint>
#include <initializer_list>

namespace shadow::exact::fixed {

__extension__ typedef __int128 i128;  // (__extension__: -Wpedantic knows no __int128)
__extension__ typedef unsigned __int128 u128;

/// Bits of |v| (0 for 0): v < 2^bits.
inline int bit_width(u128 v) {
  const auto hi = static_cast<std::uint64_t>(v >> 64);
  if (hi != 0) return 128 - __builtin_clzll(hi);
  const auto lo = static_cast<std::uint64_t>(v);
  return lo == 0 ? 0 : 64 - __builtin_clzll(lo);
}
inline u128 magnitude(i128 v) { return v < 0 ? -static_cast<u128>(v) : static_cast<u128>(v); }
inline int bit_width(i128 v) { return bit_width(magnitude(v)); }

/// The widest operand of a sum of the products below: two products of 125 bits and less, or
/// four of 124, stay below 2^126, within a signed __int128 with a bit to spare.
constexpr int kProductBits = 125;

/// z as an __int128 when |z| < 2^126 (else false).
inline bool to_i128(mpz_srcptr z, i128& out) {
  const int size = z->_mp_size;
  const int n = size < 0 ? -size : size;
  if (n > 2) return false;
  u128 m = 0;
  if (n >= 1) m = z->_mp_d[0];
  if (n == 2) m |= static_cast<u128>(z->_mp_d[1]) << 64;
  if (bit_width(m) > 126) return false;
  out = size < 0 ? -static_cast<i128>(m) : static_cast<i128>(m);
  return true;
}

/// out = v, exactly.
inline void set_mpz(mpz_ptr out, i128 v) {
  static_assert(sizeof(mp_limb_t) == 8, "64-bit GMP limbs");
  const u128 m = magnitude(v);
  const auto lo = static_cast<mp_limb_t>(m), hi = static_cast<mp_limb_t>(m >> 64);
  const int n = hi != 0 ? 2 : (lo != 0 ? 1 : 0);
  mp_limb_t* limbs = mpz_limbs_write(out, 2);
  limbs[0] = lo;
  limbs[1] = hi;
  mpz_limbs_finish(out, v < 0 ? -n : n);
}

/// gcd(a, b) (gcd(0, b) = b): Stein's binary algorithm, after one Euclidean step that brings
/// the larger down to the smaller's size.
inline u128 gcd(u128 a, u128 b) {
  if (a < b) {
    const u128 t = a;
    a = b;
    b = t;
  }
  if (b == 0) return a;
  a %= b;
  if (a == 0) return b;
  auto ctz = [](u128 v) {
    const auto lo = static_cast<std::uint64_t>(v);
    return lo != 0 ? __builtin_ctzll(lo) : 64 + __builtin_ctzll(static_cast<std::uint64_t>(v >> 64));
  };
  const int shift = ctz(a | b);
  a >>= ctz(a);
  do {
    b >>= ctz(b);
    if (a > b) {
      const u128 t = a;
      a = b;
      b = t;
    }
    b -= a;
  } while (b != 0);
  return a << shift;
}

/// y l - s d into out, when the bounds hold (a projection: scaled_chart.hpp's Y_k L - S D_k).
inline bool projection(i128 y, i128 l, i128 s, i128 d, i128& out) {
  if (bit_width(y) + bit_width(l) > kProductBits || bit_width(s) + bit_width(d) > kProductBits) return false;
  out = y * l - s * d;
  return true;
}

/// o + n . y into out (a plane value: scaled_chart.hpp's S = N.Y + O), when the bounds hold.
inline bool plane_value(const i128 n[3], i128 o, const i128 y[3], i128& out) {
  constexpr int kTerm = 124;  // four terms below 2^124: the sum below 2^126
  if (bit_width(o) > kTerm) return false;
  for (int k = 0; k < 3; ++k)
    if (bit_width(n[k]) + bit_width(y[k]) > kTerm) return false;
  out = o + n[0] * y[0] + n[1] * y[1] + n[2] * y[2];
  return true;
}

/// The canonical fraction l (sa b - sb a) / (sa - sb) (a plane crossing's coordinate: sa and sb
/// of strictly opposite signs), its numerator and denominator into num and den, when the
/// bounds hold. Reduced in two steps: by g1 = gcd(sa b - sb a, sa - sb), then by g2 = gcd(l, the
/// rest of the denominator); what is left is coprime to both factors of the numerator, so the
/// fraction is in lowest terms, as mpq_canonicalize leaves it.
inline bool crossing(i128 l, i128 sa, i128 sb, i128 a, i128 b, mpz_ptr num, mpz_ptr den) {
  if (bit_width(sa) + bit_width(b) > kProductBits || bit_width(sb) + bit_width(a) > kProductBits) return false;
  if (bit_width(sa) > 125 || bit_width(sb) > 125 || bit_width(l) > 63) return false;
  i128 p = sa * b - sb * a;
  i128 q = sa - sb;  // nonzero: opposite signs
  if (q < 0) {
    p = -p;
    q = -q;
  }
  const u128 g1 = gcd(magnitude(p), static_cast<u128>(q));
  p /= static_cast<i128>(g1);
  const u128 q1 = static_cast<u128>(q) / g1;
  const u128 g2 = gcd(magnitude(l), q1);
  const i128 l1 = l / static_cast<i128>(g2);
  set_mpz(num, p);
  mpz_mul_si(num, num, static_cast<long>(l1));  // |l1| < 2^63
  set_mpz(den, static_cast<i128>(q1 / g2));
  return true;
}

/// The canonical fraction (ao (bc - m) + bo (m - ac)) / (bc - ac) (the other coordinate where
/// edge a-b crosses the bound m: rational_points.hpp's clip_convex_2d, bc != ac), into num and
/// den, when every operand is below 2^125 (so each difference is below 2^126). Written
/// ao + x y / q with x = bo - ao, y = m - ac, q = bc - ac: gcd(ao q + x y, q) = gcd(x y, q) =
/// g1 g2 with g1 = gcd(x, q) and g2 = gcd(y, q / g1), so the lowest terms come from two
/// fixed-width gcds, and only the numerator's products (up to 252 bits) are made in GMP
/// (`t` is scratch).
inline bool cut(i128 ao, i128 bo, i128 ac, i128 bc, i128 m, mpz_ptr num, mpz_ptr den, mpz_ptr t) {
  for (i128 v : {ao, bo, ac, bc, m})
    if (bit_width(v) > 125) return false;
  i128 x = bo - ao, y = m - ac, q = bc - ac;
  if (q < 0) {
    q = -q;
    x = -x;
  }
  const u128 g1 = gcd(magnitude(x), static_cast<u128>(q));
  x /= static_cast<i128>(g1);
  const u128 q1 = static_cast<u128>(q) / g1;
  const u128 g2 = gcd(magnitude(y), q1);
  y /= static_cast<i128>(g2);
  const auto q2 = static_cast<i128>(q1 / g2);
  set_mpz(num, x);
  set_mpz(t, y);
  mpz_mul(num, num, t);  // x y / (g1 g2)
  set_mpz(den, q2);
  set_mpz(t, ao);
  mpz_addmul(num, t, den);  // + ao q / (g1 g2)
  return true;
}

}  // namespace shadow::exact::fixed
