// SPDX-License-Identifier: GPL-3.0-or-later
// Pictures of a value per face (`shadow render --irradiation`, value_picture.hpp): the scale,
// the colour map, the coloured faces (no display needed) and the picture itself (an X display:
// ctest runs this under xvfb-run), whose pixels must have the colour of their face's value.
#include <shadow/render/value_picture.hpp>

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace sr = shadow::render;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A 20 x 20 ground, a 6 x 6 x 8 block on it: its roof (face 1) and its north wall (face 2,
/// facing +y), and a south wall (face 3).
shadow::Scene block_scene() {
  shadow::Scene scene;
  auto add = [&](const std::string& mesh, std::vector<glm::dvec3> vertices) {
    if (scene.meshes.empty() || scene.meshes.back().name != mesh) {
      shadow::Mesh m;
      m.name = mesh;
      m.first_face = scene.faces.size();
      scene.meshes.push_back(m);
    }
    shadow::Face face;
    face.vertices = std::move(vertices);
    face.mesh = scene.meshes.size() - 1;
    scene.faces.push_back(face);
    ++scene.meshes.back().face_count;
  };
  add("ground", {{-7, -7, 0}, {13, -7, 0}, {13, 13, 0}, {-7, 13, 0}});
  add("block", {{0, 0, 8}, {6, 0, 8}, {6, 6, 8}, {0, 6, 8}});
  add("block", {{6, 6, 0}, {0, 6, 0}, {0, 6, 8}, {6, 6, 8}});
  add("block", {{0, 0, 0}, {6, 0, 0}, {6, 0, 8}, {0, 0, 8}});
  return scene;
}

double luminance(const glm::dvec3& srgb) { return 0.2126 * srgb.r + 0.7152 * srgb.g + 0.0722 * srgb.b; }

double polygon_area(const std::vector<glm::dvec3>& p) {
  glm::dvec3 n(0.0);
  for (std::size_t i = 0; i < p.size(); ++i) n += glm::cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * glm::length(n);
}

/// Where `p` lands in the picture (x right, y down from the top), by the pinhole camera's
/// definition (written here again, not taken from the renderer).
glm::dvec2 pixel_of(const sr::Camera& c, const glm::dvec3& p, int width, int height) {
  const glm::dvec3 forward = glm::normalize(c.target - c.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, c.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const glm::dvec3 o = p - c.eye;
  const double depth = glm::dot(o, forward);
  const double half = std::tan(0.5 * c.fov_degrees * M_PI / 180.0);
  const double x = glm::dot(o, right) / (depth * half * width / height), y = glm::dot(o, up) / (depth * half);
  return {0.5 * (x + 1.0) * width, (1.0 - 0.5 * (y + 1.0)) * height};
}

}  // namespace

TEST(ValueScale, RoundStepsFromZeroToAboveTheLargestValue) {
  sr::ValueScale s = sr::value_scale({6.54, 2.39, kNaN, 0.0});
  EXPECT_EQ(s.step, 1.0);
  EXPECT_EQ(s.top, 7.0);
  EXPECT_EQ(s.digits, 0);
  s = sr::value_scale({1234.0, 800.0});
  EXPECT_EQ(s.step, 200.0);
  EXPECT_EQ(s.top, 1400.0);
  s = sr::value_scale({0.034});
  EXPECT_DOUBLE_EQ(s.step, 0.005);
  EXPECT_DOUBLE_EQ(s.top, 0.035);
  EXPECT_EQ(s.digits, 3);
  s = sr::value_scale({kNaN, 0.0});  // nothing received: a scale from 0 to 1
  EXPECT_EQ(s.top, 1.0);
  EXPECT_EQ(s.step, 1.0);
}

TEST(ValueColour, BrightnessGrowsWithTheValueAlongTheWholeScale) {
  double previous = -1.0;
  for (int i = 0; i <= 200; ++i) {
    const double l = luminance(sr::value_colour(i / 200.0));
    EXPECT_GT(l, previous) << "at " << i / 200.0;
    previous = l;
  }
  EXPECT_LT(luminance(sr::value_colour(0.0)), 0.1);
  EXPECT_GT(luminance(sr::value_colour(1.0)), 0.85);
  EXPECT_EQ(sr::value_colour(-3.0), sr::value_colour(0.0));  // clamped
  EXPECT_EQ(sr::value_colour(5.0), sr::value_colour(1.0));
}

TEST(ValueMesh, EveryFaceIsCoveredOnceInTheColourOfItsValue) {
  const shadow::Scene scene = block_scene();
  const std::vector<double> values = {kNaN, 6.5, 2.4, 3.2};
  const sr::ValueScale scale = sr::value_scale(values);
  const sr::ColouredMesh mesh = sr::colour_faces_by_value(scene, values, scale);
  ASSERT_EQ(mesh.triangles.size(), 3 * mesh.triangle_colours.size());
  // Each triangle lies on one face: sum the areas per colour and compare with the faces'.
  auto expected = [&](std::size_t f) {
    const glm::dvec3 srgb = std::isfinite(values[f]) ? sr::value_colour(values[f] / scale.top)
                                                     : glm::dvec3(sr::kNoValueGrey, sr::kNoValueGrey, sr::kNoValueGrey * 0.98);
    glm::dvec3 lin;
    for (int i = 0; i < 3; ++i) lin[i] = srgb[i] <= 0.04045 ? srgb[i] / 12.92 : std::pow((srgb[i] + 0.055) / 1.055, 2.4);
    return lin;
  };
  std::vector<double> area(scene.faces.size(), 0.0);
  for (std::size_t t = 0; t < mesh.triangle_colours.size(); ++t) {
    const std::vector<glm::dvec3> tri = {mesh.points[mesh.triangles[3 * t]], mesh.points[mesh.triangles[3 * t + 1]],
                                         mesh.points[mesh.triangles[3 * t + 2]]};
    std::size_t matched = 0, face = 0;
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      if (glm::length(mesh.triangle_colours[t] - expected(f)) < 1e-12) ++matched, face = f;
    ASSERT_EQ(matched, 1u) << "triangle " << t << " has no single face's colour";
    area[face] += polygon_area(tri);
  }
  for (std::size_t f = 0; f < scene.faces.size(); ++f)
    EXPECT_NEAR(area[f], polygon_area(scene.faces[f].vertices), 1e-9) << "face " << f;
}

class ValuePicture : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sr::display_available()) GTEST_SKIP() << "no X display: run under xvfb-run -a";
  }
};

