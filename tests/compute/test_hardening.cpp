// SPDX-License-Identifier: GPL-3.0-or-later
// Regression tests for the engine defects of issue 11: conservative culling of thin tilted
// receivers, simple double polygons in the fragments, and very large single faces.
#include "support/polygon_tools.hpp"
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace shadow::test {
namespace {

using L2 = std::array<long double, 2>;

/// Area of a polygon in long double (shoelace).
long double area2(const std::vector<L2>& p) {
  long double a = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const L2& u = p[k];
    const L2& v = p[(k + 1) % p.size()];
    a += u[0] * v[1] - u[1] * v[0];
  }
  return a / 2;
}

/// Convex polygon `subject` (counter-clockwise) clipped to convex counter-clockwise `clip`.
std::vector<L2> clip_convex(std::vector<L2> subject, const std::vector<L2>& clip) {
  for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const L2 a = clip[e], b = clip[(e + 1) % clip.size()];
    auto side = [&](const L2& p) { return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]); };
    std::vector<L2> out;
    for (std::size_t k = 0; k < subject.size(); ++k) {
      const L2 p = subject[k], q = subject[(k + 1) % subject.size()];
      const long double sp = side(p), sq = side(q);
      if (sp >= 0) out.push_back(p);
      if ((sp >= 0) != (sq >= 0)) {
        const long double t = sp / (sp - sq);
        out.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
      }
    }
    subject = std::move(out);
  }
  return subject;
}

// ---------------------------------------------------------------------------------------------
// Item 1: culling must never drop a caster that is exactly in front of a thin tilted receiver
// ---------------------------------------------------------------------------------------------

/// A thin tilted receiver (a needle triangle about 1 km long and under 0.5 um wide, in a random
/// orientation) and a small triangle parallel to it, h above its far end, lit straight down its
/// normal. In the receiver's own frame (t along it, y across) the shadow is the receiver triangle
/// clipped by the caster triangle: `expected` is that area, computed here in long double.
struct ThinScene {
  Scene scene;
  long double expected = 0;
  double height = 0;
};

ThinScene thin_tilted_scene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1, 1), u01(0, 1);
  glm::dvec3 e1;
  do e1 = {unit(rng), unit(rng), unit(rng)};
  while (glm::length(e1) < 0.2 || glm::length(e1) > 1);
  e1 = glm::normalize(e1);
  glm::dvec3 helper{unit(rng), unit(rng), unit(rng)};
  const glm::dvec3 e2 = glm::normalize(glm::cross(e1, glm::normalize(helper)));
  const glm::dvec3 n = glm::cross(e1, e2);
  const glm::dvec3 base{200 * unit(rng), 200 * unit(rng), 200 * unit(rng)};
  const double length = 800 + 400 * u01(rng);
  const double width = 1e-7 + 4e-7 * u01(rng);
  // Heights from 10 nm to 0.1 mm, log-uniform: far above the vertices' rounding (1e-13 m), far
  // below the plane offset error of a unit normal rounded from the thin face's edges.
  const double h = std::pow(10.0, -8 + 4 * u01(rng));
  const double t0 = (0.8 + 0.15 * u01(rng)) * length, t1 = t0 + 0.02 * length;
  const double half = 1e-3;  // the caster's half width across the receiver
  auto at = [&](double t, double y, double z) { return base + t * e1 + y * e2 + z * n; };
  ThinScene out;
  out.height = h;
  add_mesh(out.scene, "receiver", {{at(0, 0, 0), at(length, 0, 0), at(length / 2, width, 0)}});
  add_mesh(out.scene, "caster", {{at(t0, -half, h), at(t1, -half, h), at(t0, half, h)}});
  out.scene.meshes[1].receiver = false;
  out.scene.lights.push_back(directional_light("sun", n));
  // The reference in the receiver's frame: the vertices as rounded, expressed in (e1, e2).
  auto frame = [&](const glm::dvec3& p) {
    long double t = 0, y = 0;
    for (int c = 0; c < 3; ++c) {
      t += (static_cast<long double>(p[c]) - base[c]) * e1[c];
      y += (static_cast<long double>(p[c]) - base[c]) * e2[c];
    }
    return L2{t, y};
  };
  std::vector<L2> receiver, caster;
  for (const glm::dvec3& p : out.scene.faces[0].vertices) receiver.push_back(frame(p));
  for (const glm::dvec3& p : out.scene.faces[1].vertices) caster.push_back(frame(p));
  out.expected = std::abs(area2(clip_convex(receiver, caster)));
  return out;
}

