// SPDX-License-Identifier: GPL-3.0-or-later
// Exact vector views (shadow/view.hpp): the visible pieces against closed-form answers, against
// an independent z-buffer of the same camera (a ray per pixel, nearest hit wins), and their
// lit/shadow split against the engine's lit areas and an independent shadow ray.
#include "support/polygon_tools.hpp"
#include "support/ray_caster.hpp"
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>
#include <shadow/view.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>

namespace shadow::test {
namespace {

double image_area(const std::vector<glm::dvec2>& poly) {
  double twice = 0;
  for (std::size_t a = 0; a < poly.size(); ++a) {
    const glm::dvec2& p = poly[a];
    const glm::dvec2& q = poly[(a + 1) % poly.size()];
    twice += (p.x - poly[0].x) * (q.y - poly[0].y) - (q.x - poly[0].x) * (p.y - poly[0].y);
  }
  return std::abs(twice) / 2;
}

/// Pixels whose centre a segment's pixel-centre classification can get wrong: those it crosses,
/// at most |dx| + |dy| + 2 for a segment in pixel units.
double boundary_pixels(const std::vector<glm::dvec2>& poly) {
  double sum = 0;
  for (std::size_t a = 0; a < poly.size(); ++a) {
    const glm::dvec2 d = poly[(a + 1) % poly.size()] - poly[a];
    sum += std::abs(d.x) + std::abs(d.y) + 2;
  }
  return sum;
}

/// An independent z-buffer: one ray from the eye through each pixel centre, the nearest face
/// hit at depth >= near wins (either side of a face: every face blocks both ways). Returns the
/// pixel count per face. Depth along the ray with the view direction's component 1, so it is the
/// camera depth the near plane cuts.
std::map<std::size_t, long> zbuffer(const Scene& scene, const ViewFrame& fr) {
  struct Prepared {
    std::size_t id;
    glm::dvec3 n, p0;
    Polygon3 poly;
  };
  std::vector<Prepared> faces;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (scene.faces[f].degenerate) continue;
    const glm::dvec3 n = newell_normal(scene.faces[f].vertices);
    faces.push_back({f, n, scene.faces[f].vertices[0], scene.faces[f].vertices});
  }
  std::map<std::size_t, long> count;
  for (int y = 0; y < fr.height; ++y) {
    for (int x = 0; x < fr.width; ++x) {
      const glm::dvec3 dir = fr.forward + ((x + 0.5 - fr.width / 2.0) / fr.focal) * fr.right -
                             ((y + 0.5 - fr.height / 2.0) / fr.focal) * fr.up;
      double best = std::numeric_limits<double>::infinity();
      std::size_t hit = SIZE_MAX;
      for (const Prepared& f : faces) {
        const double denom = glm::dot(f.n, dir);
        if (denom == 0) continue;
        const double t = glm::dot(f.n, f.p0 - fr.eye) / denom;
        if (!(t >= fr.near) || t >= best) continue;
        if (!inside_polygon(f.poly, fr.eye + t * dir)) continue;
        best = t;
        hit = f.id;
      }
      if (hit != SIZE_MAX) ++count[hit];
    }
  }
  return count;
}

struct PerFace {
  double image = 0, bound = 0, area = 0, lit_area = 0;
  bool back = false;
};
std::map<std::size_t, PerFace> per_face(const VectorView& view) {
  std::map<std::size_t, PerFace> out;
  for (const ViewPiece& p : view.pieces) {
    PerFace& f = out[p.face_id];
    f.image += image_area(p.image);
    f.bound += boundary_pixels(p.image);
    f.area += p.area;
    if (p.lit) f.lit_area += p.area;
    f.back = p.back;
  }
  return out;
}

/// Every face's pieces cover as many pixels as the z-buffer gives it, within the pixels their
/// boundaries cross; returns the largest |difference| / bound.
double check_against_zbuffer(const Scene& scene, const VectorView& view) {
  const std::map<std::size_t, long> counts = zbuffer(scene, view.frame);
  const std::map<std::size_t, PerFace> faces = per_face(view);
  double worst = 0, total_raster = 0, total_exact = 0, total_difference = 0;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const auto c = counts.find(f);
    const auto v = faces.find(f);
    const double raster = c == counts.end() ? 0.0 : static_cast<double>(c->second);
    const double exact = v == faces.end() ? 0.0 : v->second.image;
    const double bound = v == faces.end() ? 0.0 : v->second.bound;
    // A face the view leaves out entirely may still catch a pixel only where another face's
    // boundary runs (a sliver the view gave to nobody cannot exist: pieces tile the visible).
    if (v == faces.end()) {
      EXPECT_EQ(raster, 0.0) << "face " << f << " is missing from the view";
      continue;
    }
    EXPECT_LE(std::abs(raster - exact), bound) << "face " << f << ": raster " << raster << ", exact " << exact;
    total_raster += raster;
    total_exact += exact;
    total_difference += std::abs(raster - exact);
    if (bound > 0) worst = std::max(worst, std::abs(raster - exact) / bound);
  }
  std::printf("z-buffer %dx%d: %.0f pixels covered, exact image area %.3f, sum of per-face |differences| %.1f "
              "pixels (%.2e of the area); worst face at %.3f of its bound\n",
              view.frame.width, view.frame.height, total_raster, total_exact, total_difference,
              total_difference / std::max(total_exact, 1.0), worst);
  return worst;
}

