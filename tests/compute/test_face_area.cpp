// SPDX-License-Identifier: GPL-3.0-or-later
// The face area the engine reports (ShadowEngine::face_area) for exactly planar faces comes from
// exact::planar_face_area (plain integers from the input doubles, exact/exact_faces.hpp,
// internal) instead of the lazy exact face: the two must be the same double on every face.
// Seeded random triangles, axis-aligned polygons and polygons in exactly representable tilted
// planes, with coordinates from 1e-12 to 1e12 and far from the origin; and analytic areas.
#include "exact/exact_faces.hpp"

#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace {

using shadow::exact::area_3d;
using shadow::exact::make_exact_face;
using shadow::exact::planar_face_area;
using shadow::exact::prepare_face;

/// The lazy route (what the engine did before): 0 for a degenerate face.
double lazy_area(const std::vector<glm::dvec3>& v) {
  const shadow::core::FacePrep prep = prepare_face(v);
  if (prep.degenerate) return 0.0;
  const shadow::exact::ExactFace f = make_exact_face(v, prep);
  return area_3d(f.chart_area, f.area_scale_squared);
}

/// Both routes on one face; returns whether the face was exactly planar (compared).
bool same_area(const std::vector<glm::dvec3>& v) {
  const shadow::core::FacePrep prep = prepare_face(v);
  if (prep.degenerate || !prep.exactly_planar) return false;
  const std::optional<double> fast = planar_face_area(v, prep);
  EXPECT_TRUE(fast.has_value());
  if (!fast) return false;
  const double reference = lazy_area(v);
  EXPECT_EQ(*fast, reference) << std::hexfloat << *fast << " against " << reference;
  // The exact chart area and area scale the engine measures receivers with (ExactWorker::
  // exact_areas): the same rationals as the lazy exact face's.
  const shadow::exact::ExactFace lazy = make_exact_face(v, prep);
  shadow::exact::FT::Exact_type chart_area, scale;
  EXPECT_TRUE(shadow::exact::planar_face_exact_areas(v, prep, chart_area, scale));
  EXPECT_EQ(chart_area, CGAL::exact(lazy.chart_area));
  EXPECT_EQ(scale, CGAL::exact(lazy.area_scale_squared));
  return true;
}