TEST(CullingThinReceivers, CasterExactlyInFrontOfANeedleReceiverIsNeverCulled) {
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    ThinScene t = thin_tilted_scene(seed);
    SCOPED_TRACE("seed " + std::to_string(seed) + " height " + std::to_string(t.height));
    validate_scene(t.scene);
    for (Arithmetic arithmetic : {Arithmetic::Exact, Arithmetic::Fast}) {
      ShadowOptions options;
      options.threads = 1;
      options.polygons = false;
      options.arithmetic = arithmetic;
      const ShadowResult r = compute_shadows(t.scene, options);
      const FaceLighting* fl = r.find(0, 0);
      ASSERT_NE(fl, nullptr);
      ASSERT_TRUE(fl->faces_light);
      EXPECT_GE(r.stats.candidate_pairs, 1u);
      const double expected = static_cast<double>(t.expected);
      EXPECT_NEAR(fl->shadow_area, expected, 1e-5 * expected + fl->lit_area_error_bound)
          << (arithmetic == Arithmetic::Exact ? "exact" : "fast");
    }
  }
}


// ---------------------------------------------------------------------------------------------
// Items 5 and 13: one face with a very large number of vertices
// ---------------------------------------------------------------------------------------------

/// Validates and computes (polygons on) a scene of one face under an oblique sun.
ShadowResult one_face(const std::vector<glm::dvec3>& face, bool polygons = true) {
  Scene scene;
  add_mesh(scene, "face", {face});
  scene.lights.push_back(directional_light("sun", {0.1, 0.2, 1}));
  validate_scene(scene);
  ShadowOptions options;
  options.threads = 1;
  options.polygons = polygons;
  return compute_shadows(scene, options);
}

TEST(LargeFaces, CombWithFortyThousandVerticesIsLitWhole) {
  const std::size_t teeth = 10000;
  const ShadowResult r = one_face(comb_polygon(teeth));
  ASSERT_EQ(r.lighting.size(), 1u);
  EXPECT_EQ(r.lighting[0].area, 5.5 * teeth);
  EXPECT_EQ(r.lighting[0].lit_area, 5.5 * teeth);
  ASSERT_EQ(r.fragments.size(), 1u);
  EXPECT_EQ(r.fragments[0].polygon.size(), 4 * teeth + 3);
}

/// n points on a circle of radius 10 in the plane spanned by e1 and e2.
std::vector<glm::dvec3> circle(std::size_t n, glm::dvec3 e1, glm::dvec3 e2) {
  const double pi = 3.14159265358979323846;
  std::vector<glm::dvec3> p;
  for (std::size_t a = 0; a < n; ++a) {
    const double angle = 2 * pi * static_cast<double>(a) / static_cast<double>(n);
    p.push_back(10 * std::cos(angle) * e1 + 10 * std::sin(angle) * e2);
  }
  return p;
}

TEST(LargeFaces, CircleWithTwoHundredThousandVerticesDoesNotOverflowTheStack) {
  // The face's chart area was a running lazy sum 200,000 deep: evaluating it exactly recursed
  // through every node (SIGSEGV at about 100,000 vertices).
  const std::size_t n = 200000;
  const std::vector<glm::dvec3> p = circle(n, {1, 0, 0}, {0, 1, 0});
  long double shoelace = 0;  // the rounded vertices' own area, in long double
  for (std::size_t a = 0; a < n; ++a) {
    const glm::dvec3 &u = p[a], &v = p[(a + 1) % n];
    shoelace += static_cast<long double>(u.x) * v.y - static_cast<long double>(u.y) * v.x;
  }
  const double expected = static_cast<double>(shoelace / 2);
  const ShadowResult r = one_face(p);
  ASSERT_EQ(r.lighting.size(), 1u);
  EXPECT_NEAR(r.lighting[0].area, expected, 1e-12 * expected);
  EXPECT_EQ(r.lighting[0].lit_area, r.lighting[0].area);
  ASSERT_EQ(r.fragments.size(), 1u);
  EXPECT_EQ(r.fragments[0].area, r.lighting[0].area);
}