Scene box_scene() {
  Scene scene;
  add_mesh(scene, "box", box_faces({0, 0, 0}, {1, 1, 1}));
  validate_scene(scene);
  return scene;
}

double total_image_area(const VectorView& view, std::size_t face) {
  double sum = 0;
  for (const ViewPiece& p : view.pieces)
    if (p.face_id == face) sum += image_area(p.image);
  return sum;
}

TEST(VectorView, BoxSeenAlongAnAxisShowsOnlyItsTopWithTheAreaOfPerspective) {
  const Scene scene = box_scene();
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {0.5, 0.5, 10};
  camera.target = {0.5, 0.5, 0.5};
  camera.up = {0, 1, 0};
  camera.width = 640;
  camera.height = 480;
  const VectorView view = compute_vector_view(engine, camera, {std::nullopt, 1});
  ASSERT_FALSE(view.pieces.empty());
  double area = 0;
  for (const ViewPiece& p : view.pieces) {
    EXPECT_EQ(p.face_id, 0u);  // box_faces: top first
    EXPECT_FALSE(p.back);
    EXPECT_FALSE(p.lit);  // no light chosen
    area += p.area;
  }
  EXPECT_EQ(area, 1.0);
  // The top at depth 9: a square of side focal / 9 pixels, centred.
  const double side = view.frame.focal / 9;
  EXPECT_NEAR(total_image_area(view, 0), side * side, 1e-9 * side * side);
  for (const ViewPiece& p : view.pieces)
    for (const glm::dvec2& q : p.image) {
      EXPECT_NEAR(std::abs(q.x - 320), side / 2, 1e-9 * side);
      EXPECT_NEAR(std::abs(q.y - 240), side / 2, 1e-9 * side);
    }
}

TEST(VectorView, AWallHidesExactlyHalfOfAnother) {
  Scene scene;
  // A: y = 0, x in [0, 2], z in [0, 2], front toward -y (the eye). B: nearer, up to x = 1, the
  // eye's own x: the plane x = 1 through the eye cuts A in half.
  add_mesh(scene, "A", {{{0, 0, 0}, {2, 0, 0}, {2, 0, 2}, {0, 0, 2}}});
  add_mesh(scene, "B", {{{-3, -1, -5}, {1, -1, -5}, {1, -1, 5}, {-3, -1, 5}}});
  validate_scene(scene);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {1, -10, 1};
  camera.target = {1, 0, 1};
  camera.fov_degrees = 40;
  const VectorView view = compute_vector_view(engine, camera, {std::nullopt, 1});
  const std::map<std::size_t, PerFace> faces = per_face(view);
  ASSERT_EQ(faces.count(0), 1u);
  EXPECT_EQ(faces.at(0).area, 2.0);
  for (const ViewPiece& p : view.pieces)
    if (p.face_id == 0)
      for (const glm::dvec3& v : p.polygon) EXPECT_GE(v.x, 1.0);
  // Depth 10: 1 x 2 units at focal / 10 pixels per unit.
  const double f = view.frame.focal / 10;
  EXPECT_NEAR(faces.at(0).image, 2 * f * f, 1e-9 * f * f);
}

