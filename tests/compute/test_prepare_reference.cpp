// SPDX-License-Identifier: GPL-3.0-or-later
// The fast preparation steps against the implementations they replaced, kept as references:
// classify_face_shape (Epick predicates and an interval normal) against classify_face_shape_exact
// (all lazy exact), validate_scene (per-face checks in parallel) against validate_scene_reference
// (serial), and find_convex_solids against find_convex_solids_reference. Each pair must agree
// exactly: same classes, same scene changes, warnings and first error, same solids in the same order.
#include "core/culling.hpp"
#include "runtime/parallel.hpp"
#include "exact/convex_solids.hpp"
#include "exact/exact_faces.hpp"
#include "exact/face_shape.hpp"
#include "geometry/point_hash.hpp"
#include "validation/validate_reference.hpp"
#include "support/scene_builders.hpp"

#include <shadow/generators.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/testing/generators.hpp>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <map>
#include <array>
#include <set>
#include <stdexcept>
#include <tuple>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using shadow::detail::FaceShape;
using Polygon = std::vector<glm::dvec3>;

/// The classifier's precondition: no consecutive duplicates (the last vertex repeating the first
/// included); at least 3 vertices.
bool tidy(Polygon& p) {
  p.erase(std::unique(p.begin(), p.end()), p.end());
  while (p.size() > 1 && p.back() == p.front()) p.pop_back();
  return p.size() >= 3;
}

/// Seeded faces of every kind the classifier must decide: random polygons on small integer
/// grids (collinear runs, repeated vertices, crossings), lifted into planes of every tilt
/// (axis-aligned, 45 degrees: ties between normal components), bow-ties and symmetric bow-ties
/// (zero Newell normal), slivers one ulp off a line, nearly coplanar vertices, and all of that
/// scaled to huge (2^450) and tiny (2^-1000, subnormal products) coordinates or moved far from
/// the origin.
class FaceMaker {
 public:
  explicit FaceMaker(std::uint64_t seed) : rng_(seed) {}

  Polygon next() {
    Polygon p;
    switch (pick(0, 7)) {
      case 0: p = grid_polygon(); break;
      case 1: p = collinear(); break;
      case 2: p = bow_tie(); break;
      case 3: p = sliver(); break;
      case 4: p = nearly_coplanar(); break;
      case 5: p = regular_like(); break;
      case 6: p = diagonal_plane(); break;
      default: p = grid_polygon(); break;
    }
    transform(p);
    return p;
  }

 private:
  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }

  /// 2D points -> 3D on a random plane: one of the axis planes, or tilted with small integer
  /// slopes (exactly planar), vertices in either order.
  Polygon lift(const std::vector<std::array<double, 2>>& q) {
    Polygon p;
    const int axis = pick(0, 2);
    const double a = pick(-2, 2), b = pick(-2, 2), c = pick(-3, 3);
    const bool flat = pick(0, 2) == 0;
    for (const auto& [x, y] : q) {
      const double h = flat ? c : a * x + b * y + c;
      glm::dvec3 v;
      v[axis] = h;
      v[(axis + 1) % 3] = x;
      v[(axis + 2) % 3] = y;
      p.push_back(v);
    }
    if (pick(0, 1)) std::reverse(p.begin(), p.end());
    return p;
  }

  Polygon grid_polygon() {
    const int n = pick(3, 9), size = pick(1, 4);
    std::vector<std::array<double, 2>> q;
    for (int i = 0; i < n; ++i) q.push_back({double(pick(0, size)), double(pick(0, size))});
    return lift(q);
  }

  Polygon collinear() {
    const int n = pick(3, 6);
    const glm::dvec3 o(pick(-5, 5), pick(-5, 5), pick(-5, 5)), d(pick(-3, 3), pick(-3, 3), pick(-3, 3));
    Polygon p;
    for (int i = 0; i < n; ++i) p.push_back(o + double(pick(-4, 4)) * d);
    return p;
  }

  Polygon bow_tie() {
    const double s = pick(1, 5), t = pick(0, 1) ? s : pick(1, 5);  // s == t: symmetric, zero normal
    std::vector<std::array<double, 2>> q{{0, 0}, {s, t}, {s, 0}, {0, t}};
    if (pick(0, 2) == 0) q = {{0, 0}, {2 * s, 0}, {0, t}, {2 * s, t}};  // crossing the other way
    return lift(q);
  }

  Polygon sliver() {
    // A triangle (or quad) whose apex is one ulp off the line through the base, or on it.
    const double x = uniform(-10, 10), y = uniform(-10, 10);
    const double dx = uniform(-10, 10), dy = uniform(-10, 10);
    double mx = x + dx / 2, my = y + dy / 2;
    const int nudge = pick(-1, 1);
    if (nudge > 0) my = std::nextafter(my, 1e300);
    if (nudge < 0) mx = std::nextafter(mx, -1e300);
    std::vector<std::array<double, 2>> q{{x, y}, {x + dx, y + dy}, {mx, my}};
    if (pick(0, 1)) q.push_back({x + dx / 3, y + dy / 3 + (pick(0, 1) ? 0.0 : 1e-12)});
    return lift(q);
  }

  Polygon nearly_coplanar() {
    Polygon p = grid_polygon();
    for (glm::dvec3& v : p)
      for (int c = 0; c < 3; ++c)
        if (pick(0, 3) == 0) v[c] = std::nextafter(v[c], pick(0, 1) ? 1e300 : -1e300);
    return p;
  }

  Polygon regular_like() {
    // A star or convex polygon of 5 to 12 vertices with random radii, in a random tilted plane.
    const int n = pick(5, 12);
    const bool star = pick(0, 1);
    const glm::dvec3 u = glm::dvec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    const glm::dvec3 w = glm::dvec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    Polygon p;
    for (int i = 0; i < n; ++i) {
      const double angle = 2 * M_PI * i * (star ? 2 : 1) / n;
      const double r = uniform(0.5, 2);
      p.push_back(r * std::cos(angle) * u + r * std::sin(angle) * w);
    }
    return p;
  }

  Polygon diagonal_plane() {
    // Planes x = y, x = z or y = z and x + y + z = c: equal normal components (ties).
    const int n = pick(3, 6);
    Polygon p;
    const int kind = pick(0, 3);
    for (int i = 0; i < n; ++i) {
      const double a = pick(-3, 3), b = pick(-3, 3);
      switch (kind) {
        case 0: p.push_back({a, a, b}); break;
        case 1: p.push_back({a, b, a}); break;
        case 2: p.push_back({b, a, a}); break;
        default: p.push_back({a, b, 6 - a - b}); break;
      }
    }
    return p;
  }

  /// Scales (exactly, by powers of two) to huge or tiny coordinates, or moves far off.
  void transform(Polygon& p) {
    switch (pick(0, 6)) {
      case 0:
        for (glm::dvec3& v : p) v *= std::ldexp(1.0, 450);
        break;
      case 1:
        for (glm::dvec3& v : p) v *= std::ldexp(1.0, -1000);
        break;
      case 2: {
        const glm::dvec3 off(pick(-1, 1) * 1e8, pick(-1, 1) * 1e8, pick(-1, 1) * 1e7);
        for (glm::dvec3& v : p) v += off;
        break;
      }
      case 3:
        for (glm::dvec3& v : p) v *= std::ldexp(1.0, pick(-60, 60));
        break;
      default:
        break;
    }
  }

  std::mt19937_64 rng_;
};

