// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow render`'s pieces: the overlay of per-light fragments (no display needed) and the
// pictures (need an X display: ctest runs this under xvfb-run).
#include "render/render_image.hpp"
#include "render/shaded_mesh.hpp"

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
namespace sr = shadow::render;

namespace {

/// A 10 x 10 ground square at z = 0 and a 2 x 2 roof square at z = 1 over the origin, both
/// facing up. A sun along (1, 0, 1) puts the roof's shadow on x in [-2, 0], |y| <= 1; one
/// along (0, 1, 1) on y in [-2, 0], |x| <= 1.
shadow::Scene roof_scene(bool second_sun) {
  shadow::Scene scene;
  scene.meshes = {shadow::Mesh{"ground", "", 0, 1, true}, shadow::Mesh{"roof", "", 1, 1, true}};
  shadow::Face ground;
  ground.vertices = {{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}};
  ground.mesh = 0;
  shadow::Face roof;
  roof.vertices = {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
  roof.mesh = 1;
  scene.faces = {ground, roof};
  shadow::Light east;
  east.name = "east";
  east.to_light = {1, 0, 1};
  scene.lights = {east};
  if (second_sun) {
    shadow::Light north;
    north.name = "north";
    north.to_light = {0, 1, 1};
    scene.lights.push_back(north);
  }
  shadow::validate_scene(scene);
  return scene;
}

double area(const std::vector<glm::dvec3>& polygon) {
  glm::dvec3 n(0.0);
  for (std::size_t i = 0; i < polygon.size(); ++i) n += glm::cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  return 0.5 * glm::length(n);
}

/// Straight down on the scene from 20 above: world x goes right, y up, and the ground's
/// half height in view is 20 tan 20 degrees = 7.28 (200 x 200 pixels).
sr::RenderOptions top_view(shadow::LightingModel model, sr::Shading shading) {
  sr::RenderOptions options;
  options.width = 200;
  options.height = 200;
  options.shade.camera.eye = {0, 0, 20};
  options.shade.camera.target = {0, 0, 0};
  options.shade.camera.up = {0, 1, 0};
  options.shade.camera.fov_degrees = 40.0;
  options.shade.lighting.model = model;
  options.shade.shading = shading;
  return options;
}

/// The pixel where world point (x, y, 0) appears in top_view.
std::pair<int, int> pixel_of(double x, double y) {
  const double half = 20.0 * std::tan(20.0 * M_PI / 180.0);
  return {static_cast<int>(100.0 + 100.0 * x / half), static_cast<int>(100.0 - 100.0 * y / half)};
}

int brightness(const sr::Image& image, double x, double y) {
  const auto [px, py] = pixel_of(x, y);
  const std::uint8_t* p = image.pixel(px, py);
  return p[0] + p[1] + p[2];
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

// ---- the overlay ---------------------------------------------------------------------------------

TEST(Overlay, CellsCoverEachFaceOnceWithTheVisibilityOfEveryLight) {
  const shadow::Scene scene = roof_scene(true);
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  const std::vector<sr::OverlayCell> cells = sr::overlay_fragments(scene, result);
  double ground = 0, both_lit = 0, east_only = 0, north_only = 0, neither = 0, roof = 0;
  for (const sr::OverlayCell& cell : cells) {
    ASSERT_EQ(cell.lit.size(), 2u);
    const double a = area(cell.polygon);
    if (cell.face_id == 1) {
      roof += a;
      EXPECT_TRUE(cell.lit[0] && cell.lit[1]);
      continue;
    }
    ground += a;
    if (cell.lit[0] && cell.lit[1]) both_lit += a;
    else if (cell.lit[0]) east_only += a;
    else if (cell.lit[1]) north_only += a;
    else neither += a;
  }
  // Shadows [-2,0]x[-1,1] (east sun) and [-1,1]x[-2,0] (north sun) overlap on [-1,0]x[-1,0].
  EXPECT_NEAR(ground, 100.0, 1e-9);
  EXPECT_NEAR(roof, 4.0, 1e-12);
  EXPECT_NEAR(neither, 1.0, 1e-9);
  EXPECT_NEAR(east_only, 3.0, 1e-9);   // lit by the east sun, in the north sun's shadow
  EXPECT_NEAR(north_only, 3.0, 1e-9);
  EXPECT_NEAR(both_lit, 93.0, 1e-9);
}

TEST(Overlay, PhongShadingSubdividesToAboutAPixelAndKeepsFlatOneColourPerTriangle) {
  const shadow::Scene scene = roof_scene(false);
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  const auto cells = sr::overlay_fragments(scene, result);
  sr::ShadeOptions options = top_view(shadow::LightingModel::Lambert, sr::Shading::Flat).shade;
  options.image_height = 200;
  const sr::ColouredMesh flat = sr::shade_cells(scene, cells, options);
  EXPECT_EQ(flat.triangle_colours.size() * 3, flat.triangles.size());
  EXPECT_TRUE(flat.point_colours.empty());
  options.shading = sr::Shading::Gouraud;
  const sr::ColouredMesh gouraud = sr::shade_cells(scene, cells, options);
  EXPECT_EQ(gouraud.point_colours.size(), gouraud.points.size());
  options.shading = sr::Shading::Phong;
  const sr::ColouredMesh phong = sr::shade_cells(scene, cells, options);
  EXPECT_EQ(phong.point_colours.size(), phong.points.size());
  // The ground is about 137 pixels wide: cut to 1.5-pixel steps that is thousands of triangles.
  EXPECT_GT(phong.triangles.size() / 3, 5000u);
  EXPECT_GT(phong.triangles.size(), 20 * gouraud.triangles.size());
}

TEST(Camera, TheDefaultCameraHasEveryVertexInViewAndLooksDown) {
  const shadow::Scene scene = roof_scene(false);
  const double aspect = 4.0 / 3.0;
  const sr::Camera camera = sr::default_camera(scene, aspect);
  const glm::dvec3 view = glm::normalize(camera.target - camera.eye);
  EXPECT_LT(view.z, -0.5);  // 40 degrees down
  const glm::dvec3 right = glm::normalize(glm::cross(view, camera.up));
  const glm::dvec3 up = glm::cross(right, view);
  const double tan_v = std::tan(0.5 * camera.fov_degrees * M_PI / 180.0);
  double widest = 0.0;
  for (const shadow::Face& face : scene.faces)
    for (const glm::dvec3& v : face.vertices) {
      const glm::dvec3 o = v - camera.eye;
      const double depth = glm::dot(o, view);
      ASSERT_GT(depth, 0.0);
      const double x = glm::dot(o, right) / (depth * tan_v * aspect);
      const double y = glm::dot(o, up) / (depth * tan_v);
      EXPECT_LE(std::abs(x), 1.0);
      EXPECT_LE(std::abs(y), 1.0);
      widest = std::max({widest, std::abs(x), std::abs(y)});
    }
  EXPECT_GT(widest, 0.9);  // and the scene fills the picture
}

TEST(Shading, NamesRoundTrip) {
  for (sr::Shading s : {sr::Shading::Flat, sr::Shading::Gouraud, sr::Shading::Phong}) {
    sr::Shading parsed = sr::Shading::Flat;
    ASSERT_TRUE(sr::parse_shading(sr::to_string(s), parsed));
    EXPECT_EQ(parsed, s);
  }
  sr::Shading unused;
  EXPECT_FALSE(sr::parse_shading("smooth", unused));
}

// ---- pictures --------------------------------------------------------------------------------------

class RenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sr::display_available()) GTEST_SKIP() << "no X display: run under xvfb-run -a";
  }
};