TEST(VectorView, AFaceSeenFromItsBackIsVisibleAndInItsAttachedShadow) {
  Scene scene;
  add_mesh(scene, "roof", {rectangle_z(0, 0, 1, 1, 0)});  // front up
  scene.lights.push_back(directional_light("sun", {0, 0, 1}));
  validate_scene(scene);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {0.5, 0.5, -5};  // below: the back
  camera.target = {0.5, 0.5, 0};
  camera.up = {0, 1, 0};
  const VectorView below = compute_vector_view(engine, camera, {std::size_t{0}, 1});
  double area = 0;
  for (const ViewPiece& p : below.pieces) {
    EXPECT_TRUE(p.back);
    EXPECT_FALSE(p.lit);
    area += p.area;
  }
  EXPECT_EQ(area, 1.0);
  camera.eye = {0.5, 0.5, 5};  // above: the front, lit by the sun overhead
  const VectorView above = compute_vector_view(engine, camera, {std::size_t{0}, 1});
  area = 0;
  for (const ViewPiece& p : above.pieces) {
    EXPECT_FALSE(p.back);
    EXPECT_TRUE(p.lit);
    area += p.area;
  }
  EXPECT_EQ(area, 1.0);
}

TEST(VectorView, AFaceInTheEyesPlaneIsEdgeOnAndGivesNothing) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "post", {{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}});  // the plane y = 0
  validate_scene(scene);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {3, 0, 2};  // in the post's plane
  camera.target = {0, 0, 0};
  const VectorView view = compute_vector_view(engine, camera, {std::nullopt, 1});
  EXPECT_EQ(per_face(view).count(1), 0u);
  EXPECT_EQ(per_face(view).count(0), 1u);
  EXPECT_LE(check_against_zbuffer(scene, view), 1.0);
}

TEST(VectorView, GroundCrossingTheEyesPlaneIsCutAtTheNearPlaneAndMatchesAZBuffer) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-50, -50, 50, 50, 0)});
  add_mesh(scene, "box", box_faces({-1, 2, 0}, {1, 4, 1.5}));
  add_mesh(scene, "behind", {{{-3, -5, 0}, {3, -5, 0}, {3, -5, 3}, {-3, -5, 3}}});  // face 7, behind the eye
  scene.lights.push_back(point_light("lamp", {3, 0, 4}));
  validate_scene(scene);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {0.3, -2, 0.8};  // the ground runs behind the eye
  camera.target = {0, 10, 0.5};
  camera.width = 400;
  camera.height = 300;
  camera.fov_degrees = 70;
  const VectorView view = compute_vector_view(engine, camera, {std::size_t{0}, 1});
  for (const ViewPiece& p : view.pieces)
    for (const glm::dvec2& q : p.image) {
      EXPECT_GE(q.x, -1e-6);
      EXPECT_LE(q.x, 400 + 1e-6);
      EXPECT_GE(q.y, -1e-6);
      EXPECT_LE(q.y, 300 + 1e-6);
    }
  EXPECT_EQ(per_face(view).count(7), 0u);
  for (const ViewPiece& p : view.pieces)  // nothing nearer than the near plane
    for (const glm::dvec3& v : p.polygon) {
      double depth = 0;
      (void)project_to_image(view.frame, v, &depth);
      EXPECT_GE(depth, view.frame.near * (1 - 1e-9));
    }
  EXPECT_NEAR(view.frame.near, 1e-3 * glm::length(camera.target - camera.eye), 1e-15);
  EXPECT_LE(check_against_zbuffer(scene, view), 1.0);
}