TEST(ClassifyFaceShape, SameAsTheExactReferenceOnSeededFaces) {
  FaceMaker maker(20261126);
  std::array<int, 3> seen{0, 0, 0};
  int checked = 0;
  while (checked < 60000) {
    Polygon p = maker.next();
    if (!tidy(p)) continue;
    ++checked;
    const FaceShape fast = shadow::detail::classify_face_shape(p);
    const FaceShape exact = shadow::detail::classify_face_shape_exact(p);
    ++seen[static_cast<int>(exact)];
    if (fast != exact) {
      std::string text;
      for (const glm::dvec3& v : p) text += "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ") ";
      ADD_FAILURE() << "face " << checked << ": " << text << "fast " << int(fast) << ", exact " << int(exact);
      break;
    }
  }
  // Every class comes up often: the comparison covers each decision.
  for (int count : seen) EXPECT_GT(count, 3000);
}

TEST(ClassifyFaceShape, KnownAnswers) {
  using shadow::detail::classify_face_shape;
  EXPECT_EQ(classify_face_shape({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}), FaceShape::Simple);
  EXPECT_EQ(classify_face_shape({{0, 0, 0}, {1, 1, 1}, {3, 3, 3}}), FaceShape::ZeroArea);
  // Symmetric bow-tie: the exact Newell normal is zero.
  EXPECT_EQ(classify_face_shape({{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}), FaceShape::SelfIntersecting);
  // Asymmetric bow-tie: a non-zero normal, a crossing boundary.
  EXPECT_EQ(classify_face_shape({{0, 0, 0}, {2, 1, 0}, {2, 0, 0}, {0, 3, 0}}), FaceShape::SelfIntersecting);
  // Tiny (subnormal products) and huge coordinates.
  const double tiny = std::ldexp(1.0, -1000), huge = std::ldexp(1.0, 480);
  EXPECT_EQ(classify_face_shape({{0, 0, 0}, {tiny, 0, 0}, {0, tiny, tiny}}), FaceShape::Simple);
  EXPECT_EQ(classify_face_shape({{huge, 0, 0}, {0, huge, 0}, {0, 0, huge}}), FaceShape::Simple);
}

std::string outcome_of(shadow::Scene& scene, const shadow::LoadOptions& options, bool reference) {
  try {
    if (reference)
      shadow::detail::validate_scene_reference(scene, options);
    else
      shadow::validate_scene(scene, options);
  } catch (const shadow::InputError& e) {
    return std::string("error: ") + e.what();
  }
  std::string text;
  for (const shadow::Warning& w : scene.warnings) text += w.to_string() + "\n";
  return text;
}

/// A city with bad faces put in at seeded places: zero-area faces (warnings), and, when
/// `errors`, a bow-tie, a non-planar face, a two-vertex face; plus consecutive duplicates.
shadow::Scene city_with_defects(std::uint64_t seed, bool errors) {
  shadow::Scene scene = shadow::make_city(400, 200, seed);
  std::mt19937_64 rng(seed);
  auto at = [&] { return std::uniform_int_distribution<std::size_t>(1, scene.faces.size() - 1)(rng); };
  for (int i = 0; i < 5; ++i) scene.faces[at()].vertices = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  for (int i = 0; i < 5; ++i) {
    std::vector<glm::dvec3>& v = scene.faces[at()].vertices;
    v.insert(v.begin() + 1, v[1]);
  }
  // Closed parts turned inward (a whole box reversed) and made inconsistent (one face reversed):
  // warnings whose order and "first part" follow the part search's union-find roots.
  const std::size_t boxes = (scene.faces.size() - 1) / 6;
  auto box = [&] { return 1 + 6 * std::uniform_int_distribution<std::size_t>(0, boxes - 1)(rng); };
  for (int i = 0; i < 8; ++i) {
    const std::size_t first = box();
    for (std::size_t f = first; f < first + 6; ++f) std::reverse(scene.faces[f].vertices.begin(), scene.faces[f].vertices.end());
  }
  for (int i = 0; i < 8; ++i) {
    std::vector<glm::dvec3>& v = scene.faces[box() + 2].vertices;
    std::reverse(v.begin(), v.end());
  }
  // The buildings' faces shuffled: the boxes' faces interleave, so the order in which closed parts
  // are visited (by union-find root) is not simply box order.
  std::shuffle(scene.faces.begin() + 1, scene.faces.end(), rng);
  if (errors) {
    scene.faces[at()].vertices = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 2, 0}};
    scene.faces[at()].vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5}, {0, 1, 0}};
    scene.faces[at()].vertices = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  }
  return scene;
}

TEST(ValidateScene, SameOutcomeAsTheSerialReference) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
    for (bool errors : {false, true})
      for (unsigned threads : {1u, 2u, 3u, 8u}) {
        shadow::Scene a = city_with_defects(seed, errors), b = a;
        shadow::LoadOptions options;
        options.threads = threads;
        options.orient_outward = seed % 2 == 0;
        const std::string fast = outcome_of(a, options, false), reference = outcome_of(b, options, true);
        EXPECT_EQ(fast, reference) << "seed " << seed << ", threads " << threads;
        EXPECT_EQ(fast.rfind("error: ", 0) == 0, errors);
        if (!errors) {
          EXPECT_NE(fast.find("zero area"), std::string::npos);
          EXPECT_NE(fast.find(options.orient_outward ? "orient outward" : "inconsistent face orientation"), std::string::npos);
        }
        if (!errors) {
          ASSERT_EQ(a.faces.size(), b.faces.size());
          for (std::size_t f = 0; f < a.faces.size(); ++f) {
            EXPECT_EQ(a.faces[f].vertices, b.faces[f].vertices);
            EXPECT_EQ(a.faces[f].degenerate, b.faces[f].degenerate);
          }
        }
      }
}