TEST_F(ValuePicture, TheRoofThatReceivedMoreIsBrighterThanTheNorthWallAndEachHasItsValuesColour) {
  const shadow::Scene scene = block_scene();
  const std::vector<double> values = {kNaN, 6.5, 2.4, 3.2};
  sr::RenderOptions options;
  options.width = 640;
  options.height = 480;
  options.legend = true;
  // From the north-east, above: the roof and the north wall in view, the legend top left.
  options.shade.camera.eye = {30.0, 40.0, 35.0};
  options.shade.camera.target = {3.0, 3.0, 3.0};
  options.shade.camera.up = {0.0, 0.0, 1.0};
  options.shade.camera.fov_degrees = 30.0;
  const sr::Image image = sr::render_face_values(scene, values, options, "total irradiation, kWh/m2");
  ASSERT_EQ(image.width, 640);
  ASSERT_EQ(image.height, 480);
  auto colour_at = [&](const glm::dvec3& p) {
    const glm::dvec2 px = pixel_of(options.shade.camera, p, image.width, image.height);
    const std::uint8_t* c = image.pixel(static_cast<int>(px.x), static_cast<int>(px.y));
    return glm::dvec3(c[0], c[1], c[2]) / 255.0;
  };
  const glm::dvec3 roof = colour_at({3.0, 3.0, 8.0}), wall = colour_at({3.0, 6.0, 4.0}), ground = colour_at({10.0, 10.0, 0.0});
  const sr::ValueScale scale = sr::value_scale(values);
  EXPECT_LT(glm::length(roof - sr::value_colour(6.5 / scale.top)), 3.0 / 255.0);
  EXPECT_LT(glm::length(wall - sr::value_colour(2.4 / scale.top)), 3.0 / 255.0);
  EXPECT_LT(glm::length(ground - glm::dvec3(0.80, 0.80, 0.784)), 3.0 / 255.0);  // no value: grey
  EXPECT_GT(luminance(roof), luminance(wall) + 0.2);
  // The legend's top row: the colour of the scale's top (7), top left.
  bool top_swatch = false;
  for (int y = 0; y < image.height / 4 && !top_swatch; ++y)
    for (int x = 0; x < image.width / 4 && !top_swatch; ++x) {
      const std::uint8_t* c = image.pixel(x, y);
      top_swatch = glm::length(glm::dvec3(c[0], c[1], c[2]) / 255.0 - sr::value_colour(1.0)) < 3.0 / 255.0;
    }
  EXPECT_TRUE(top_swatch) << "no swatch of the scale's top in the legend";
}