/// The example scene's shapes (a ground, two boxes, a floating roof) at 2000 x 2000.
TEST(VectorView, PiecesMatchAHighResolutionZBuffer) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-6, -6, 6, 6, 0)});
  add_mesh(scene, "box", box_faces({-2, -1, 0}, {0, 1, 2}));
  add_mesh(scene, "tower", box_faces({1, 1, 0}, {2, 3, 4}));
  // A tilted quadrilateral, exactly planar: z = 2.75 + x / 8 - y / 4.
  auto roof_z = [](double x, double y) { return 2.75 + x / 8 - y / 4; };
  add_mesh(scene, "roof", {{{-1, -3, roof_z(-1, -3)}, {2, -3, roof_z(2, -3)}, {1.5, -1, roof_z(1.5, -1)},
                            {-1.5, -1.5, roof_z(-1.5, -1.5)}}});
  scene.lights.push_back(directional_light("sun", {0.4, -0.7, 1}));
  validate_scene(scene);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {7, -9, 6};
  camera.target = {0, 0, 1};
  camera.width = 2000;
  camera.height = 2000;
  camera.fov_degrees = 45;
  const VectorView view = compute_vector_view(engine, camera, {std::size_t{0}, 1});
  const double worst = check_against_zbuffer(scene, view);
  EXPECT_LE(worst, 1.0);
  RecordProperty("worst_error_over_bound", std::to_string(worst));
}

TEST(VectorView, RandomScenesMatchAZBuffer) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    Scene scene = random_scene(seed);
    validate_scene(scene);
    const ShadowEngine engine(scene, 1);
    ViewCamera camera;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    camera.eye = {12 * u(rng), 12 * u(rng), 3 + 6 * (u(rng) + 1)};
    camera.target = {u(rng), u(rng), 0.5};
    camera.width = 500;
    camera.height = 400;
    camera.fov_degrees = 50;
    const VectorView view = compute_vector_view(engine, camera, {std::size_t{0}, 1});
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_LE(check_against_zbuffer(scene, view), 1.0);
  }
}

/// Lit pieces against the engine: a wholly visible face shows all of its lit area; no face shows
/// more; and sample points of each piece agree with an independent shadow ray.
TEST(VectorView, TheLitSplitAgreesWithTheEngineAndAShadowRay) {
  for (std::uint64_t seed = 11; seed <= 14; ++seed) {
    Scene scene = random_scene(seed);
    validate_scene(scene);
    const ShadowEngine engine(scene, 1);
    ShadowOptions options;
    options.threads = 1;
    const ShadowResult result = engine.compute(options);
    ViewCamera camera;
    camera.eye = {6, -14, 12};
    camera.target = {0, 0, 0};
    camera.fov_degrees = 60;
    const VectorView view = compute_vector_view(engine, camera, {std::size_t{0}, 1});
    SCOPED_TRACE("seed " + std::to_string(seed));
    int fully_visible = 0;
    for (const auto& [face, pf] : per_face(view)) {
      const FaceLighting* lighting = result.find(face, 0);
      ASSERT_NE(lighting, nullptr);
      EXPECT_LE(pf.lit_area, lighting->lit_area * (1 + 1e-12) + 1e-12);
      if (pf.back) {  // seen from the back: in its attached shadow whatever the light does
        EXPECT_EQ(pf.lit_area, 0.0);
        continue;
      }
      if (std::abs(pf.area - lighting->area) <= 1e-12 * lighting->area) {
        ++fully_visible;
        EXPECT_NEAR(pf.lit_area, lighting->lit_area, 1e-11 * lighting->area) << "face " << face;
      }
    }
    EXPECT_GT(fully_visible, 0);
    // Sample points of each front piece: lit exactly when the engine's lit fragments of that face
    // hold them (the same light), and when a shadow ray in doubles reaches the light.
    int checked = 0, in_fragments = 0;
    std::mt19937_64 rng(seed);
    for (const ViewPiece& p : view.pieces) {
      if (p.back || p.area < 1e-4) continue;
      for (const glm::dvec3& q : sample_interior(p.polygon, 3, 1e-3, rng)) {
        int lit_hits = 0, dark_hits = 0;
        bool near_edge = false;
        for (const Fragment& fragment : result.fragments) {
          if (fragment.face_id != p.face_id || fragment.light_id != 0) continue;
          double d = 0;
          const bool inside = inside_polygon(fragment.polygon, q, &d);
          if (d < 1e-7) near_edge = true;
          if (inside) ++(fragment.lit ? lit_hits : dark_hits);
        }
        if (!near_edge) {
          EXPECT_EQ(lit_hits + dark_hits, 1) << "face " << p.face_id;
          EXPECT_EQ(lit_hits == 1, p.lit) << "face " << p.face_id;
          ++in_fragments;
        }
        const RayVerdict v = cast_shadow_ray(scene, p.face_id, q, scene.lights[0], 1e-7);
        if (v == RayVerdict::Unsure) continue;
        EXPECT_EQ(v == RayVerdict::Lit, p.lit) << "face " << p.face_id;
        ++checked;
      }
    }
    EXPECT_GT(checked, 0);
    EXPECT_GT(in_fragments, 0);
    std::printf("seed %llu: %d sample points against the fragments, %d against a shadow ray\n",
                static_cast<unsigned long long>(seed), in_fragments, checked);
  }
}