/// Scenes for the orientation check alone, seeded: a large city mesh ("buildings": a million-face
/// city scaled down to `boxes` boxes in one mesh, its faces shuffled, so that closed parts
/// interleave) with boxes turned inward, faces reversed and zeros of either sign (-0.0 == 0.0
/// must join edges); a second large mesh of boxes in a row, some inward; and small meshes (a box
/// each: outward, inward, one face reversed, open, an edge used three times). Validated with
/// orient outward off (which leaves the faces as they are).
shadow::Scene orientation_scene(std::uint64_t seed, std::size_t boxes) {
  shadow::Scene scene = shadow::make_city(boxes, 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0), seed);
  std::mt19937_64 rng(seed);
  const shadow::Mesh buildings = scene.meshes.back();
  const std::size_t count = buildings.face_count / 6;
  auto box = [&] { return buildings.first_face + 6 * std::uniform_int_distribution<std::size_t>(0, count - 1)(rng); };
  auto reverse = [&](std::size_t f) { std::reverse(scene.faces[f].vertices.begin(), scene.faces[f].vertices.end()); };
  for (int i = 0; i < 12; ++i) {
    const std::size_t first = box();
    for (std::size_t f = first; f < first + 6; ++f) reverse(f);
  }
  for (int i = 0; i < 12; ++i) reverse(box() + std::uniform_int_distribution<std::size_t>(0, 5)(rng));
  for (std::size_t f = buildings.first_face; f < buildings.first_face + buildings.face_count; ++f)
    for (glm::dvec3& v : scene.faces[f].vertices)
      if (v.z == 0 && rng() % 2 == 0) v.z = -0.0;
  std::shuffle(scene.faces.begin() + static_cast<std::ptrdiff_t>(buildings.first_face),
               scene.faces.begin() + static_cast<std::ptrdiff_t>(buildings.first_face + buildings.face_count), rng);
  std::vector<Polygon> row;
  for (int b = 0; b < 800; ++b) {
    std::vector<Polygon> faces = shadow::box_faces({5000.0 + 3 * b, 0, 0}, {5001.0 + 3 * b, 1, 2});
    if (b % 97 == 5)
      for (Polygon& f : faces) std::reverse(f.begin(), f.end());
    row.insert(row.end(), faces.begin(), faces.end());
  }
  shadow::add_mesh(scene, "row", row);
  for (int m = 0; m < 40; ++m) {
    std::vector<Polygon> faces = shadow::box_faces({-1000.0 - 3 * m, 0, 0}, {-999.0 - 3 * m, 1, 1});
    switch (m % 5) {
      case 1:
        for (Polygon& f : faces) std::reverse(f.begin(), f.end());
        break;
      case 2:
        std::reverse(faces[m % 6].begin(), faces[m % 6].end());
        break;
      case 3:
        faces.pop_back();
        break;
      case 4:
        faces.push_back(faces[0]);
        break;
      default:
        break;
    }
    shadow::add_mesh(scene, "box" + std::to_string(m), faces);
  }
  shadow::validate_scene(scene);
  return scene;
}

std::vector<std::string> texts(const std::vector<shadow::Warning>& warnings) {
  std::vector<std::string> out;
  for (const shadow::Warning& w : warnings) out.push_back(w.to_string());
  return out;
}

TEST(Orientation, ParallelCheckEqualsTheSerialReference) {
  for (std::uint64_t seed : {3u, 4u})
    for (bool orient : {false, true}) {
      const shadow::Scene base = orientation_scene(seed, 1500);
      ASSERT_GE(base.meshes[1].face_count, 9000u);
      shadow::LoadOptions options;
      options.orient_outward = orient;
      shadow::Scene reference = base;
      const std::vector<std::string> expected = texts(shadow::detail::check_mesh_orientation(reference, options, true));
      // Something to find in each kind of mesh: the buildings, the row, the small boxes.
      for (const char* mesh : {"mesh \"buildings\"", "mesh \"row\"", "mesh \"box1\"", "mesh \"box2\""})
        EXPECT_TRUE(std::any_of(expected.begin(), expected.end(),
                                [&](const std::string& w) { return w.find(mesh) != std::string::npos; }))
            << mesh;
      std::size_t changed = 0;
      for (std::size_t f = 0; f < base.faces.size(); ++f) changed += reference.faces[f].vertices != base.faces[f].vertices;
      if (orient)
        EXPECT_GT(changed, 12u * 6);
      else
        EXPECT_EQ(changed, 0u);
      for (unsigned threads : {1u, 2u, 3u, 8u}) {
        shadow::Scene scene = base;
        options.threads = threads;
        EXPECT_EQ(texts(shadow::detail::check_mesh_orientation(scene, options, false)), expected)
            << "seed " << seed << ", orient " << orient << ", threads " << threads;
        for (std::size_t f = 0; f < scene.faces.size(); ++f)
          ASSERT_EQ(scene.faces[f].vertices, reference.faces[f].vertices) << "face " << f << ", threads " << threads;
      }
    }
}

TEST(ValidateScene, ThreadCountAboveTheLimitIsAnInputError) {
  shadow::Scene scene = shadow::make_city(2, 20, 1);
  shadow::LoadOptions options;
  options.threads = 100000;
  EXPECT_THROW(shadow::validate_scene(scene, options), shadow::InputError);
}

void expect_same_solids(const shadow::Scene& scene, unsigned threads) {
  std::vector<shadow::core::FacePrep> prep(scene.faces.size());
  for (std::size_t f = 0; f < prep.size(); ++f) {
    if (scene.faces[f].degenerate || scene.faces[f].vertices.size() < 3)
      prep[f].degenerate = true;
    else
      prep[f] = shadow::exact::prepare_face(scene.faces[f].vertices);
  }
  std::vector<int> of, ref_of;
  const std::vector<shadow::core::ConvexSolid> solids = shadow::exact::find_convex_solids(scene, prep, of, threads);
  const std::vector<shadow::core::ConvexSolid> ref = shadow::exact::find_convex_solids_reference(scene, prep, ref_of);
  ASSERT_EQ(solids.size(), ref.size());
  EXPECT_EQ(of, ref_of);
  for (std::size_t s = 0; s < solids.size(); ++s) {
    EXPECT_EQ(solids[s].vertices, ref[s].vertices) << "solid " << s;
    EXPECT_EQ(solids[s].edges, ref[s].edges) << "solid " << s;
  }
}