TEST_F(RenderTest, AShadowedPixelIsDarkerThanALitOne) {
  const shadow::Scene scene = roof_scene(false);
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  for (auto shading : {sr::Shading::Flat, sr::Shading::Gouraud, sr::Shading::Phong}) {
    const sr::Image image = sr::render_scene(scene, result, top_view(shadow::LightingModel::BlinnPhong, shading));
    ASSERT_EQ(image.width, 200);
    ASSERT_EQ(image.height, 200);
    // (-1.5, 0) is in the roof's shadow and not under the roof; (3, 0) and (-3, 0) are lit.
    EXPECT_LT(brightness(image, -1.5, 0.0), brightness(image, 3.0, 0.0)) << sr::to_string(shading);
    EXPECT_LT(brightness(image, -1.5, 0.0), brightness(image, -3.0, 0.0)) << sr::to_string(shading);
    // Shadowed: ambient only, k_a i_a = 0.3 of white, sRGB-encoded: 1.055 * 0.3^(1/2.4) - 0.055
    // = 0.5838, 149 of 255 in each channel.
    EXPECT_NEAR(brightness(image, -1.5, 0.5), 3 * 149, 3) << sr::to_string(shading);
  }
}

TEST_F(RenderTest, TheShadowEdgeIsWhereTheExactShadowSays) {
  const shadow::Scene scene = roof_scene(false);
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  const sr::Image image =
      sr::render_scene(scene, result, top_view(shadow::LightingModel::Lambert, sr::Shading::Flat));
  // The shadow ends at x = -2: a little inside it is dark, a little outside it is lit.
  EXPECT_LT(brightness(image, -1.85, 0.0), brightness(image, -2.15, 0.0));
}