TEST(VectorView, EachLightSplitsItsOwnView) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "square", {rectangle_z(0, 0, 1, 1, 1)});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("low", {0, 1, -0.1}));  // below the ground's plane
  validate_scene(scene);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {0.5, 0.5, 20};
  camera.target = {0.5, 0.5, 0};
  camera.up = {0, 1, 0};
  camera.fov_degrees = 60;  // the whole ground in view
  const VectorView overhead = compute_vector_view(engine, camera, {std::size_t{0}, 1});
  const std::map<std::size_t, PerFace> a = per_face(overhead);
  // From 20 up, the unit square at height 1 hides a square of side 20 / 19 of the ground, which
  // holds its own shadow (1 x 1) under the overhead light: all that is seen of the ground is lit.
  const double hidden = (20.0 / 19) * (20.0 / 19);
  EXPECT_NEAR(a.at(0).area, 100 - hidden, 1e-12);
  EXPECT_NEAR(a.at(0).lit_area, 100 - hidden, 1e-12);
  EXPECT_EQ(a.at(1).lit_area, 1.0);
  const VectorView low = compute_vector_view(engine, camera, {std::size_t{1}, 1});
  const std::map<std::size_t, PerFace> b = per_face(low);
  EXPECT_EQ(b.at(0).lit_area, 0.0);  // the light is below the ground's plane: attached shadow
  EXPECT_NEAR(b.at(0).area, 100 - hidden, 1e-12);
  ASSERT_TRUE(low.light_id);
  EXPECT_EQ(*low.light_id, 1u);
}

TEST(VectorView, FromInsideAClosedBoxEveryWallIsSeenFromItsBackAndFillsTheImage) {
  Scene scene;
  add_mesh(scene, "box", box_faces({-2, -3, -1}, {4, 2, 3}));  // fronts outward
  scene.lights.push_back(point_light("inside", {0.5, 0.5, 1}));
  validate_scene(scene);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {0.3, -0.2, 0.4};
  camera.target = {1, 1, 0.5};
  camera.fov_degrees = 100;
  camera.width = 300;
  camera.height = 200;
  const VectorView view = compute_vector_view(engine, camera, {std::size_t{0}, 1});
  double image = 0;
  for (const ViewPiece& p : view.pieces) {
    EXPECT_TRUE(p.back);
    EXPECT_FALSE(p.lit);  // the light inside sees only backs too
    image += image_area(p.image);
  }
  EXPECT_NEAR(image, 300.0 * 200.0, 1e-6);
  EXPECT_LE(check_against_zbuffer(scene, view), 1.0);
  // Inside a room (fronts inward) the same walls are seen from the front and lit.
  Scene room;
  add_mesh(room, "room", room_faces({-2, -3, -1}, {4, 2, 3}));
  room.lights.push_back(point_light("inside", {0.5, 0.5, 1}));
  validate_scene(room);
  const ShadowEngine room_engine(room, 1);
  const VectorView inside = compute_vector_view(room_engine, camera, {std::size_t{0}, 1});
  image = 0;
  for (const ViewPiece& p : inside.pieces) {
    EXPECT_FALSE(p.back);
    EXPECT_TRUE(p.lit);
    image += image_area(p.image);
  }
  EXPECT_NEAR(image, 300.0 * 200.0, 1e-6);
}