TEST(FindConvexSolids, SameAsTheReferenceOnGeneratedScenes) {
  for (unsigned threads : {1u, 2u, 5u}) {
    shadow::Scene city = shadow::make_city(3000, 600, 2026);  // overlapping and touching boxes
    shadow::validate_scene(city);
    expect_same_solids(city, threads);
    // Faces shuffled within the mesh: the solids' order (by union-find root) is not box order.
    std::mt19937_64 rng(threads);
    std::shuffle(city.faces.begin() + 1, city.faces.end(), rng);
    expect_same_solids(city, threads);
    shadow::Scene spheres = shadow::make_sphere_field(40, 60, 7);
    shadow::validate_scene(spheres);
    expect_same_solids(spheres, threads);
    shadow::Scene room = shadow::make_furnished_room(6, 3);
    shadow::validate_scene(room);
    expect_same_solids(room, threads);
  }
}

TEST(FindConvexSolids, SharedEdgesAcrossMeshesAndOpenParts) {
  // Two meshes with the same box (each its own solid), a box missing its lid (open), a box
  // whose one face is reversed (not oppositely shared), and a non-convex closed L-prism built
  // from boxes' faces sharing vertices with the others.
  shadow::Scene scene;
  shadow::add_mesh(scene, "a", shadow::box_faces({0, 0, 0}, {1, 1, 1}));
  shadow::add_mesh(scene, "b", shadow::box_faces({0, 0, 0}, {1, 1, 1}));
  std::vector<shadow::Polygon3> lidless = shadow::box_faces({1, 0, 0}, {2, 1, 1});
  lidless.pop_back();
  shadow::add_mesh(scene, "c", lidless);
  std::vector<shadow::Polygon3> reversed = shadow::box_faces({0, 1, 0}, {1, 2, 1});
  std::reverse(reversed[2].begin(), reversed[2].end());
  std::vector<shadow::Polygon3> both = shadow::box_faces({3, 0, 0}, {4, 1, 1});
  for (const shadow::Polygon3& f : shadow::box_faces({4, 0, 0}, {5, 1, 2})) both.push_back(f);
  for (const shadow::Polygon3& f : reversed) both.push_back(f);
  shadow::add_mesh(scene, "d", both);
  for (unsigned threads : {1u, 3u}) expect_same_solids(scene, threads);
}

std::vector<signed char> closed_outward_of(const shadow::Scene& scene, unsigned threads) {
  std::vector<shadow::core::FacePrep> prep(scene.faces.size());
  for (std::size_t f = 0; f < prep.size(); ++f) prep[f] = shadow::exact::prepare_face(scene.faces[f].vertices);
  std::vector<int> of;
  std::vector<signed char> outward;
  shadow::exact::find_convex_solids(scene, prep, of, threads, &outward);
  return outward;
}

TEST(FindConvexSolids, ClosedSolidsThatAreNotConvexAreToldWithTheirOrientation) {
  using shadow::test::l_prism_triangles;
  std::vector<Polygon> closed = l_prism_triangles({0, 0, 0}, 4, true, true), inward = closed,
                       no_floor = l_prism_triangles({0, 0, 0}, 4, false, true),
                       no_roof = l_prism_triangles({0, 0, 0}, 4, true, false), pierced = closed,
                       sloped = l_prism_triangles({0, 0, 0}, 4, false, true);
  for (Polygon& f : inward) std::reverse(f.begin(), f.end());
  // A roof corner pushed below the floor: still every edge used twice, but the surface crosses
  // itself.
  for (Polygon& f : pierced)
    for (glm::dvec3& v : f)
      if (v == glm::dvec3(6, 3, 4)) v = glm::dvec3(6, 3, -2);
  // A border that is not horizontal: one bottom corner lifted.
  for (Polygon& f : sloped)
    for (glm::dvec3& v : f)
      if (v == glm::dvec3(0, 0, 0)) v = glm::dvec3(0, 0, 0.5);
  // A pyramid with a narrower pyramidal hollow under it, the two meeting only at the apex (a
  // pinched vertex), closed by a ring of four trapezoids at z = 0; faces interleaved so that a
  // surface mesh takes both fans. Not shown to be a solid: 0.
  std::vector<Polygon> pinched;
  {
    const glm::dvec3 apex(0, 0, 6);
    const glm::dvec3 outer[4] = {{-4, -4, 0}, {4, -4, 0}, {4, 4, 0}, {-4, 4, 0}};
    const glm::dvec3 inner[4] = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}};
    for (int i = 0; i < 4; ++i) {
      const int j = (i + 1) % 4;
      pinched.push_back({outer[i], outer[j], apex});  // outward
      pinched.push_back({inner[j], inner[i], apex});  // the hollow's walls, facing into it
    }
    for (int i = 0; i < 4; ++i) {
      const int j = (i + 1) % 4;
      pinched.push_back({outer[j], outer[i], inner[i], inner[j]});  // the ring, facing down
    }
  }
  struct Case {
    const char* name;
    const std::vector<Polygon>* faces;
    signed char expected;
  };
  const Case cases[] = {{"closed", &closed, 1},        {"inward", &inward, -1},  {"no floor", &no_floor, 2},
                        {"no roof", &no_roof, 0},      {"pierced", &pierced, 0}, {"sloped border", &sloped, 0},
                        {"pinched", &pinched, 0}};
  for (const Case& c : cases) {
    shadow::Scene scene;
    shadow::add_mesh(scene, c.name, *c.faces);
    shadow::add_mesh(scene, "box", shadow::box_faces({10, 10, 0}, {12, 13, 5}));  // convex: a solid, not told
    shadow::add_mesh(scene, "ground", {{{-20, -20, 0}, {40, -20, 0}, {40, 40, 0}, {-20, 40, 0}}});
    for (unsigned threads : {1u, 2u}) {
      const std::vector<signed char> outward = closed_outward_of(scene, threads);
      ASSERT_EQ(outward.size(), scene.faces.size());
      for (std::size_t f = 0; f < c.faces->size(); ++f) EXPECT_EQ(outward[f], c.expected) << c.name << " face " << f;
      for (std::size_t f = c.faces->size(); f < scene.faces.size(); ++f) EXPECT_EQ(outward[f], 0) << c.name << " face " << f;
    }
  }
}