TEST_F(RenderTest, RendersAreDeterministic) {
  const shadow::Scene scene = roof_scene(true);
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  const auto options = top_view(shadow::LightingModel::Phong, sr::Shading::Phong);
  const sr::Image first = sr::render_scene(scene, result, options);
  const sr::Image second = sr::render_scene(scene, result, options);
  EXPECT_EQ(first.rgb, second.rgb);

  const fs::path dir = fs::temp_directory_path() / ("libshadow-test_render-" + std::to_string(getpid()));
  fs::create_directories(dir);
  sr::write_png(first, dir / "a.png");
  sr::write_png(second, dir / "b.png");
  const std::string a = read_bytes(dir / "a.png");
  EXPECT_GT(a.size(), 100u);
  EXPECT_EQ(a, read_bytes(dir / "b.png"));
  fs::remove_all(dir);
}

TEST_F(RenderTest, PhongShadingShowsALampsPoolOfLightThatGouraudInterpolatesAway) {
  // A lamp one unit above the ground, away from the roof: with 1/r^2 it makes a small bright
  // pool. Gouraud only sees the ground cells' far corners; Phong evaluates under the lamp.
  shadow::Scene scene = roof_scene(false);
  shadow::Light lamp;
  lamp.name = "lamp";
  lamp.type = shadow::LightType::Point;
  lamp.position = {3.0, 3.0, 1.0};
  scene.lights = {lamp};
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  auto options = top_view(shadow::LightingModel::Lambert, sr::Shading::Gouraud);
  options.shade.lighting.attenuation = shadow::Attenuation::InverseSquare;
  const sr::Image gouraud = sr::render_scene(scene, result, options);
  options.shade.shading = sr::Shading::Phong;
  const sr::Image phong = sr::render_scene(scene, result, options);
  EXPECT_GT(brightness(phong, 3.0, 3.0), brightness(gouraud, 3.0, 3.0) + 100);
  // Under the lamp: N.L = 1, r = 1: k_a + k_d = 1.0, white.
  EXPECT_GE(brightness(phong, 3.0, 3.0), 3 * 250);
}

TEST_F(RenderTest, TheAmbientModelShowsNoShadow) {
  const shadow::Scene scene = roof_scene(false);
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  const sr::Image image =
      sr::render_scene(scene, result, top_view(shadow::LightingModel::Ambient, sr::Shading::Gouraud));
  EXPECT_EQ(brightness(image, -1.5, 0.0), brightness(image, 3.0, 0.0));
}

TEST(RenderFiles, AnUnwritablePngIsARenderErrorNamingTheFile) {
  sr::Image image;
  image.width = 2;
  image.height = 2;
  image.rgb.assign(12, 0);
  try {
    sr::write_png(image, "/nonexistent-dir/x.png");
    FAIL() << "no error";
  } catch (const sr::RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.png"), std::string::npos) << e.what();
  }
}
