// SPDX-License-Identifier: GPL-3.0-or-later
// Pictures of a radiosity result (`shadow render --radiosity`, radiosity_picture.hpp): the
// element values (colour = emittance + RGB reflectance x irradiance), the vertex averages of
// --smooth against hand-worked means, the automatic exposure (no display needed), and pictures
// of a solved room (an X display: ctest runs this under Xvfb) whose pixels must have their
// element's colour, the red wall red and the green wall green, and no wall seen from behind.
#include <shadow/render/radiosity_picture.hpp>

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

namespace sr = shadow::render;
namespace fs = std::filesystem;

namespace {

/// A unit square (face 0) cut along its diagonal into a triangle of area 0.5 and two of 0.25,
/// and one more triangle on face 1 touching the square's corner (1, 0, 0).
shadow::RadiosityFiles three_and_one() {
  shadow::RadiosityFiles files;
  auto add = [&](std::size_t face, std::vector<glm::dvec3> p, double b, glm::dvec3 rgb, double h, double e) {
    shadow::RadiosityElement el;
    el.face_id = face;
    el.polygon = std::move(p);
    const glm::dvec3 n = glm::cross(el.polygon[1] - el.polygon[0], el.polygon[2] - el.polygon[0]);
    el.area = 0.5 * glm::length(n);
    el.radiosity = b;
    el.irradiance = h;
    el.irradiance_rgb = glm::dvec3(h);
    el.emittance = e;
    files.elements.push_back(el);
    files.reflectance_rgb.push_back(rgb);
  };
  // (0,0) (1,0) (1,1) | (0,0) (1,1) (0.5,1) | (0,0) (0.5,1) (0,1)
  add(0, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, 1.0, {0.5, 0.25, 0.125}, 10.0, 0.0);
  add(0, {{0, 0, 0}, {1, 1, 0}, {0.5, 1, 0}}, 3.0, {0.1, 0.2, 0.3}, 20.0, 2.0);
  add(0, {{0, 0, 0}, {0.5, 1, 0}, {0, 1, 0}}, 5.0, {0.0, 0.0, 0.0}, 30.0, 0.0);
  add(1, {{1, 0, 0}, {1, 0, 1}, {2, 0, 0}}, 100.0, {1.0, 1.0, 1.0}, 0.0, 0.0);
  return files;
}

std::size_t point_at(const sr::ColouredMesh& mesh, const glm::dvec3& p, const glm::dvec3& value) {
  std::size_t found = mesh.points.size(), count = 0;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (mesh.points[i] == p && mesh.point_colours[i] == value) found = i, ++count;
  return count == 1 ? found : mesh.points.size();
}

}  // namespace

TEST(RadiosityValues, ColourIsEmittancePlusTheWallColourTimesTheIrradiance) {
  const shadow::RadiosityFiles files = three_and_one();
  const std::vector<glm::dvec3> b = sr::radiosity_element_values(files, sr::RadiosityMode::Radiosity);
  const std::vector<glm::dvec3> h = sr::radiosity_element_values(files, sr::RadiosityMode::Irradiance);
  const std::vector<glm::dvec3> c = sr::radiosity_element_values(files, sr::RadiosityMode::Colour);
  EXPECT_EQ(b[1], glm::dvec3(3.0));
  EXPECT_EQ(h[2], glm::dvec3(30.0));
  EXPECT_EQ(c[0], glm::dvec3(5.0, 2.5, 1.25));
  EXPECT_EQ(c[1], glm::dvec3(2.0 + 2.0, 2.0 + 4.0, 2.0 + 6.0));
  EXPECT_EQ(c[2], glm::dvec3(0.0));
  EXPECT_EQ(sr::parse_radiosity_mode("color"), sr::RadiosityMode::Colour);
  EXPECT_THROW(sr::parse_radiosity_mode("grey"), shadow::InputError);
  // A colour solution: each channel's reflectance times that channel's irradiance.
  shadow::RadiosityFiles coloured = three_and_one();
  coloured.elements[0].irradiance_rgb = {10.0, 20.0, 40.0};
  EXPECT_EQ(sr::radiosity_element_values(coloured, sr::RadiosityMode::Colour)[0], glm::dvec3(5.0, 5.0, 5.0));
}

