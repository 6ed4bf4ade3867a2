// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path's union in strips (fast/strip_union.hpp, internal header) against Clipper's
// one-pass union of the same polygons: the areas agree within the rounding term the fast path
// charges to its bound for the levels the strips went through (fast/error_bound.hpp), and below
// the threshold the strips are not used at all (bit for bit the one-pass union). Seeded.
#include "fast/error_bound.hpp"
#include "fast/strip_union.hpp"

#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

namespace {

namespace CL = ClipperLib;
__extension__ typedef __int128 Int128;

Int128 area2(const CL::Paths& paths) {
  Int128 sum = 0;
  for (const CL::Path& p : paths)
    for (std::size_t a = 0; a < p.size(); ++a) {
      const CL::IntPoint& u = p[a];
      const CL::IntPoint& v = p[(a + 1) % p.size()];
      sum += static_cast<Int128>(u.X) * v.Y - static_cast<Int128>(v.X) * u.Y;
    }
  return sum;
}

double perimeter(const CL::Paths& paths) {
  double length = 0;
  for (const CL::Path& p : paths)
    for (std::size_t a = 0; a < p.size(); ++a)
      length += std::hypot(static_cast<double>(p[(a + 1) % p.size()].X - p[a].X),
                           static_cast<double>(p[(a + 1) % p.size()].Y - p[a].Y));
  return length;
}

/// Shadows of boxes under a low sun: long thin quadrilaterals along (dx, dy), scattered over a
/// square of the grid, with non-grid-aligned slopes so that the unions create rounded points.
CL::Paths long_shadows(std::size_t count, double dx, double dy, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> where(-4e8, 4e8), width(2e5, 2e6), length(5e6, 6e7), wobble(-0.2, 0.2);
  CL::Paths out;
  for (std::size_t n = 0; n < count; ++n) {
    const double x = where(rng), y = where(rng), w = width(rng), l = length(rng);
    const double ux = dx + wobble(rng), uy = dy + wobble(rng);
    const double norm = std::hypot(ux, uy);
    const double ax = ux / norm, ay = uy / norm, bx = -ay, by = ax;
    auto at = [](double v) { return static_cast<CL::cInt>(std::llround(v)); };
    out.push_back({{at(x), at(y)},
                   {at(x + w * bx), at(y + w * by)},
                   {at(x + w * bx + l * ax), at(y + w * by + l * ay)},
                   {at(x + l * ax), at(y + l * ay)}});
    if (area2({out.back()}) < 0) std::reverse(out.back().begin(), out.back().end());
  }
  return out;
}

Int128 one_pass(const CL::Paths& polygons) {
  CL::Clipper clipper;
  clipper.AddPaths(polygons, CL::ptSubject, true);
  CL::Paths out;
  clipper.Execute(CL::ctUnion, out, CL::pftNonZero, CL::pftNonZero);
  return area2(out);
}

TEST(StripUnion, AreaWithinTheRoundingOfItsLevels) {
  const shadow::fast::StripUnionOptions options{200, 32};  // small, so that the test is quick
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const double dx = seed == 3 ? 0.0 : -1.0, dy = seed == 3 ? 1.0 : -0.4 * seed;
    const CL::Paths polygons = long_shadows(3000, dx, dy, seed);
    CL::Paths strips;
    const int levels = shadow::fast::strip_union(polygons, dx, dy, strips, options);
    EXPECT_GE(levels, 2) << "seed " << seed;
    // What unite() charges: the grid's rounding is half a step per axis (rho = sqrt(2)/2 in grid
    // units) per level.
    const double rho = 0.5 * std::sqrt(2.0);
    shadow::fast::LitAreaBound bound;
    // The strips carry `levels` roundings and the one-pass union it is compared with its own.
    bound.union_rounding(perimeter(polygons), (levels + 1) * rho);
    const double allowed = bound.unshadowed(1.0);
    const double plain = 0.5 * static_cast<double>(one_pass(polygons));
    const double strip = 0.5 * static_cast<double>(area2(strips));
    EXPECT_GT(plain, 0);
    EXPECT_LE(std::abs(strip - plain), allowed) << "seed " << seed << ": plain " << plain << ", strips " << strip;
    // Not vacuous: the bound is a small fraction of the area.
    EXPECT_LT(allowed, 1e-3 * plain) << "seed " << seed;
  }
}