TEST(PointHash, NegativeZeroIsZeroAndOtherBitsDiffer) {
  using namespace shadow::geometry;
  const glm::dvec3 zero(0.0, 2.5, 0.0), negative(-0.0, 2.5, -0.0);
  EXPECT_EQ(point_key(zero), point_key(negative));
  EXPECT_EQ(point_hash(zero), point_hash(negative));
  EXPECT_EQ(PointKeyHash{}(point_key(zero)), PointKeyHash{}(point_key(negative)));
  EXPECT_EQ(point_hash(zero), point_key_hash(point_key(zero)));
  const glm::dvec3 tiny(std::nextafter(0.0, 1.0), 2.5, 0.0);  // the smallest subnormal: another point
  EXPECT_NE(point_key(zero), point_key(tiny));
  EXPECT_NE(point_hash(zero), point_hash(tiny));
  EXPECT_NE(point_hash(zero), point_hash(glm::dvec3(2.5, 0.0, 0.0)));  // coordinates in order
}

TEST(FindConvexSolids, NegativeZeroCoordinatesAreTheSameVertex) {
  // A unit box whose bottom face writes its zeros as -0.0: both searches (vertex keys from
  // geometry/point_hash.hpp) must still see one closed convex solid.
  std::vector<shadow::Polygon3> faces = shadow::box_faces({0, 0, 0}, {1, 1, 1});
  std::size_t flipped = 0;
  for (glm::dvec3& v : faces[0])
    for (int c = 0; c < 3; ++c)
      if (v[c] == 0.0) {
        v[c] = -0.0;
        ++flipped;
      }
  ASSERT_GT(flipped, 0u);
  shadow::Scene scene;
  shadow::add_mesh(scene, "box", faces);
  for (unsigned threads : {1u, 2u}) expect_same_solids(scene, threads);
  std::vector<shadow::core::FacePrep> prep(scene.faces.size());
  for (std::size_t f = 0; f < prep.size(); ++f) prep[f] = shadow::exact::prepare_face(scene.faces[f].vertices);
  std::vector<int> of;
  EXPECT_EQ(shadow::exact::find_convex_solids(scene, prep, of, 1).size(), 1u);
  EXPECT_EQ(of, std::vector<int>(scene.faces.size(), 0));
}

RC_GTEST_PROP(FindConvexSolids, SameAsTheReferenceOnHardCases, ()) {
  shadow::Scene scene = *shadow::testing::gen::hard_case();
  shadow::validate_scene(scene);
  std::vector<shadow::core::FacePrep> prep(scene.faces.size());
  for (std::size_t f = 0; f < prep.size(); ++f) {
    if (scene.faces[f].degenerate)
      prep[f].degenerate = true;
    else
      prep[f] = shadow::exact::prepare_face(scene.faces[f].vertices);
  }
  std::vector<int> of, ref_of;
  const auto solids = shadow::exact::find_convex_solids(scene, prep, of, 2);
  const auto ref = shadow::exact::find_convex_solids_reference(scene, prep, ref_of);
  RC_ASSERT(of == ref_of);
  RC_ASSERT(solids.size() == ref.size());
  for (std::size_t s = 0; s < solids.size(); ++s) {
    RC_ASSERT(solids[s].vertices == ref[s].vertices);
    RC_ASSERT(solids[s].edges == ref[s].edges);
  }
  // Every face's class too.
  for (const shadow::Face& face : scene.faces)
    RC_ASSERT(shadow::detail::classify_face_shape(face.vertices) == shadow::detail::classify_face_shape_exact(face.vertices));
}

}  // namespace

// The vertex numbering of the convex-solid search on several threads (shards by hash, first
// corners numbered by a prefix sum): the same ids, in order of first use, as one thread.
TEST(FindConvexSolids, VertexIdsAreTheSameOnEveryThreadCount) {
  shadow::Scene city = shadow::make_city(2000, 500, 7);
  // Some corners at z = -0.0 (box bottoms): the same vertices as at +0.0 in the walls.
  std::size_t negative_zeros = 0;
  for (shadow::Face& face : city.faces)
    if (face.vertices.size() == 4 && face.vertices[0].z == 0 && face.vertices[2].z == 0 && negative_zeros < 50) {
      face.vertices[0].z = -0.0;
      ++negative_zeros;
    }
  ASSERT_EQ(negative_zeros, 50u);
  std::vector<shadow::core::FacePrep> prep(city.faces.size());
  std::size_t corners = 0;
  for (std::size_t f = 0; f < prep.size(); ++f) {
    prep[f] = shadow::exact::prepare_face(city.faces[f].vertices);
    if (!prep[f].degenerate && prep[f].exactly_planar) corners += city.faces[f].vertices.size();
  }
  ASSERT_GE(corners, shadow::exact::kParallelNumberingCorners);
  shadow::runtime::UninitVector<int> one(corners), many(corners);
  shadow::runtime::UninitVector<glm::dvec3> one_position, many_position;
  shadow::exact::number_vertices(city, prep, one, one_position, 1);
  // Ids in order of first use: each corner's id is at most one more than every id before it.
  int next = 0;
  for (int id : one) {
    ASSERT_LE(id, next);
    if (id == next) ++next;
  }
  EXPECT_EQ(static_cast<std::size_t>(next), one_position.size());
  EXPECT_EQ(one_position.size(), 4 + 8 * 2000u);  // the ground's corners and every box's 8
  for (unsigned threads : {2u, 3u, 8u}) {
    shadow::exact::number_vertices(city, prep, many, many_position, threads);
    EXPECT_EQ(many, one) << threads << " threads";
    EXPECT_EQ(many_position, one_position) << threads << " threads";
  }
}