TEST(LargeFaces, TiltedCircleLiftedOntoItsNewellPlaneKeepsItsSumsShallow) {
  // Rotated, the rounded vertices are planar only within tolerance: the exact engine lifts them
  // with the exact Newell normal and centroid, sums over every vertex.
  const std::size_t n = 60000;
  const glm::dvec3 e1 = glm::normalize(glm::dvec3(1, 2, 3));
  const glm::dvec3 e2 = glm::normalize(glm::cross(e1, glm::dvec3(0, 0, 1)));
  const glm::dvec3 normal = glm::cross(e1, e2);
  const double expected = 0.5 * static_cast<double>(n) * 100 * std::sin(2 * 3.14159265358979323846 / n);
  const ShadowResult r = one_face(circle(n, e1, e2));
  ASSERT_EQ(r.lighting.size(), 1u);
  EXPECT_NEAR(r.lighting[0].area, expected, 1e-9 * expected);
  EXPECT_EQ(r.lighting[0].faces_light, glm::dot(normal, glm::dvec3(0.1, 0.2, 1)) > 0);
  EXPECT_EQ(r.lighting[0].shadow_area + r.lighting[0].lit_area, r.lighting[0].area);
}

// ---------------------------------------------------------------------------------------------
// Item 2: every fragment written is one simple polygon of doubles with non-zero area
// ---------------------------------------------------------------------------------------------

/// A seeded scene of boxes and tetrahedra on a ground square, everything rotated about a random
/// axis: rotated faces put shadow edges at irrational-looking slopes, and many exact cells are
/// slivers (1e-37 to 1e-14 m^2) whose vertices round onto each other.
Scene rotated_solids(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  for (int b = 0; b < 4; ++b) {
    const glm::dvec3 lo{-8 + 14 * u(rng), -8 + 14 * u(rng), 3 * u(rng)};
    add_mesh(scene, "box" + std::to_string(b), box_faces(lo, lo + glm::dvec3(0.5 + 2 * u(rng), 0.5 + 2 * u(rng), 0.5 + 3 * u(rng))));
  }
  for (int t = 0; t < 4; ++t) {
    glm::dvec3 p[4];
    const glm::dvec3 c{-8 + 16 * u(rng), -8 + 16 * u(rng), 0.5 + 3 * u(rng)};
    for (glm::dvec3& q : p) q = c + glm::dvec3(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1);
    // Outward orientation: flip when the first three see the fourth in front.
    if (glm::dot(glm::cross(p[1] - p[0], p[2] - p[0]), p[3] - p[0]) > 0) std::swap(p[1], p[2]);
    add_mesh(scene, "tet" + std::to_string(t), {{p[0], p[1], p[2]}, {p[0], p[3], p[1]}, {p[1], p[3], p[2]}, {p[2], p[3], p[0]}});
  }
  scene.lights.push_back(directional_light("sun", {0.3 * u(rng) - 0.15, 0.3 * u(rng) - 0.15, 1}));
  scene.lights.push_back(point_light("lamp", {4 * u(rng) - 2, 4 * u(rng) - 2, 9}));
  const glm::dvec3 axis{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
  return transformed(scene, 1.0, axis, 0.3 + 2 * u(rng), {0, 0, 0});
}

/// Problems of a fragment's double polygon against the output contract ("" when none).
std::string polygon_problem(const std::vector<glm::dvec3>& poly) {
  const std::size_t n = poly.size();
  if (n < 3) return "fewer than 3 vertices";
  std::vector<glm::dvec3> sorted = poly;
  std::sort(sorted.begin(), sorted.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
    return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
  });
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return "repeated vertex";
  glm::dvec3 normal(0.0);
  for (std::size_t a = 0; a < n; ++a) normal += glm::cross(poly[a] - poly[0], poly[(a + 1) % n] - poly[0]);
  const glm::dvec3 an = glm::abs(normal);
  const int k = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  // Relative to the first vertex (long double differences of nearby doubles are exact).
  std::vector<L2> chart;
  for (const glm::dvec3& v : poly)
    chart.push_back({static_cast<long double>(v[i]) - poly[0][i], static_cast<long double>(v[j]) - poly[0][j]});
  if (area2(chart) == 0) return "zero area";
  // Edges that definitely cross (long double orientations clearly of opposite signs).
  auto orient = [](const L2& a, const L2& b, const L2& c) {
    const long double d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    const long double scale = (std::abs(b[0] - a[0]) + std::abs(b[1] - a[1])) * (std::abs(c[0] - a[0]) + std::abs(c[1] - a[1]));
    return d > 1e-15L * scale ? 1 : (d < -1e-15L * scale ? -1 : 0);
  };
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 2; b < n; ++b) {
      if (a == 0 && b == n - 1) continue;  // adjacent
      const L2 &p = chart[a], &q = chart[(a + 1) % n], &r = chart[b], &s = chart[(b + 1) % n];
      const int o1 = orient(p, q, r), o2 = orient(p, q, s), o3 = orient(r, s, p), o4 = orient(r, s, q);
      if (o1 * o2 < 0 && o3 * o4 < 0) return "edges cross";
    }
  return "";
}

