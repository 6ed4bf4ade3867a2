// SPDX-License-Identifier: GPL-3.0-or-later
// Points keyed and hashed by their exact coordinates, for the tables that number a scene's
// vertices (validation's edge grouping, the convex-solid search): equal points by == get equal
// keys and hashes, -0.0 counting as 0.0. Doubles only.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace shadow::geometry {

/// A 64-bit mix (the finaliser of MurmurHash3's 64-bit variant, a well-known constant choice).
inline std::uint64_t mix64(std::uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return h;
}

/// A coordinate's bits, -0.0 folded into 0.0: equal for coordinates that == compares equal
/// (NaN aside).
inline std::uint64_t coordinate_bits(double x) {
  x += 0.0;
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

/// A point's exact coordinates as a key: equal keys for points that == compares equal.
using PointKey = std::array<std::uint64_t, 3>;

inline PointKey point_key(const glm::dvec3& v) { return {coordinate_bits(v.x), coordinate_bits(v.y), coordinate_bits(v.z)}; }

/// The hash of a point's key: the coordinates' bits mixed in one after the other.
inline std::uint64_t point_key_hash(const PointKey& key) {
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (const std::uint64_t bits : key) h = mix64(h ^ bits);
  return h;
}

/// The hash of a point's coordinates (point_key_hash of its point_key).
inline std::uint64_t point_hash(const glm::dvec3& v) { return point_key_hash(point_key(v)); }

/// point_key_hash as a hasher for standard containers.
struct PointKeyHash {
  std::size_t operator()(const PointKey& key) const { return static_cast<std::size_t>(point_key_hash(key)); }
};

}  // namespace shadow::geometry