// The scene's frame (the culling's origin and diameter) by blocks of faces on several threads:
// the same bits as one pass, a tie between +0.0 and -0.0 included (the first one met wins).
TEST(SceneFrame, TheSameBitsOnEveryThreadCount) {
  shadow::Scene scene;
  std::mt19937 rng(35);
  std::uniform_real_distribution<double> coordinate(0.0, 100.0);
  for (std::size_t f = 0; f < 50000; ++f) {
    shadow::Face face;
    const double x = coordinate(rng), y = coordinate(rng);
    face.vertices = {{x, y, 0.0}, {x + 1, y, 0.0}, {x, y + 1, 0.0}};
    scene.faces.push_back(face);
  }
  // Every z is 0: -0.0 in the first face, +0.0 elsewhere; the smallest x is 0, -0.0 met first
  // in a later block of faces.
  for (glm::dvec3& v : scene.faces[0].vertices) v.z = -0.0;
  scene.faces[20000].vertices[0] = {-0.0, 5.0, 0.0};
  scene.faces[30000].vertices[0] = {0.0, 5.0, 0.0};
  scene.faces[40000].vertices[1] = {-0.0, 6.0, 0.0};
  auto bits = [](const shadow::core::SceneFrame& frame) {
    std::array<unsigned char, 4 * sizeof(double)> out{};
    const double values[4] = {frame.centre.x, frame.centre.y, frame.centre.z, frame.diagonal};
    std::memcpy(out.data(), values, sizeof values);
    return out;
  };
  const auto one = bits(shadow::core::scene_frame(scene, 1));
  for (unsigned threads : {2u, 3u, 8u}) EXPECT_EQ(bits(shadow::core::scene_frame(scene, threads)), one) << threads;
  // The first z met is -0.0: both ends of the box in z, hence the centre's z, are -0.0.
  EXPECT_TRUE(std::signbit(shadow::core::scene_frame(scene, 4).centre.z));
}

/// A generated city prepared for culling as the engine prepares it: faces, convex solids, cull scene.
struct CullingCity {
  CullingCity(std::size_t boxes, double side, unsigned seed, unsigned threads)
      : city(shadow::make_city(boxes, side, seed)), prep(city.faces.size()) {
    for (std::size_t f = 0; f < prep.size(); ++f) prep[f] = shadow::exact::prepare_face(city.faces[f].vertices);
    solids = shadow::exact::find_convex_solids(city, prep, solid_of, threads);
    cull = shadow::core::make_cull_scene(city, prep, threads);
  }
  shadow::Scene city;
  std::vector<shadow::core::FacePrep> prep;
  std::vector<int> solid_of;
  std::vector<shadow::core::ConvexSolid> solids;
  shadow::core::CullScene cull;
};

// The light-space grid's cells filled on several threads (items in ranges, counted per range and
// cell): every query visits the same faces in the same order as with one thread.
TEST(LightSpaceGrid, TheSameQueriesOnEveryThreadCount) {
  const CullingCity c(12000, 1700, 11, 2);
  const auto& [city, prep, solid_of, solids, cull] = std::tie(c.city, c.prep, c.solid_of, c.solids, c.cull);
  ASSERT_EQ(solids.size(), 12000u);
  for (const glm::dvec3 to_light : {glm::dvec3(0.5, -0.5, 0.64), glm::dvec3(0.7, -0.7, 0.087)}) {
    auto visits = [&](unsigned threads, const std::vector<int>* of) {
      const shadow::core::LightSpaceGrid grid(cull, prep, to_light, of, threads);
      std::vector<std::size_t> out;
      for (std::size_t f = 0; f < city.faces.size(); f += 7) {
        out.push_back(grid.count(f));
        grid.query(f, [&](std::size_t g) { out.push_back(g); });
        out.push_back(SIZE_MAX);
      }
      return out;
    };
    const std::vector<int>* none = nullptr;
    for (const std::vector<int>* of : {none, static_cast<const std::vector<int>*>(&solid_of)}) {
      const std::vector<std::size_t> one = visits(1, of);
      EXPECT_GT(one.size(), 3 * city.faces.size() / 7);
      for (unsigned threads : {2u, 3u, 8u}) EXPECT_EQ(visits(threads, of), one) << threads << " threads";
    }
  }
}

// A query reports every face whose light-space box overlaps the receiver's, each once: an item
// met in several cells is taken in one cell both cover (the first of each range), which the
// query always visits. Low and high suns, with and without convex solids as items, against
// every face tested by the box test alone.
TEST(LightSpaceGrid, QueriesReportEveryOverlappingFaceOnce) {
  const shadow::Scene city = shadow::make_city(300, 400, 5);
  std::vector<shadow::core::FacePrep> prep(city.faces.size());
  for (std::size_t f = 0; f < prep.size(); ++f) prep[f] = shadow::exact::prepare_face(city.faces[f].vertices);
  std::vector<int> solid_of;
  shadow::exact::find_convex_solids(city, prep, solid_of, 1);
  const shadow::core::CullScene cull = shadow::core::make_cull_scene(city, prep, 1);
  const std::vector<int>* none = nullptr;
  std::size_t reported = 0;
  for (const glm::dvec3 to_light : {glm::dvec3(0.5, -0.5, 0.64), glm::dvec3(0.7, -0.7, 0.087), glm::dvec3(-0.2, 0.1, 1.0),
                                    glm::dvec3(0.95, 0.1, 0.05)})
    for (const std::vector<int>* of : {none, static_cast<const std::vector<int>*>(&solid_of)}) {
      const shadow::core::LightSpaceGrid grid(cull, prep, to_light, of, 1);
      for (std::size_t f = 0; f < city.faces.size(); f += 3) {
        if (prep[f].degenerate) continue;
        std::vector<std::size_t> got;
        grid.query(f, [&](std::size_t g) { got.push_back(g); });
        std::sort(got.begin(), got.end());
        std::vector<std::size_t> want;
        for (std::size_t g = 0; g < city.faces.size(); ++g)
          if (!prep[g].degenerate && grid.reports(f, g)) want.push_back(g);
        ASSERT_EQ(got, want) << "face " << f;  // sorted equal: each reported exactly once
        reported += got.size();
        // A part of the face (a tile: here its first vertices, in the cull scene's local frame):
        // each face once (the candidates' gather keeps no stamp), and only faces of the whole
        // face's query.
        const shadow::core::CullFace& cf = cull.faces[f];
        std::vector<glm::dvec3> part(cull.vertices.begin() + static_cast<std::ptrdiff_t>(cf.first),
                                     cull.vertices.begin() + static_cast<std::ptrdiff_t>(cf.first + std::min<std::size_t>(cf.count, 2)));
        std::vector<std::size_t> in_part;
        grid.query_part(f, part, 0.5, [&](std::size_t g) { in_part.push_back(g); });
        std::sort(in_part.begin(), in_part.end());
        EXPECT_TRUE(std::adjacent_find(in_part.begin(), in_part.end()) == in_part.end()) << "face " << f;
        EXPECT_TRUE(std::includes(got.begin(), got.end(), in_part.begin(), in_part.end())) << "face " << f;
      }
    }
  EXPECT_GT(reported, 8 * city.faces.size());  // the queries meet many faces, not a handful
}