TEST(FaceArea, AnalyticAreas) {
  const shadow::core::FacePrep square = prepare_face({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  EXPECT_EQ(planar_face_area({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, square).value(), 1.0);
  const std::vector<glm::dvec3> triangle{{0, 0, 5}, {3, 0, 5}, {0, 4, 5}};
  EXPECT_EQ(planar_face_area(triangle, prepare_face(triangle)).value(), 6.0);
  // A 2 x 3 rectangle in the plane z = x (tilted 45 degrees): 6 exactly, its chart area 6 / sqrt(2).
  const std::vector<glm::dvec3> tilted{{0, 0, 0}, {0, 3, 0}, {std::sqrt(2.0), 3, std::sqrt(2.0)}, {std::sqrt(2.0), 0, std::sqrt(2.0)}};
  const shadow::core::FacePrep tp = prepare_face(tilted);
  ASSERT_TRUE(tp.exactly_planar);
  EXPECT_NEAR(planar_face_area(tilted, tp).value(), 6.0, 1e-14);
  EXPECT_EQ(planar_face_area(tilted, tp).value(), lazy_area(tilted));
  // Tiny and huge faces: scaling by powers of two scales the area exactly.
  for (int e : {-200, -40, 40, 200}) {
    std::vector<glm::dvec3> t = triangle;
    for (glm::dvec3& p : t) p = glm::dvec3(std::ldexp(p.x, e), std::ldexp(p.y, e), std::ldexp(p.z, e));
    EXPECT_EQ(planar_face_area(t, prepare_face(t)).value(), std::ldexp(6.0, 2 * e));
  }
}

// Exponents far apart within one face (subnormals beside 2^500): the power-of-two scaling's shifts
// are large here.
TEST(FaceArea, MixedExponentsInOneFace) {
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> unit(0.5, 1.0);
  std::uniform_int_distribution<int> exponent(-1074, 500), sign(0, 1);
  int compared = 0;
  for (int trial = 0; trial < 400; ++trial) {
    auto coordinate = [&] { return (sign(rng) ? 1 : -1) * std::ldexp(unit(rng), exponent(rng)); };
    std::vector<glm::dvec3> v;
    for (int a = 0; a < 3; ++a) v.push_back({coordinate(), coordinate(), coordinate()});
    if (same_area(v)) ++compared;
  }
  // A right triangle with legs 2^500 and 1 and a subnormal offset: the area 2^499 exactly.
  const double tiny = std::numeric_limits<double>::denorm_min();
  const std::vector<glm::dvec3> right{{tiny, 0, 0}, {tiny + std::ldexp(1.0, 500), 0, 0}, {tiny, 1, 0}};
  EXPECT_TRUE(same_area(right));
  EXPECT_GT(compared, 200);
}

// Faces square to an axis whose exact area lies halfway between two doubles: the area is |T|
// 2^(2e-1) for an integer T (planar_face_area's fixed-width route rounds T once), so it must round
// to even as the lazy exact face's root does. Also beside the subnormal range, where scaling a
// rounded T would round twice.
TEST(FaceArea, HalfwayAreasRoundToEven) {
  // 3 x b = 2^54 + 2, halfway between 2^54 and 2^54 + 4: to 2^54. 5 x c = 2^54 + 6: to 2^54 + 8.
  const double b = static_cast<double>(((std::uint64_t{1} << 54) + 2) / 3);
  const double c = static_cast<double>(((std::uint64_t{1} << 54) + 6) / 5);
  ASSERT_EQ(3 * static_cast<std::uint64_t>(b), (std::uint64_t{1} << 54) + 2);
  ASSERT_EQ(5 * static_cast<std::uint64_t>(c), (std::uint64_t{1} << 54) + 6);
  struct Case {
    double width, height, area;
  };
  for (const Case& k : {Case{3, b, std::ldexp(1.0, 54)}, Case{5, c, std::ldexp(1.0, 54) + 8}}) {
    for (int axis = 0; axis < 3; ++axis)
      for (int shift : {0, -30, 20}) {
        // The rectangle in the plane x_axis = 7, at an offset, scaled by 2^shift (area by 2^(2 shift)).
        auto at = [&](double u, double v) {
          glm::dvec3 p(0.0);
          p[axis] = std::ldexp(7.0, shift);
          p[(axis + 1) % 3] = std::ldexp(u + 1024, shift);
          p[(axis + 2) % 3] = std::ldexp(v, shift);
          return p;
        };
        const std::vector<glm::dvec3> rect{at(0, 0), at(k.width, 0), at(k.width, k.height), at(0, k.height)};
        const shadow::core::FacePrep prep = prepare_face(rect);
        ASSERT_TRUE(prep.exactly_planar);
        EXPECT_EQ(planar_face_area(rect, prep).value(), std::ldexp(k.area, 2 * shift))
            << "axis " << axis << " shift " << shift;
        EXPECT_TRUE(same_area(rect));
      }
  }
  // Areas below, at and just above the least normal double (2^-1072, 3 x 2^-1074, 2^-1075
  // halfway to 0, 2^-1022, 2^-1020), in the plane z = 0 so that the coordinates span a few bits
  // and take the fixed-width route: its exact scaling of |T| where the area is normal, the MPFR
  // root below.
  for (const auto& [leg, other] : {std::pair{std::ldexp(1.0, -536), std::ldexp(1.0, -536)},
                                   std::pair{std::ldexp(3.0, -537), std::ldexp(1.0, -537)},
                                   std::pair{std::ldexp(1.0, -537), std::ldexp(1.0, -538)},
                                   std::pair{std::ldexp(1.0, -511), std::ldexp(1.0, -511)},
                                   std::pair{std::ldexp(1.0, -510), std::ldexp(1.0, -510)}}) {
    const std::vector<glm::dvec3> rect{{0, 0, 0}, {leg, 0, 0}, {leg, other, 0}, {0, other, 0}};
    EXPECT_TRUE(same_area(rect)) << leg << " x " << other;
    EXPECT_EQ(planar_face_area(rect, prepare_face(rect)).value(), leg * other) << leg << " x " << other;
  }
}

// The exact areas of a face that has none (the engine falls back to the lazy exact face).
TEST(FaceArea, ExactAreasOfAZeroChartAreaAreRefused) {
  const std::vector<glm::dvec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  shadow::core::FacePrep prep = prepare_face(square);
  shadow::exact::FT::Exact_type chart_area, scale;
  ASSERT_TRUE(shadow::exact::planar_face_exact_areas(square, prep, chart_area, scale));
  EXPECT_EQ(chart_area, 1);
  EXPECT_EQ(scale, 1);
  const std::vector<glm::dvec3> zeros(4, glm::dvec3(0.0));
  EXPECT_FALSE(shadow::exact::planar_face_exact_areas(zeros, prep, chart_area, scale));
  EXPECT_EQ(chart_area, 1);  // untouched
}

// The engine reports these areas: ShadowEngine::face_area against the lazy exact face on a city.
TEST(FaceArea, EngineFaceAreasAreTheLazyOnes) {
  shadow::Scene scene = shadow::make_city(40, 80.0, 11);
  const shadow::ShadowEngine engine(scene, 2);
  for (std::size_t f = 0; f < scene.faces.size(); ++f)
    EXPECT_EQ(engine.face_area(f), lazy_area(scene.faces[f].vertices)) << "face " << f;
}

TEST(FaceArea, SameDoubleAsTheLazyExactFace) {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-40, 40), small(-4, 4), count(3, 9);
  int compared = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const double scale = std::ldexp(1.0, exponent(rng));
    const glm::dvec3 offset = glm::dvec3(unit(rng), unit(rng), unit(rng)) * std::ldexp(1.0, exponent(rng));
    std::vector<glm::dvec3> v;
    switch (trial % 4) {
      case 0:  // any triangle is exactly planar
        for (int a = 0; a < 3; ++a) v.push_back(offset + scale * glm::dvec3(unit(rng), unit(rng), unit(rng)));
        break;
      case 1: {  // a convex polygon in an axis plane
        const int n = count(rng), axis = trial % 3;
        const double c = offset[axis];
        for (int a = 0; a < n; ++a) {
          const double t = 2 * M_PI * (a + 0.3 * unit(rng)) / n;
          glm::dvec3 p = offset + scale * glm::dvec3(std::cos(t), std::sin(t), std::cos(t + 1));
          p[axis] = c;
          v.push_back(p);
        }
        break;
      }
      case 2:
      case 3: {  // z = a x + b y with small integers a, b and coordinates on a dyadic grid: exact
        const int n = count(rng);
        const double a = small(rng), b = small(rng);
        for (int k = 0; k < n; ++k) {
          const double t = 2 * M_PI * (k + 0.3 * unit(rng)) / n;
          const double x = std::ldexp(std::round(std::ldexp(std::cos(t), 20)), -20) * scale;
          const double y = std::ldexp(std::round(std::ldexp(std::sin(t), 20)), -20) * scale;
          v.push_back({x, y, a * x + b * y});
        }
        break;
      }
    }
    if (same_area(v)) ++compared;
  }
  EXPECT_GT(compared, 2500);  // nearly every face above is exactly planar and not degenerate
}

}  // namespace