TEST(RadiosityMesh, FlatKeepsEachElementsValueAndSmoothAveragesSharedVerticesByArea) {
  const shadow::RadiosityFiles files = three_and_one();
  const std::vector<glm::dvec3> b = sr::radiosity_element_values(files, sr::RadiosityMode::Radiosity);
  const sr::ColouredMesh flat = sr::radiosity_value_mesh(files, b, false);
  ASSERT_EQ(flat.triangle_colours.size(), 4u);
  EXPECT_EQ(flat.points.size(), 12u);
  for (std::size_t t = 0; t < 4; ++t) EXPECT_EQ(flat.triangle_colours[t], b[t]);

  const sr::ColouredMesh smooth = sr::radiosity_value_mesh(files, b, true);
  EXPECT_TRUE(smooth.triangle_colours.empty());
  ASSERT_EQ(smooth.triangles.size(), 12u);
  // Face 0 has 5 distinct vertices, face 1 three of its own: (1, 0, 0) is one point per face.
  ASSERT_EQ(smooth.points.size(), 8u);
  // Hand-worked area-weighted means (areas 0.5, 0.25, 0.25; values 1, 3, 5):
  // (0,0): all three: (0.5 + 0.75 + 1.25) / 1 = 2.5; (1,1): the first two: (0.5 + 0.75) / 0.75;
  // (0.5,1): the last two: 4; (1,0) on face 0: 1; (0,1): 5; (1,0) on face 1: 100.
  EXPECT_LT(point_at(smooth, {0, 0, 0}, glm::dvec3(2.5)), 8u);
  EXPECT_LT(point_at(smooth, {1, 1, 0}, glm::dvec3(1.25 / 0.75)), 8u);
  EXPECT_LT(point_at(smooth, {0.5, 1, 0}, glm::dvec3(4.0)), 8u);
  EXPECT_LT(point_at(smooth, {1, 0, 0}, glm::dvec3(1.0)), 8u);
  EXPECT_LT(point_at(smooth, {0, 1, 0}, glm::dvec3(5.0)), 8u);
  EXPECT_LT(point_at(smooth, {1, 0, 0}, glm::dvec3(100.0)), 8u);  // face 1's own: not averaged across faces
}

TEST(RadiosityMesh, ANeighboursVertexOnAnElementsEdgeBecomesOneOfItsVerticesSoThatNoCrackIsLeft) {
  // A's long edge (2,0)-(0,2) has B1's and B2's shared vertex (1,1) inside it: a T-junction.
  shadow::RadiosityFiles files;
  auto add = [&](std::vector<glm::dvec3> p, double b) {
    shadow::RadiosityElement e;
    e.polygon = std::move(p);
    e.area = 0.5 * glm::length(glm::cross(e.polygon[1] - e.polygon[0], e.polygon[2] - e.polygon[0]));
    e.radiosity = b;
    files.elements.push_back(e);
    files.reflectance_rgb.emplace_back(0.5);
  };
  add({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}, 3.0);
  add({{2, 0, 0}, {2, 2, 0}, {1, 1, 0}}, 6.0);
  add({{1, 1, 0}, {2, 2, 0}, {0, 2, 0}}, 9.0);
  const std::vector<glm::dvec3> b = sr::radiosity_element_values(files, sr::RadiosityMode::Radiosity);
  for (bool smooth : {false, true}) {
    const sr::ColouredMesh mesh = sr::radiosity_value_mesh(files, b, smooth);
    const std::size_t triangles = mesh.triangles.size() / 3;
    double area = 0.0;
    for (std::size_t t = 0; t < triangles; ++t) {
      const glm::dvec3 p[3] = {mesh.points[mesh.triangles[3 * t]], mesh.points[mesh.triangles[3 * t + 1]],
                               mesh.points[mesh.triangles[3 * t + 2]]};
      area += 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
      // Conforming: no point of the mesh lies strictly inside an edge of a triangle.
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 a = p[k], d = p[(k + 1) % 3] - a;
        for (const glm::dvec3& q : mesh.points) {
          const double s = glm::dot(q - a, d) / glm::dot(d, d);
          EXPECT_FALSE(s > 1e-9 && s < 1 - 1e-9 && glm::length(q - (a + s * d)) < 1e-12)
              << "smooth " << smooth << ": (" << q.x << ", " << q.y << ") inside an edge of triangle " << t;
        }
      }
    }
    EXPECT_NEAR(area, 4.0, 1e-12) << "smooth " << smooth;  // A 2, B1 1, B2 1: covered once
    EXPECT_EQ(triangles, 4u + 1u + 1u);  // A: a fan of 4 from its centroid
    if (smooth) {
      // (1,1) is a corner of B1 and B2 only: (6 + 9) / 2; A's centroid the mean of its corners:
      // (0,0) 3, (2,0) (3 x 2 + 6 x 1) / 3 = 4, (0,2) (3 x 2 + 9 x 1) / 3 = 5.
      EXPECT_LT(point_at(mesh, {1, 1, 0}, glm::dvec3(7.5)), mesh.points.size());
      EXPECT_LT(point_at(mesh, {2.0 / 3.0, 2.0 / 3.0, 0}, glm::dvec3(4.0)), mesh.points.size());
    }
  }
}