// A query with a depth (how far towards the light the caller's points reach at the least) leaves
// out exactly the items that reach less far, each of its faces wholly behind every such point,
// and keeps every face of every other item: the cells' entries are sorted by reach and the scan
// of a cell stops at the first that falls short. Against the query without a depth.
TEST(LightSpaceGrid, ADepthLeavesOutOnlyItemsWhollyBehindIt) {
  const CullingCity c(300, 400, 5, 1);
  const auto& [city, prep, solid_of, cull] = std::tie(c.city, c.prep, c.solid_of, c.cull);
  const auto keep_all = [](const shadow::core::LocalBounds&) { return true; };
  std::size_t left_out = 0, kept = 0;
  for (const glm::dvec3 to_light : {glm::dvec3(0.5, -0.5, 0.64), glm::dvec3(0.7, -0.7, 0.087), glm::dvec3(-0.2, 0.1, 1.0)}) {
    const glm::dvec3 d = glm::normalize(to_light);
    const shadow::core::LightSpaceGrid grid(cull, prep, to_light, &solid_of, 2);
    auto deepest = [&](std::size_t g) {  // of face g's vertices
      const shadow::core::CullFace& cf = cull.faces[g];
      double w = -1e300;
      for (std::size_t a = cf.first; a < cf.first + cf.count; ++a) w = std::max(w, glm::dot(d, cull.vertices[a]));
      return w;
    };
    for (std::size_t f = 0; f < city.faces.size(); f += 5) {
      if (prep[f].degenerate) continue;
      std::vector<std::size_t> all, near;
      grid.query(f, [&](std::size_t g) { all.push_back(g); }, keep_all);
      // The depth of the receiver's own vertex nearest the light: items beyond it and behind it.
      const shadow::core::CullFace& cf = cull.faces[f];
      double min_depth = 1e300;
      for (std::size_t a = cf.first; a < cf.first + cf.count; ++a) min_depth = std::min(min_depth, grid.depth(cull.vertices[a]));
      grid.query(f, [&](std::size_t g) { near.push_back(g); }, keep_all, shadow::core::LightSpaceGrid::kNoItem, min_depth);
      std::sort(all.begin(), all.end());
      std::sort(near.begin(), near.end());
      ASSERT_TRUE(std::includes(all.begin(), all.end(), near.begin(), near.end())) << "face " << f;
      // Per item of the full list: left out whole when its deepest face falls short (by more
      // than the margin), kept whole otherwise.
      std::map<std::uint32_t, double> item_depth;
      for (std::size_t g : all) {
        const std::uint32_t item = grid.item_of(g);
        item_depth[item] = item_depth.count(item) ? std::max(item_depth[item], deepest(g)) : deepest(g);
      }
      for (std::size_t g : all) {
        const bool in_near = std::binary_search(near.begin(), near.end(), g);
        const double reach = item_depth[grid.item_of(g)];
        if (!in_near) {
          EXPECT_LT(reach, min_depth) << "face " << g << " left out of face " << f << "'s query";
          ++left_out;
        } else {
          EXPECT_GT(reach, min_depth - 1e-6) << "face " << g << " kept in face " << f << "'s query";
          ++kept;
        }
      }
    }
  }
  EXPECT_GT(left_out, 1000u);  // the depth leaves out many items, not a handful
  EXPECT_GT(kept, 1000u);
}

// With one_face_per_solid (a caller that casts every convex solid as one hull at its first face
// in the list), the candidates are the full list less each solid's faces after its first: the
// solid's first listed face is its lowest that passes culling, as in the full list, so the hull
// is cast at the same place and every result is the same. A grid whose solids are not items
// (its faces visited in cell order), and no grid, keep the full list.
TEST(CasterCandidates, OneFacePerSolidKeepsEachSolidsLowestFaceThatPasses) {
  const CullingCity c(300, 400, 5, 1);
  const auto& [city, prep, solid_of, solids, cull] = std::tie(c.city, c.prep, c.solid_of, c.solids, c.cull);
  shadow::core::CasterCandidates candidates;
  candidates.reset(solids.size());
  std::size_t dropped = 0;
  for (const glm::dvec3 to_light : {glm::dvec3(0.5, -0.5, 0.64), glm::dvec3(0.7, -0.7, 0.087), glm::dvec3(-0.2, 0.1, 1.0)}) {
    shadow::Light sun;
    sun.type = shadow::LightType::Directional;
    sun.to_light = to_light;
    const shadow::core::LightSpaceGrid with_solids(cull, prep, to_light, &solid_of, 1);
    const shadow::core::LightSpaceGrid faces_alone(cull, prep, to_light, nullptr, 1);
    for (std::size_t f = 0; f < city.faces.size(); f += 2) {
      if (prep[f].degenerate) continue;
      const shadow::core::ReceiverCuller culler(cull, prep[f], f, sun);
      for (const shadow::core::LightSpaceGrid* grid : {&with_solids, &faces_alone, static_cast<const shadow::core::LightSpaceGrid*>(nullptr)}) {
        const std::vector<std::size_t> all = candidates.gather(culler, prep, f, grid, nullptr, nullptr, &solid_of, false);
        std::vector<std::size_t> want;
        std::set<int> listed;
        for (std::size_t q : all)
          if (solid_of[q] < 0 || grid != &with_solids || listed.insert(solid_of[q]).second) want.push_back(q);
        const std::vector<std::size_t> one = candidates.gather(culler, prep, f, grid, nullptr, nullptr, &solid_of, true);
        ASSERT_EQ(one, want) << "face " << f;
        dropped += all.size() - one.size();
      }
    }
  }
  EXPECT_GT(dropped, 1000u);  // solids met with several faces that pass: the case exists
}