TEST(FragmentPolygons, RotatedBoxesAndTetrahedraWriteOnlySimpleNonDegeneratePolygons) {
  std::size_t cells = 0, dropped_entries = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    Scene scene = rotated_solids(seed);
    validate_scene(scene);
    for (Arithmetic arithmetic : {Arithmetic::Exact, Arithmetic::Fast}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + (arithmetic == Arithmetic::Exact ? " exact" : " fast"));
      ShadowOptions options;
      options.threads = 2;
      options.arithmetic = arithmetic;
      const ShadowResult r = compute_shadows(scene, options);
      std::vector<double> sum(r.lighting.size(), 0.0);
      for (const Fragment& f : r.fragments) {
        ++cells;
        const std::string problem = polygon_problem(f.polygon);
        EXPECT_EQ(problem, "") << "face " << f.face_id << " light " << f.light_id << " fragment " << f.fragment_id << " area " << f.area << " first " << f.polygon[0].x << " " << f.polygon[0].y << " " << f.polygon[0].z << " n " << f.polygon.size();
        EXPECT_GT(f.area, 0.0);
        for (std::size_t e = 0; e < r.lighting.size(); ++e)
          if (r.lighting[e].face_id == f.face_id && r.lighting[e].light_id == f.light_id) sum[e] += f.area;
      }
      for (std::size_t e = 0; e < r.lighting.size(); ++e) {
        const FaceLighting& fl = r.lighting[e];
        if (fl.dropped_area > 0) ++dropped_entries;
        // Dropped cells are slivers: their area is far below the face's (bound: docs).
        EXPECT_LE(fl.dropped_area, 1e-9 * fl.area);
        EXPECT_NEAR(sum[e] + fl.dropped_area, fl.area, 1e-9 * fl.area + fl.lit_area_error_bound);
      }
    }
  }
  EXPECT_GT(cells, 500u);
  RecordProperty("entries_with_dropped_cells", static_cast<int>(dropped_entries));
}

TEST(FragmentPolygons, ASliverFaceWhollyLitOrInShadowIsWrittenOnlyAsValidPolygons) {
  // A triangle of exact area 2^-53 m^2 whose shoelace in doubles cannot be told from zero:
  // written whole it would break the contract, so it goes the way of any other broken cell.
  Scene scene;
  add_mesh(scene, "sliver", {{{0, 0, 0}, {1, 1, 0}, {2, 2 + std::ldexp(1.0, -51), 0}}});
  add_mesh(scene, "square", {rectangle_z(5, 5, 6, 6, 0)});
  scene.lights.push_back(directional_light("sun", {0.2, 0.1, 1}));   // both lit whole
  scene.lights.push_back(directional_light("under", {0.2, 0.1, -1}));  // both in attached shadow
  validate_scene(scene);
  ASSERT_FALSE(scene.faces[0].degenerate);
  for (Arithmetic arithmetic : {Arithmetic::Exact, Arithmetic::Fast}) {
    SCOPED_TRACE(arithmetic == Arithmetic::Exact ? "exact" : "fast");
    ShadowOptions options;
    options.arithmetic = arithmetic;
    const ShadowResult r = compute_shadows(scene, options);
    for (const Fragment& f : r.fragments) EXPECT_EQ(polygon_problem(f.polygon), "") << "face " << f.face_id;
    for (const FaceLighting& fl : r.lighting) {
      double written = 0;
      for (const Fragment& f : r.fragments)
        if (f.face_id == fl.face_id && f.light_id == fl.light_id) written += f.area;
      EXPECT_EQ(written + fl.dropped_area, fl.area) << "face " << fl.face_id << " light " << fl.light_id;
    }
    EXPECT_EQ(r.find(0, 0)->lit_area, std::ldexp(1.0, -52));
    // The sliver cannot be written: its whole area is accounted as dropped, lit or not.
    EXPECT_EQ(r.find(0, 0)->dropped_area, std::ldexp(1.0, -52));
    EXPECT_EQ(r.find(0, 1)->dropped_area, std::ldexp(1.0, -52));
    EXPECT_EQ(r.find(1, 0)->dropped_area, 0.0);
  }
}