TEST(RadiosityExposure, PutsThe99thPercentileOfTheBrightestChannelAt085) {
  std::vector<glm::dvec3> colours;
  for (int i = 1; i <= 101; ++i) colours.emplace_back(0.1 * i, 0.0, 0.5);  // r: 0.1 ... 10.1
  // rank 0.99 x 100 = 99: the 100th smallest brightest channel, r = 10.0
  EXPECT_DOUBLE_EQ(sr::radiosity_auto_exposure(colours), 0.85 / 10.0);
  EXPECT_EQ(sr::radiosity_auto_exposure({glm::dvec3(0.0)}), 1.0);  // all black: left alone
  EXPECT_DOUBLE_EQ(sr::radiosity_auto_exposure({glm::dvec3(0.01, 0.02, 0.001)}), 42.5);  // up, too
}

namespace {

/// Where `p` lands (x right, y down), by the pinhole camera's definition, written again here.
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

/// A closed 5 m room, fronts inward: red wall at x = 0, green at x = 5, white elsewhere, a
/// 1 m^2 area light under the ceiling (examples/cornell_room.json without its boxes).
constexpr const char* kRoom = R"({
  "materials": [
    {"name": "white", "reflectance": [0.75, 0.75, 0.75]},
    {"name": "red", "reflectance": [0.63, 0.06, 0.04]},
    {"name": "green", "reflectance": [0.15, 0.48, 0.09]}],
  "meshes": [
    {"name": "floor", "material": "white", "polygons": [[[0, 0, 0], [5, 0, 0], [5, 5, 0], [0, 5, 0]]]},
    {"name": "ceiling", "material": "white", "polygons": [[[0, 0, 5], [0, 5, 5], [5, 5, 5], [5, 0, 5]]]},
    {"name": "back", "material": "white", "polygons": [[[0, 5, 0], [5, 5, 0], [5, 5, 5], [0, 5, 5]]]},
    {"name": "front", "material": "white", "polygons": [[[0, 0, 0], [0, 0, 5], [5, 0, 5], [5, 0, 0]]]},
    {"name": "left", "material": "red", "polygons": [[[0, 0, 0], [0, 5, 0], [0, 5, 5], [0, 0, 5]]]},
    {"name": "right", "material": "green", "polygons": [[[5, 0, 0], [5, 0, 5], [5, 5, 5], [5, 5, 0]]]}],
  "lights": [{"name": "lamp", "type": "area", "intensity": 100,
              "polygon": [[2, 2, 4.99], [2, 3, 4.99], [3, 3, 4.99], [3, 2, 4.99]]}]})";

class RadiosityPicture : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sr::display_available()) GTEST_SKIP() << "no X display: run under xvfb-run -a";
    dir_ = fs::temp_directory_path() / ("radiosity-picture-" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "room.json") << kRoom;
    scene_ = shadow::load_scene(dir_ / "room.json");
    shadow::RadiosityOptions options;
    options.max_element_area = 2.0;
    options.tolerance = 0.02;
    options.threads = 2;
    const shadow::RadiosityResult result = shadow::solve_radiosity(scene_, options);
    shadow::write_radiosity_outputs(dir_, scene_, result, shadow::RadiosityRunInfo{});
    files_ = shadow::read_radiosity_files(dir_);
    // From outside, in front of the front wall (whose back it sees): the room inside shows.
    options_.width = 480;
    options_.height = 360;
    options_.shade.camera.eye = {2.5, -9.0, 3.0};
    options_.shade.camera.target = {2.5, 2.5, 2.5};
    options_.shade.camera.up = {0.0, 0.0, 1.0};
    options_.shade.camera.fov_degrees = 40.0;
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  glm::dvec3 colour_at(const sr::Image& image, const glm::dvec3& p) const {
    const glm::dvec2 px = pixel_of(options_.shade.camera, p, image.width, image.height);
    const std::uint8_t* c = image.pixel(static_cast<int>(px.x), static_cast<int>(px.y));
    return glm::dvec3(c[0], c[1], c[2]) / 255.0;
  }
  /// The element of face `face` whose triangle holds `p` (on the face's plane).
  const shadow::RadiosityElement& element_at(std::size_t face, const glm::dvec3& p) const {
    for (const shadow::RadiosityElement& e : files_.elements) {
      if (e.face_id != face) continue;
      const glm::dvec3 n = glm::cross(e.polygon[1] - e.polygon[0], e.polygon[2] - e.polygon[0]);
      bool inside = true;
      for (int k = 0; k < 3; ++k)
        inside = inside && glm::dot(glm::cross(e.polygon[(k + 1) % 3] - e.polygon[k], p - e.polygon[k]), n) > 0;
      if (inside) return e;
    }
    ADD_FAILURE() << "no element of face " << face << " holds the point";
    return files_.elements.front();
  }
  shadow::Scene scene_;
  fs::path dir_;
  shadow::RadiosityFiles files_;
  sr::RenderOptions options_;
};

}  // namespace