// The grid query skips the receiver's own convex solid and, with one_face_per_solid, leaves a
// solid's faces once one is listed. The same candidates as a grid of the same items that neither
// skips nor leaves early: one made from a copy of solid_of (a pointer gather does not match).
TEST(CasterCandidates, OwnSolidSkippedAndListedSolidsLeftEarlyGiveTheSameCandidates) {
  const CullingCity c(300, 400, 5, 1);
  const auto& [city, prep, solid_of, solids, cull] = std::tie(c.city, c.prep, c.solid_of, c.solids, c.cull);
  const std::vector<int> solid_copy = solid_of;
  shadow::core::CasterCandidates candidates;
  candidates.reset(solids.size());
  std::size_t skipped = 0, compared = 0;
  for (const glm::dvec3 to_light : {glm::dvec3(0.5, -0.5, 0.64), glm::dvec3(0.7, -0.7, 0.087), glm::dvec3(-0.2, 0.1, 1.0)}) {
    shadow::Light sun;
    sun.type = shadow::LightType::Directional;
    sun.to_light = to_light;
    const shadow::core::LightSpaceGrid with_solids(cull, prep, to_light, &solid_of, 1);
    const shadow::core::LightSpaceGrid same_items(cull, prep, to_light, &solid_copy, 1);
    for (std::size_t f = 0; f < city.faces.size(); ++f) {
      if (prep[f].degenerate) continue;
      if (solid_of[f] >= 0) {
        ++skipped;
        ASSERT_NE(with_solids.item_of(f), shadow::core::LightSpaceGrid::kNoItem) << f;
      }
      const shadow::core::ReceiverCuller culler(cull, prep[f], f, sun);
      const std::vector<std::size_t> full = candidates.gather(culler, prep, f, &same_items, nullptr, nullptr, &solid_of, true);
      ASSERT_EQ(candidates.gather(culler, prep, f, &with_solids, nullptr, nullptr, &solid_of, false), full) << f;
      std::vector<std::size_t> want;
      std::set<int> listed;
      for (std::size_t q : full)
        if (solid_of[q] < 0 || listed.insert(solid_of[q]).second) want.push_back(q);
      ASSERT_EQ(candidates.gather(culler, prep, f, &with_solids, nullptr, nullptr, &solid_of, true), want) << f;
      compared += full.size();
    }
  }
  EXPECT_GT(skipped, 1000u);   // receivers on a solid: the skip applies
  EXPECT_GT(compared, 1000u);  // and they have candidates
}

// An item of the grid (a convex solid, or a face alone) whose local box the culler rules out
// whole (ReceiverCuller::may_cast_any) is skipped before its faces are read. Sound: no face whose
// box it rules out passes may_cast. And the candidates are the same with the items' boxes and
// without, for solids and faces alone, under a high, a low and a grazing sun.
TEST(CasterCandidates, ItemsRuledOutWholeChangeNoCandidate) {
  const CullingCity c(300, 400, 5, 1);
  const auto& [city, prep, solid_of, solids, cull] = std::tie(c.city, c.prep, c.solid_of, c.solids, c.cull);
  const std::vector<shadow::core::LocalBounds> faces = shadow::core::face_bounds(cull, 2);
  const std::vector<shadow::core::LocalBounds> solid_items =
      shadow::core::LightSpaceGrid::item_bounds(cull, prep, &solid_of, 2);
  const std::vector<shadow::core::LocalBounds> face_items = shadow::core::LightSpaceGrid::item_bounds(cull, prep, nullptr, 1);
  ASSERT_EQ(solid_items.size(), solids.size() + 1);  // the boxes and the ground
  shadow::core::CasterCandidates candidates;
  candidates.reset(solids.size());
  std::size_t ruled_out = 0, skipped = 0, compared = 0;
  for (const glm::dvec3 to_light : {glm::dvec3(0.5, -0.5, 0.64), glm::dvec3(0.7, -0.7, 0.087), glm::dvec3(-0.2, 0.1, 1.0),
                                    glm::dvec3(1.0, 0.3, 1e-9)}) {
    shadow::Light sun;
    sun.type = shadow::LightType::Directional;
    sun.to_light = to_light;
    const shadow::core::LightSpaceGrid plain(cull, prep, to_light, &solid_of, 1);
    const shadow::core::LightSpaceGrid with_bounds(cull, prep, to_light, &solid_of, 1, &solid_items);
    const shadow::core::LightSpaceGrid alone_plain(cull, prep, to_light, nullptr, 1);
    const shadow::core::LightSpaceGrid alone_bounds(cull, prep, to_light, nullptr, 1, &face_items);
    for (std::size_t f = 0; f < city.faces.size(); f += 3) {
      if (prep[f].degenerate) continue;
      const shadow::core::ReceiverCuller culler(cull, prep[f], f, sun);
      for (std::size_t q = 0; q < city.faces.size(); ++q) {
        if (culler.may_cast_any(faces[q])) continue;
        ++ruled_out;
        ASSERT_FALSE(culler.may_cast(q)) << "receiver " << f << ", face " << q;
      }
      for (const bool one_face : {false, true}) {
        const std::vector<std::size_t> want = candidates.gather(culler, prep, f, &plain, nullptr, nullptr, &solid_of, one_face);
        ASSERT_EQ(candidates.gather(culler, prep, f, &with_bounds, nullptr, nullptr, &solid_of, one_face), want) << f;
        const std::vector<std::size_t> alone = candidates.gather(culler, prep, f, &alone_plain, nullptr, nullptr, &solid_of, one_face);
        ASSERT_EQ(candidates.gather(culler, prep, f, &alone_bounds, nullptr, nullptr, &solid_of, one_face), alone) << f;
        ++compared;
      }
      with_bounds.query(f, [](std::size_t) {}, [&](const shadow::core::LocalBounds& b) {
        const bool keep = culler.may_cast_any(b);
        skipped += keep ? 0 : 1;
        return keep;
      });
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_GT(ruled_out, 10000u);  // the case exists: faces behind a receiver's plane or beside its prism
  EXPECT_GT(skipped, 100u);      // and whole items in the cells a query visits
}

// A grid refuses item boxes made for another scene or other solids (their count differs).
TEST(LightSpaceGrid, RefusesItemBoundsOfAnotherScene) {
  const CullingCity c(30, 100, 3, 1);
  const std::vector<shadow::core::LocalBounds> faces_alone = shadow::core::LightSpaceGrid::item_bounds(c.cull, c.prep, nullptr, 1);
  EXPECT_THROW(shadow::core::LightSpaceGrid(c.cull, c.prep, glm::dvec3(0.3, 0.2, 1.0), &c.solid_of, 1, &faces_alone),
               std::logic_error);
}