TEST(CullingThinReceivers, AReceiverWithoutANormalInDoublesKeepsItsCasters) {
  // A sliver whose exact area (4.6e-15 m^2) rounds to zero in doubles has no culling normal: the
  // light-space grid's depth cut once lifted its chart corners with that normal, got NaN, and
  // left out every caster, so the sliver under a roof read as lit whole. The cut now takes the
  // receiver's own vertices, which need no normal.
  Scene scene;
  add_mesh(scene, "sliver", {{{0, 0, 0}, {1.7638479564302947, 8.519489903165045, 0}, {3.940988363159399, 19.03520677393165, 0}}});
  add_mesh(scene, "roof", {rectangle_z(-5, -5, 10, 25, 5)});
  scene.lights.push_back(directional_light("sun", {0, 0, 1}));
  scene.lights.push_back(directional_light("low sun", {0.3, 0.2, 1}));
  validate_scene(scene);
  ASSERT_FALSE(scene.faces[0].degenerate);
  for (Arithmetic arithmetic : {Arithmetic::Exact, Arithmetic::Fast}) {
    SCOPED_TRACE(arithmetic == Arithmetic::Exact ? "exact" : "fast");
    ShadowOptions options;
    options.arithmetic = arithmetic;
    options.polygons = false;
    const ShadowResult r = compute_shadows(scene, options);
    for (std::size_t light = 0; light < 2; ++light) {
      const FaceLighting* sliver = r.find(0, light);
      ASSERT_NE(sliver, nullptr);
      EXPECT_TRUE(sliver->faces_light) << "light " << light;
      EXPECT_EQ(sliver->lit_fraction, 0.0) << "light " << light;
    }
  }
}

TEST(LargeFaces, CombOverAGroundCastsItsExactAreaAndTheGroundsCellsTileIt) {
  // The ground's lit region is a box with one comb-shaped hole of 8,000 vertices: its cells
  // come from a triangulation of that region (it used to take minutes).
  const std::size_t teeth = 2000;
  const std::vector<glm::dvec3> raised = comb_polygon(teeth, 1);
  const double t = static_cast<double>(teeth);
  Scene scene;
  add_mesh(scene, "ground", {{{-5, -5, 0}, {t + 5, -5, 0}, {t + 5, 15, 0}, {-5, 15, 0}}});
  add_mesh(scene, "comb", {raised});
  scene.lights.push_back(directional_light("sun", {0.1, 0.2, 1}));
  validate_scene(scene);
  ShadowOptions options;
  options.threads = 2;
  const ShadowResult r = compute_shadows(scene, options);
  const FaceLighting* ground = r.find(0, 0);
  ASSERT_NE(ground, nullptr);
  EXPECT_EQ(ground->area, (t + 10) * 20);
  EXPECT_EQ(ground->shadow_area, 5.5 * t);  // a translated copy of the comb, all on the ground
  double lit = 0, shadowed = 0;
  std::size_t cells = 0;
  for (const Fragment& f : r.fragments) {
    if (f.face_id != 0) continue;
    ++cells;
    EXPECT_EQ(polygon_problem(f.polygon), "");
    (f.lit ? lit : shadowed) += f.area;
  }
  EXPECT_GT(cells, 2u);
  EXPECT_NEAR(lit + ground->dropped_area, ground->lit_area, 1e-9 * ground->area);
  EXPECT_NEAR(shadowed, ground->shadow_area, 1e-9 * ground->area);
}