TEST_F(RadiosityPicture, EachPixelHasItsElementsRadiosityColourAndTheFrontWallIsSeenThrough) {
  sr::RadiosityPictureOptions picture;
  const sr::Image image = sr::render_radiosity(scene_, files_, options_, picture);
  ASSERT_EQ(image.width, 480);
  ASSERT_EQ(image.height, 360);
  std::vector<double> values;
  for (const shadow::RadiosityElement& e : files_.elements) values.push_back(e.radiosity);
  const sr::ValueScale scale = sr::value_scale(values);
  // Points inside elements, away from their edges: the back wall, the floor, the red wall.
  for (const auto& [face, p] : std::vector<std::pair<std::size_t, glm::dvec3>>{
           {2, {1.3, 5.0, 2.1}}, {0, {3.1, 3.3, 0.0}}, {4, {0.0, 3.4, 1.2}}}) {
    const shadow::RadiosityElement& e = element_at(face, p);
    EXPECT_LT(glm::length(colour_at(image, p) - sr::value_colour(e.radiosity / scale.top)), 3.0 / 255.0)
        << "face " << face << " radiosity " << e.radiosity;
    if (face != 0) continue;
    // The front wall (face 3) stands between the eye and p, seen from behind: were it drawn,
    // the floor's pixel would have its colour, which differs (the floor is under the lamp).
    const glm::dvec3 eye = options_.shade.camera.eye;
    const glm::dvec3 q = eye + (p - eye) * ((0.0 - eye.y) / (p.y - eye.y));
    const shadow::RadiosityElement& front = element_at(3, q);
    EXPECT_GT(glm::length(colour_at(image, p) - sr::value_colour(front.radiosity / scale.top)), 6.0 / 255.0)
        << "face " << face;
  }
}

TEST_F(RadiosityPicture, InColourTheRedWallIsRedTheGreenWallGreenAndTheFloorGrey) {
  sr::RadiosityPictureOptions picture;
  picture.mode = sr::RadiosityMode::Colour;
  for (bool smooth : {false, true}) {
    picture.smooth = smooth;
    sr::RenderOptions options = options_;
    options.shade.exposure.automatic = true;
    options.legend = true;
    const sr::Image image = sr::render_radiosity(scene_, files_, options, picture);
    EXPECT_GT(image.exposure, 0.0);
    const glm::dvec3 red = colour_at(image, {0.0, 3.0, 2.5}), green = colour_at(image, {5.0, 3.0, 2.5}),
                     floor = colour_at(image, {2.5, 2.5, 0.0});
    EXPECT_GT(red.r, red.g + 0.3) << "smooth " << smooth;
    EXPECT_GT(red.r, red.b + 0.3);
    EXPECT_GT(green.g, green.r + 0.2);
    EXPECT_GT(green.g, green.b + 0.2);
    // The white floor under white light takes the walls' colours (the colour solution): red and
    // green from the walls, no blue from anything but the white faces.
    EXPECT_GT(floor.r, floor.b + 0.01) << "smooth " << smooth;
    EXPECT_GT(floor.g, floor.b + 0.01) << "smooth " << smooth;
    EXPECT_GT(floor.r, 0.3);
    // Flat, the red wall's pixel at an element's centroid is its colour through the exposure.
    if (!smooth) {
      const shadow::RadiosityElement& e = element_at(4, {0.0, 3.3, 1.9});
      const glm::dvec3 centroid = (e.polygon[0] + e.polygon[1] + e.polygon[2]) / 3.0;
      const glm::dvec3 expected = sr::expose(glm::dvec3(0.63, 0.06, 0.04) * e.irradiance_rgb, options.shade.exposure, image.exposure);
      glm::dvec3 srgb;
      for (int k = 0; k < 3; ++k)
        srgb[k] = expected[k] <= 0.0031308 ? 12.92 * expected[k] : 1.055 * std::pow(expected[k], 1.0 / 2.4) - 0.055;
      EXPECT_LT(glm::length(colour_at(image, centroid) - srgb), 3.0 / 255.0);
    }
  }
}