TEST(VectorView, ThreadsDoNotChangeThePieces) {
  Scene scene = random_scene(5);
  validate_scene(scene);
  const ShadowEngine engine(scene, 2);
  ViewCamera camera;
  camera.eye = {9, -7, 5};
  camera.target = {0, 0, 0.5};
  const VectorView one = compute_vector_view(engine, camera, {std::size_t{0}, 1});
  const VectorView two = compute_vector_view(engine, camera, {std::size_t{0}, 2});
  ASSERT_EQ(one.pieces.size(), two.pieces.size());
  for (std::size_t k = 0; k < one.pieces.size(); ++k) {
    EXPECT_EQ(one.pieces[k].face_id, two.pieces[k].face_id);
    EXPECT_EQ(one.pieces[k].lit, two.pieces[k].lit);
    EXPECT_EQ(one.pieces[k].polygon, two.pieces[k].polygon);
    EXPECT_EQ(one.pieces[k].area, two.pieces[k].area);
  }
}

// An extended light splits the view by the hard shadow of its centre (it was refused): the
// pieces are those of a point light at an area light's centroid, of the sun disk's central
// direction.
TEST(VectorView, AnExtendedLightSplitsTheViewFromItsCentre) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "square", {rectangle_z(0, 0, 1, 1, 1)});
  Light area;
  area.name = "panel";
  area.type = LightType::Area;
  area.polygon = {{0, 0, 4}, {0, 1, 4}, {1, 1, 4}, {1, 0, 4}};
  scene.lights.push_back(area);
  scene.lights.push_back(point_light("centre", {0.5, 0.5, 4}));
  Light sun = directional_light("sun", {0.3, 0.4, 1});
  sun.angular_diameter = 0.53;
  scene.lights.push_back(sun);
  scene.lights.push_back(directional_light("point sun", {0.3, 0.4, 1}));
  validate_scene(scene);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {6, -7, 9};
  camera.target = {0, 0, 0};
  for (std::size_t pair : {0u, 2u}) {
    const VectorView extended = compute_vector_view(engine, camera, {std::size_t{pair}, 1});
    const VectorView centre = compute_vector_view(engine, camera, {std::size_t{pair + 1}, 1});
    ASSERT_TRUE(extended.light_id);
    EXPECT_EQ(*extended.light_id, pair);
    ASSERT_EQ(extended.pieces.size(), centre.pieces.size());
    std::size_t shadowed = 0;
    for (std::size_t k = 0; k < extended.pieces.size(); ++k) {
      EXPECT_EQ(extended.pieces[k].face_id, centre.pieces[k].face_id);
      EXPECT_EQ(extended.pieces[k].lit, centre.pieces[k].lit);
      EXPECT_EQ(extended.pieces[k].polygon, centre.pieces[k].polygon);
      shadowed += extended.pieces[k].lit ? 0 : 1;
    }
    EXPECT_GT(shadowed, 0u);
  }
}

TEST(VectorView, BadInputIsAnInputError) {
  Scene scene = box_scene();
  scene.lights.push_back(point_light("lamp", {3, 3, 3}));
  Light disk;
  disk.type = LightType::Disk;
  disk.position = {0, 0, 5};
  disk.radius = 1;
  disk.normal = {0, 0, 0};  // unusable (an extended light as such is drawn from its centre)
  scene.lights.push_back(disk);
  const ShadowEngine engine(scene, 1);
  ViewCamera camera;
  camera.eye = {5, 5, 5};
  camera.target = {0, 0, 0};
  EXPECT_THROW((void)compute_vector_view(engine, camera, {std::size_t{7}, 1}), InputError);
  EXPECT_THROW((void)compute_vector_view(engine, camera, {std::size_t{1}, 1}), InputError);
  ViewCamera same = camera;
  same.target = same.eye;
  EXPECT_THROW((void)compute_vector_view(engine, same, {}), InputError);
  ViewCamera parallel = camera;
  parallel.up = {1, 1, 1};
  EXPECT_THROW((void)compute_vector_view(engine, parallel, {}), InputError);
  ViewCamera wide = camera;
  wide.fov_degrees = 180;
  EXPECT_THROW((void)compute_vector_view(engine, wide, {}), InputError);
  ViewCamera empty = camera;
  empty.width = 0;
  EXPECT_THROW((void)compute_vector_view(engine, empty, {}), InputError);
  ViewCamera nan = camera;
  nan.eye.x = std::nan("");
  EXPECT_THROW((void)compute_vector_view(engine, nan, {}), InputError);
}

}  // namespace
}  // namespace shadow::test