TEST(LargeFaces, CombWhoseShadowLeavesTheGroundIsCutToIt) {
  // A non-convex caster wholly in front casts its whole outline only when that stays inside the
  // receiver's chart box; this comb's shadow leaves the ground, so it casts piece by piece, each
  // clipped to the box. Dyadic numbers: the expected area is exact in doubles.
  const std::size_t teeth = 2000;
  const std::vector<glm::dvec3> raised = comb_polygon(teeth, 1);
  Scene scene;
  add_mesh(scene, "ground", {{{-5, -5, 0}, {1000.25, -5, 0}, {1000.25, 15, 0}, {-5, 15, 0}}});
  add_mesh(scene, "comb", {raised});
  scene.lights.push_back(directional_light("sun", {0.125, 0.25, 1}));  // shadow shifted by (-1/8, -1/4)
  validate_scene(scene);
  for (bool polygons : {false, true}) {
    ShadowOptions options;
    options.threads = 2;
    options.polygons = polygons;
    const ShadowResult r = compute_shadows(scene, options);
    const FaceLighting* ground = r.find(0, 0);
    ASSERT_NE(ground, nullptr);
    // The spine from x = -1/8 to the ground's edge, and the 1,000 teeth left of it (the edge at
    // 1000.25 falls in the gap between teeth 1000 and 1001).
    EXPECT_EQ(ground->shadow_area, 1000.375 * 1 + 1000 * 0.5 * 9);
    if (!polygons) continue;
    double shadowed = 0;
    for (const Fragment& f : r.fragments)
      if (f.face_id == 0 && !f.lit) {
        EXPECT_EQ(polygon_problem(f.polygon), "");
        shadowed += f.area;
      }
    EXPECT_NEAR(shadowed, ground->shadow_area, 1e-9 * ground->area);
  }
}

TEST(LargeFaces, CombUnderALampCastsItsScaledOutlineOnAndOffTheGround) {
  // A point lamp 2 m up over a comb 1 m up: the comb's shadow is the comb scaled by 2 about the
  // lamp's foot (1000, 5), area 4 x 5.5 x teeth. On a ground that holds it all, and on one whose
  // edge x = 2000.5 is the image of x = 1500.25, in the gap between teeth 1500 and 1501 (then the
  // spine up to 1500.25 and 1,500 teeth of 0.5 x 9). Dyadic numbers: the areas are exact in
  // doubles. Areas only and with polygons (whose shadowed fragments add up to the same).
  const std::size_t teeth = 2000;
  const double whole = 4 * 5.5 * static_cast<double>(teeth), cut = 4 * (1500.25 + 1500 * 4.5);
  for (const auto& [x1, expected] : {std::pair{3001.0, whole}, std::pair{2000.5, cut}}) {
    Scene scene;
    add_mesh(scene, "ground", {rectangle_z(-1001, -6, x1, 16, 0)});
    add_mesh(scene, "comb", {comb_polygon(teeth, 1)});
    scene.lights.push_back(point_light("lamp", {1000, 5, 2}));
    validate_scene(scene);
    for (bool polygons : {false, true}) {
      ShadowOptions options;
      options.threads = 2;
      options.polygons = polygons;
      const ShadowResult r = compute_shadows(scene, options);
      const FaceLighting* ground = r.find(0, 0);
      ASSERT_NE(ground, nullptr);
      EXPECT_EQ(ground->shadow_area, expected) << "ground to x = " << x1 << (polygons ? ", polygons" : "");
      EXPECT_EQ(ground->lit_area, ground->area - expected);
      if (!polygons) continue;
      double shadowed = 0;
      for (const Fragment& f : r.fragments)
        if (f.face_id == 0 && !f.lit) {
          EXPECT_EQ(polygon_problem(f.polygon), "");
          shadowed += f.area;
        }
      EXPECT_NEAR(shadowed, expected, 1e-9 * ground->area);
    }
  }
}

}  // namespace
}  // namespace shadow::test