TEST(StripUnion, BelowTheThresholdItIsTheOnePassUnion) {
  const CL::Paths polygons = long_shadows(500, -1, -0.5, 7);
  CL::Paths strips;
  EXPECT_EQ(shadow::fast::strip_union(polygons, -1, -0.5, strips, {500, 32}), 1);
  CL::Clipper clipper;
  clipper.AddPaths(polygons, CL::ptSubject, true);
  CL::Paths plain;
  clipper.Execute(CL::ctUnion, plain, CL::pftNonZero, CL::pftNonZero);
  EXPECT_EQ(strips, plain);
}

TEST(StripUnion, DisjointPolygonsKeepTheirExactArea) {
  // Squares on a lattice, none overlapping: no intersection point to round, the areas agree
  // exactly, whatever the strips.
  CL::Paths squares;
  Int128 total = 0;
  for (int a = 0; a < 40; ++a)
    for (int b = 0; b < 40; ++b) {
      const CL::cInt x = a * 1000, y = b * 1000;
      squares.push_back({{x, y}, {x + 700, y}, {x + 700, y + 500}, {x, y + 500}});
      total += 2 * 700 * 500;
    }
  CL::Paths strips;
  EXPECT_GE(shadow::fast::strip_union(squares, 1, 1, strips, {100, 16}), 2);
  EXPECT_EQ(area2(strips), total);
  EXPECT_EQ(strips.size(), squares.size());
}

/// Sets the engine's strip-union options for one scope (internal knob), then restores them.
class EngineStrips {
 public:
  explicit EngineStrips(const shadow::fast::StripUnionOptions& options)
      : saved_(shadow::fast::engine_strip_union().options) {
    shadow::fast::engine_strip_union().options = options;
    shadow::fast::engine_strip_union().used = 0;
  }
  ~EngineStrips() { shadow::fast::engine_strip_union().options = saved_; }
  EngineStrips(const EngineStrips&) = delete;
  EngineStrips& operator=(const EngineStrips&) = delete;
  std::uint64_t used() const { return shadow::fast::engine_strip_union().used.load(); }

 private:
  shadow::fast::StripUnionOptions saved_;
};

// Inside the engine: a low threshold sends a small city's ground (and walls) under a low sun
// through the strips; its fast areas stay within their bounds of the exact ones, areas only (the
// strips' area is the shadow's) and with polygons (the strips' union stands for the casts).
TEST(StripUnion, EngineFastAreasWithinBoundsThroughTheStrips) {
  using namespace shadow;
  Scene scene = make_city(120, 110, 4);
  scene.lights.push_back(directional_light("low sun", sun_direction(6, 130)));
  scene.lights.push_back(directional_light("sun", sun_direction(30, 200)));
  validate_scene(scene);
  ShadowOptions exact_options;
  exact_options.threads = 2;
  exact_options.polygons = false;
  exact_options.planes = false;
  const ShadowResult exact = compute_shadows(scene, exact_options);
  for (const fast::StripUnionOptions& strips : {fast::StripUnionOptions{12, 4, 0}, fast::StripUnionOptions{12, 4, 2}})
    for (bool polygons : {false, true}) {
      const std::string label = std::string(polygons ? "polygons" : "areas only") + ", fan-in " +
                                std::to_string(strips.fan_in);
      const EngineStrips knob(strips);
      ShadowOptions o = exact_options;
      o.arithmetic = Arithmetic::Fast;
      o.polygons = polygons;
      o.fast_tile_casters = 0;
      const ShadowResult fast = compute_shadows(scene, o);
      EXPECT_GT(knob.used(), 10u) << label;  // the strips were reached
      ASSERT_EQ(fast.lighting.size(), exact.lighting.size());
      std::size_t shadowed = 0;
      for (std::size_t n = 0; n < fast.lighting.size(); ++n) {
        const FaceLighting& e = exact.lighting[n];
        const FaceLighting& f = fast.lighting[n];
        EXPECT_LE(std::abs(f.lit_area - e.lit_area), f.lit_area_error_bound)
            << label << ": face " << f.face_id << " light " << f.light_id;
        EXPECT_LE(f.lit_area_error_bound, 1e-5 * (1 + e.area)) << label << ": face " << f.face_id;
        shadowed += e.shadow_area > 0 ? 1 : 0;
      }
      EXPECT_GT(shadowed, 50u) << label;
    }
  EXPECT_EQ(fast::engine_strip_union().options.threshold, fast::StripUnionOptions{}.threshold);
}

}  // namespace
