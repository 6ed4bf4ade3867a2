// SPDX-License-Identifier: GPL-3.0-or-later
// The culler's caster-plane rule (core/culling.hpp, ReceiverCuller::caster_plane_rules_out): a
// face is left out as a caster of a receiver only where the whole receiver lies on the light's
// side of the face's plane, or on it. Checked against rays: from points of a receiver that the
// rule leaves a caster out for, no ray to the light meets the caster. Then through the engine: a
// wall standing on the ground is not a candidate for the ground any more, a wall through the
// ground still is, and both get their lit areas worked out by hand. Seeded.
#include "core/culling.hpp"
#include "exact/exact_faces.hpp"

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace shadow::test {
namespace {

/// The preparation the culler reads: each face's FacePrep, and the scene in the local frame.
struct Prepared {
  std::vector<core::FacePrep> prep;
  core::CullScene cull;
  explicit Prepared(const Scene& scene) {
    for (const Face& f : scene.faces) prep.push_back(exact::prepare_face(f.vertices));
    cull = core::make_cull_scene(scene, prep);
  }
};

/// Whether the ray p + t d meets triangle abc at a parameter clearly above 0 (and below
/// `t_max`: 1 for the segment to a lamp at p + d), strictly inside (long double, margins far
/// above its rounding).
bool ray_meets(const glm::dvec3& p, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
               long double t_max) {
  using L = long double;
  const L ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z, vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const L nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
  const L den = nx * d.x + ny * d.y + nz * d.z;
  if (std::fabs(den) < 1e-12L) return false;
  const L t = -(nx * (p.x - a.x) + ny * (p.y - a.y) + nz * (p.z - a.z)) / den;
  if (t <= 1e-9L || t >= t_max - 1e-9L) return false;
  const L x = p.x + t * d.x, y = p.y + t * d.y, z = p.z + t * d.z;
  auto side = [&](const glm::dvec3& s, const glm::dvec3& e) {
    const L ex = e.x - s.x, ey = e.y - s.y, ez = e.z - s.z, wx = x - s.x, wy = y - s.y, wz = z - s.z;
    return (ey * wz - ez * wy) * nx + (ez * wx - ex * wz) * ny + (ex * wy - ey * wx) * nz;
  };
  const L n2 = nx * nx + ny * ny + nz * nz;
  return side(a, b) > 1e-9L * n2 && side(b, c) > 1e-9L * n2 && side(c, a) > 1e-9L * n2;
}

TEST(CasterPlanes, RaysFromReceiversLeftOutNeverMeetTheCaster) {
  // Random triangles (exactly planar: the rule's double route) and axis-aligned rectangles (its
  // exact route), some resting on one another's planes, under random suns.
  std::mt19937_64 rng(20261207);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto coordinate = [&] { return std::round(40 * unit(rng) - 20) / 2; };  // halves: ties on planes
  std::size_t ruled_out = 0, lamp_ruled_out = 0, pairs = 0, rays = 0;
  for (int round = 0; round < 60; ++round) {
    Scene scene;
    std::vector<Polygon3> faces;
    for (int f = 0; f < 8; ++f) {
      if (f % 2 == 0) {
        faces.push_back({{coordinate(), coordinate(), coordinate()},
                         {coordinate(), coordinate(), coordinate()},
                         {coordinate(), coordinate(), coordinate()}});
      } else {
        const double z = f == 1 ? 0.0 : coordinate(), x0 = coordinate(), y0 = coordinate();
        faces.push_back(rectangle_z(x0, y0, x0 + 1 + 4 * unit(rng), y0 + 1 + 4 * unit(rng), z, unit(rng) < 0.8));
      }
    }
    // A wall on the ground rectangle's plane z = 0 (the foot of a wall: vertices on the plane).
    faces.push_back({{0, 0, 0}, {4, 1, 0}, {4, 1, 3}, {0, 0, 3}});
    for (const Polygon3& f : faces) add_mesh(scene, "f" + std::to_string(scene.meshes.size()), {f});
    // A sun, or (every third round) a lamp, on a plane of the faces' coordinates now and then.
    const bool lamp = round % 3 == 2;
    const glm::dvec3 d = sun_direction(5 + 80 * unit(rng), 360 * unit(rng));
    const glm::dvec3 at(coordinate(), coordinate(), round % 2 == 0 ? coordinate() : 12.0);
    scene.lights.push_back(lamp ? point_light("lamp", at) : directional_light("sun", d));
    bool valid = true;
    try {
      validate_scene(scene);
    } catch (const std::exception&) {
      valid = false;  // a degenerate random triangle
    }
    if (!valid) continue;
    const Prepared p(scene);
    for (std::size_t r = 0; r < scene.faces.size(); ++r) {
      if (p.prep[r].degenerate) continue;
      core::ReceiverCuller culler(p.cull, p.prep[r], r, scene.lights[0]);
      culler.use_caster_planes(scene, p.prep);
      for (std::size_t q = 0; q < scene.faces.size(); ++q) {
        if (q == r || p.prep[q].degenerate) continue;
        ++pairs;
        if (!culler.caster_plane_rules_out(q)) continue;
        ++ruled_out;
        lamp_ruled_out += lamp ? 1 : 0;
        const Polygon3& R = scene.faces[r].vertices;
        const Polygon3& Q = scene.faces[q].vertices;
        for (int k = 0; k < 64; ++k) {  // points of the receiver: convex combinations of its vertices
          glm::dvec3 point(0.0);
          double total = 0;
          for (const glm::dvec3& v : R) {
            const double w = unit(rng);
            point += w * v;
            total += w;
          }
          point /= total;
          for (std::size_t t = 1; t + 1 < Q.size(); ++t) {  // the caster's fan (convex faces here)
            ++rays;
            const bool meets = lamp ? ray_meets(point, at - point, Q[0], Q[t], Q[t + 1], 1)
                                    : ray_meets(point, d, Q[0], Q[t], Q[t + 1], 1e300L);
            EXPECT_FALSE(meets) << "round " << round << " receiver " << r << " caster " << q;
          }
        }
      }
    }
  }
  // Not vacuous: the rule applies to a good share of the pairs (every face on the ground's light
  // side, for one), under lamps too.
  std::printf("%zu of %zu pairs left out (%zu under lamps), %zu rays\n", ruled_out, pairs, lamp_ruled_out, rays);
  EXPECT_GT(ruled_out, pairs / 10);
  EXPECT_GT(lamp_ruled_out, ruled_out / 20);
  EXPECT_GT(rays, 10000u);
}

TEST(CasterPlanes, ALightInTheFloorsPlaneOrACasterNotExactlyPlanarDecidesNothing) {
  Scene scene;
  add_mesh(scene, "floor", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(scene, "table", {rectangle_z(0, 0, 2, 1, 0.8)});
  // A quad planar only within tolerance, under the table: no exact plane to decide by.
  add_mesh(scene, "warped", {{{-1, -1, 0.1}, {3, -1, 0.1}, {3, 2, 0.1 + 1e-12}, {-1, 2, 0.1}}});
  scene.lights.push_back(point_light("lamp", {1, 1, 2.5}));
  scene.lights.push_back(point_light("on the floor", {5, 5, 0}));
  scene.lights.push_back(point_light("under it", {5, 5, -1}));
  scene.lights.push_back(directional_light("sun", {0.3, 0.2, 1}));
  scene.lights.push_back(directional_light("level sun", {1, 0.5, 0}));
  validate_scene(scene);
  const Prepared p(scene);
  ASSERT_FALSE(p.prep[2].exactly_planar);
  const bool expected[] = {true, false, false, true, false};
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    core::ReceiverCuller culler(p.cull, p.prep[1], 1, scene.lights[l]);
    culler.use_caster_planes(scene, p.prep);
    EXPECT_EQ(culler.caster_plane_rules_out(0), expected[l]) << scene.lights[l].name;
    EXPECT_FALSE(culler.caster_plane_rules_out(2)) << scene.lights[l].name;
  }
}

TEST(CasterPlanes, NotWhereTheLightIsExtendedOrTheCullerWasNotAsked) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(scene, "wall", {{{0, 0, 0}, {4, 0, 0}, {4, 0, 3}, {0, 0, 3}}});
  scene.lights.push_back(directional_light("sun", sun_direction(30, 180)));
  Light disc = directional_light("disc", sun_direction(30, 180));
  disc.angular_diameter = 0.5;
  scene.lights.push_back(disc);
  validate_scene(scene);
  const Prepared p(scene);
  core::ReceiverCuller sun(p.cull, p.prep[1], 1, scene.lights[0]);
  EXPECT_FALSE(sun.caster_plane_rules_out(0));  // not asked
  sun.use_caster_planes(scene, p.prep);
  EXPECT_TRUE(sun.caster_plane_rules_out(0));
  core::ReceiverCuller extended(p.cull, p.prep[1], 1, scene.lights[1]);
  extended.use_caster_planes(scene, p.prep);
  EXPECT_FALSE(extended.caster_plane_rules_out(0));
}

TEST(CasterPlanes, AWallOnTheGroundIsNoCandidateAWallThroughItIs) {
  // A wall facing the sun (due south, 30 degrees up) on the ground: the ground was a candidate
  // caster (its far part lies in front of the wall's plane) whose cast falls below the wall.
  // Now it is none; the same wall sunk 1 m into the ground keeps it, and the part below the
  // ground is in its shadow: lit 4 x 3 of 4 x 4.
  ShadowOptions options;
  options.threads = 1;
  options.polygons = false;
  options.planes = false;
  for (const Arithmetic arithmetic : {Arithmetic::Exact, Arithmetic::Fast}) {
    for (const double foot : {0.0, -1.0}) {
      Scene scene;
      add_mesh(scene, "ground", {rectangle_z(-50, -50, 50, 50, 0)});
      add_mesh(scene, "wall", {{{0, 0, foot}, {4, 0, foot}, {4, 0, 3}, {0, 0, 3}}});  // facing -y: south
      scene.lights.push_back(directional_light("sun", sun_direction(30, 180)));
      validate_scene(scene);
      options.arithmetic = arithmetic;
      const ShadowResult r = compute_shadows(scene, options);
      const FaceLighting* wall = r.find(1, 0);
      ASSERT_NE(wall, nullptr);
      EXPECT_TRUE(wall->faces_light);
      const std::string label = std::string(arithmetic == Arithmetic::Exact ? "exact" : "fast") + " foot " + std::to_string(foot);
      if (foot == 0.0) {
        EXPECT_EQ(wall->lit_area, 12.0) << label;
        EXPECT_EQ(r.stats.candidate_pairs, 1u) << label;  // the ground's: the wall
      } else {
        EXPECT_NEAR(wall->lit_area, 12.0, wall->lit_area_error_bound) << label;
        if (arithmetic == Arithmetic::Exact) EXPECT_EQ(wall->lit_area, 12.0) << label;
        EXPECT_EQ(r.stats.candidate_pairs, 2u) << label;  // and the wall's: the ground
      }
    }
  }
}

}  // namespace
}  // namespace shadow::test
