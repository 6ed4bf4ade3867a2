// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow render`'s pieces: the overlay of per-light fragments (no display needed) and the
// pictures (need an X display: ctest runs this under xvfb-run).
#include <shadow/render/camera.hpp>
#include <shadow/render/render_image.hpp>
#include <shadow/render/shaded_mesh.hpp>

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
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

TEST(RenderFiles, AnUnwritablePngIsAnOutputErrorNamingTheFile) {
  // Written like every output (shadow::write_file_staged): an OutputError, exit status 3.
  sr::Image image;
  image.width = 2;
  image.height = 2;
  image.rgb.assign(12, 0);
  try {
    sr::write_png(image, "/nonexistent-dir/x.png");
    FAIL() << "no error";
  } catch (const shadow::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.png"), std::string::npos) << e.what();
  }
}

// ---- the exact overlay: no pinholes ----------------------------------------------------------------

namespace {

/// True when (x, y) is inside the polygon's plan (even-odd rule).
bool inside_plan(const std::vector<glm::dvec3>& polygon, double x, double y) {
  bool in = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const glm::dvec3& a = polygon[i];
    const glm::dvec3& b = polygon[j];
    if ((a.y > y) != (b.y > y) && x < a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y)) in = !in;
  }
  return in;
}

/// Distance in plan from (x, y) to segment a-b.
double plan_distance(const glm::dvec3& a, const glm::dvec3& b, double x, double y) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double length2 = dx * dx + dy * dy;
  double t = length2 > 0 ? ((x - a.x) * dx + (y - a.y) * dy) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(a.x + t * dx - x, a.y + t * dy - y);
}

std::uint8_t srgb_byte(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  const double encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return static_cast<std::uint8_t>(std::lround(255.0 * encoded));
}

}  // namespace

// Seventeen suns on the ground of examples/sun (a June day in Berlin), seen from straight above:
// every ground pixel away from an edge must have the colour its exact fragments say (Lambert,
// directional suns: one grey per combination of lit suns, whatever the shading). The
// double-precision overlay this replaced, with its per-triangle Phong grids, left 3 of these
// 34,318 pixels showing the sky through cracks between cells: pinholes.
TEST_F(RenderTest, EveryGroundPixelHasTheColourOfItsExactFragments) {
  shadow::Scene scene = shadow::load_scene(fs::path(LIBSHADOW_EXAMPLES_DIR) / "sun" / "scene.json");
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  ASSERT_GT(scene.lights.size(), 10u);
  const std::size_t ground = 0;  // the scene's first face
  ASSERT_EQ(scene.meshes[0].name, "ground");

  sr::RenderOptions options;
  options.width = 300;
  options.height = 300;
  options.shade.shading = sr::Shading::Phong;
  options.shade.lighting.model = shadow::LightingModel::Lambert;
  const glm::dvec3 centre(10.0, 10.0, 0.0);  // the ground spans [-20, 40]^2
  const double fov = 20.0;
  const double height = 30.0 / std::tan(0.5 * fov * M_PI / 180.0);  // half width 30 in view
  options.shade.camera.eye = centre + glm::dvec3(0, 0, height);
  options.shade.camera.target = centre;
  options.shade.camera.up = {0, 1, 0};
  options.shade.camera.fov_degrees = fov;
  // Every sun lit: k_a + k_d sum of cosines; scaled to 1 so that no combination is clipped.
  double all = 0.3;
  for (const shadow::Light& light : scene.lights) all += 0.7 * glm::normalize(light.to_light).z;
  options.shade.exposure.scale = 1.0 / all;
  const sr::Image image = sr::render_scene(scene, result, options);

  std::vector<std::vector<const shadow::Fragment*>> by_light(scene.lights.size());
  for (const shadow::Fragment& f : result.fragments)
    if (f.face_id == ground) by_light[f.light_id].push_back(&f);
  const double tan_half = std::tan(0.5 * fov * M_PI / 180.0);
  const double pixel = 2.0 * height * tan_half / options.height;  // on the ground
  std::size_t checked = 0, wrong = 0;
  for (int py = 0; py < image.height; ++py)
    for (int px = 0; px < image.width; ++px) {
      // Where the pixel's centre looks at the ground (the ground plane is z = 0).
      const double sx = (2.0 * (px + 0.5) / image.width - 1.0) * tan_half;
      const double sy = (1.0 - 2.0 * (py + 0.5) / image.height) * tan_half;
      const double x = centre.x + sx * height, y = centre.y + sy * height;
      // Only open ground: off the buildings as seen from the eye (each face projected from the
      // eye onto the ground) and away from their edges.
      bool skip = false;
      for (std::size_t f = 1; f < scene.faces.size() && !skip; ++f) {
        std::vector<glm::dvec3> seen;
        for (const glm::dvec3& v : scene.faces[f].vertices) {
          const glm::dvec3 eye = options.shade.camera.eye;
          seen.push_back(eye + (v - eye) * (eye.z / (eye.z - v.z)));
        }
        skip = inside_plan(seen, x, y);
        for (std::size_t i = 0; i < seen.size() && !skip; ++i)
          skip = plan_distance(seen[i], seen[(i + 1) % seen.size()], x, y) < 2 * pixel;
      }
      if (skip || std::abs(x - 10) > 29 || std::abs(y - 10) > 29) continue;
      std::vector<bool> lit(scene.lights.size(), false);
      bool near_edge = false, found_all = true;
      for (std::size_t k = 0; k < scene.lights.size() && !near_edge; ++k) {
        bool found = false;
        for (const shadow::Fragment* f : by_light[k]) {
          for (std::size_t i = 0; i < f->polygon.size() && !near_edge; ++i)
            near_edge = plan_distance(f->polygon[i], f->polygon[(i + 1) % f->polygon.size()], x, y) < 2 * pixel;
          if (!found && inside_plan(f->polygon, x, y)) {
            found = true;
            lit[k] = f->lit;
          }
        }
        found_all = found_all && found;
      }
      if (near_edge || !found_all) continue;
      double expected = 0.3;
      for (std::size_t k = 0; k < scene.lights.size(); ++k)
        if (lit[k]) expected += 0.7 * glm::normalize(scene.lights[k].to_light).z;
      const int want = srgb_byte(expected / all);
      const std::uint8_t* p = image.pixel(px, py);
      ++checked;
      if (std::abs(p[0] - want) > 2 || std::abs(p[1] - want) > 2 || std::abs(p[2] - want) > 2) {
        ++wrong;
        if (std::getenv("LIBSHADOW_TEST_VERBOSE"))
          std::printf("wrong %d %d (%.3f %.3f): %d %d %d want %d\n", px, py, x, y, p[0], p[1], p[2], want);
      }
    }
  EXPECT_GT(checked, 20000u);
  EXPECT_EQ(wrong, 0u) << "of " << checked << " ground pixels";
}

// ---- `shadow render`'s defaults on a scene without materials (issue 17) ----------------------------

namespace {

struct Png {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // rows from the top
  const std::uint8_t* pixel(int x, int y) const { return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x); }
};

/// Reads a PNG back with VTK's reader (rows from the top).
Png read_png(const fs::path& path) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.string().c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  Png png;
  png.width = dims[0];
  png.height = dims[1];
  const int components = image->GetNumberOfScalarComponents();
  png.rgb.resize(static_cast<std::size_t>(3) * dims[0] * dims[1]);
  for (int y = 0; y < dims[1]; ++y)
    for (int x = 0; x < dims[0]; ++x)
      for (int c = 0; c < 3; ++c)
        png.rgb[3 * (static_cast<std::size_t>(y) * dims[0] + x) + c] =
            static_cast<std::uint8_t>(image->GetScalarComponentAsDouble(x, dims[1] - 1 - y, 0, std::min(c, components - 1)));
  return png;
}

/// Runs the `shadow` program; its exit status.
int run_shadow(const std::string& arguments) {
  const std::string command = std::string("'") + LIBSHADOW_SHADOW_EXE + "' " + arguments + " > /dev/null";
  return std::system(command.c_str());
}

double linear(std::uint8_t byte) {
  const double c = byte / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// Relative luminance (Rec. 709 weights on linear RGB).
double luminance(const std::uint8_t* p) { return 0.2126 * linear(p[0]) + 0.7152 * linear(p[1]) + 0.0722 * linear(p[2]); }

/// True when the segment from `from` to `to` meets the axis-aligned box [lo, hi] (slabs).
bool segment_meets_box(const glm::dvec3& from, const glm::dvec3& to, const glm::dvec3& lo, const glm::dvec3& hi) {
  double t0 = 0.0, t1 = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double d = to[a] - from[a];
    if (d == 0.0) {
      if (from[a] < lo[a] || from[a] > hi[a]) return false;
      continue;
    }
    double u = (lo[a] - from[a]) / d, v = (hi[a] - from[a]) / d;
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u);
    t1 = std::min(t1, v);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace

// examples/gallery/boxes.json: three boxes on a 60 m ground under one sun, no materials.
TEST_F(RenderTest, TheDefaultsReadWellOnASceneWithoutMaterials) {
  const fs::path gallery = fs::path(LIBSHADOW_EXAMPLES_DIR) / "gallery";
  const fs::path scene_file = gallery / "boxes.json";
  const fs::path dir = fs::temp_directory_path() / ("libshadow-test_render-defaults-" + std::to_string(getpid()));
  fs::create_directories(dir);
  auto render = [&](const fs::path& scene, const std::string& name, const std::string& options) {
    EXPECT_EQ(run_shadow("render '" + scene.string() + "' -o '" + (dir / name).string() + "' " + options), 0);
    return read_png(dir / name);
  };
  const Png now = render(scene_file, "boxes.png", "");
  // A sun and a lamp: now, and in the look before issue 17 (white material, the models'
  // values clipped at 1, the whole scene framed).
  const Png two_lights = render(gallery / "sun_and_lamp.json", "two.png", "");
  const Png two_lights_before =
      render(gallery / "sun_and_lamp.json", "two-old.png", "--colours white --exposure 1 --tone clip --frame scene");
  fs::remove_all(dir);
  ASSERT_EQ(now.width, 800);
  ASSERT_EQ(now.height, 600);

  // The sky (RenderOptions::background, 0.93, 0.95, 0.98 as bytes); the side-lit camera of
  // issue 31 may have ground in the picture's corners.
  const std::uint8_t background[3] = {237, 242, 250};
  auto is_background = [&](const std::uint8_t* p) { return std::equal(p, p + 3, background); };
  // The share of the model's pixels clipped to white, and the model's share of the frame.
  auto clipped_share = [&](const Png& png) {
    std::size_t model = 0, white = 0;
    for (int y = 0; y < png.height; ++y)
      for (int x = 0; x < png.width; ++x) {
        const std::uint8_t* p = png.pixel(x, y);
        if (is_background(p)) continue;
        ++model;
        if (p[0] >= 254 && p[1] >= 254 && p[2] >= 254) ++white;
      }
    return std::make_pair(static_cast<double>(white) / std::max<std::size_t>(model, 1),
                          static_cast<double>(model) / (png.width * png.height));
  };
  const auto [white_now, model_now] = clipped_share(now);
  const auto [white_two, model_two] = clipped_share(two_lights);
  const auto [white_two_before, model_two_before] = clipped_share(two_lights_before);
  std::printf("clipped to white: boxes %.2f%%, sun and lamp %.2f%% (before: %.2f%%) of the model's pixels; "
              "model %.0f%% and %.0f%% of the frame (before: %.0f%%)\n",
              100 * white_now, 100 * white_two, 100 * white_two_before, 100 * model_now, 100 * model_two,
              100 * model_two_before);
  EXPECT_LT(white_now, 0.01);  // issue 17: less than 1% of the model's pixels clipped to white
  EXPECT_LT(white_two, 0.01);
  // where the old look clipped a good part of it (17% from the old viewpoint, 5.2% from the
  // side-lit one of issue 31, which sees the lamp-lit walls at a slant)
  EXPECT_GT(white_two_before, 0.03);
  EXPECT_GT(model_now, 0.9);         // the model (ground included) fills the frame
  EXPECT_GT(model_two, 0.6);         // the lamp's long shadows leave a corner of sky

  // The boxes (everything but the ground) fill a stated share of the frame: their projected
  // extent is at least 60% of the picture's width or height.
  shadow::Scene scene = shadow::load_scene(scene_file);
  const sr::Camera camera = sr::resolve_camera(scene, sr::CameraRequest{}, 800.0 / 600.0);
  const glm::dvec3 view = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(view, camera.up));
  const glm::dvec3 up = glm::cross(right, view);
  const double tan_v = std::tan(0.5 * camera.fov_degrees * M_PI / 180.0), tan_h = tan_v * 800.0 / 600.0;
  double x_lo = 1, x_hi = -1, y_lo = 1, y_hi = -1;
  std::vector<std::pair<glm::dvec3, glm::dvec3>> boxes;  // the boxes' bounds, for occlusion
  for (std::size_t m = 1; m < scene.meshes.size(); ++m) {
    glm::dvec3 lo(1e300), hi(-1e300);
    for (std::size_t f = scene.meshes[m].first_face; f < scene.meshes[m].first_face + scene.meshes[m].face_count; ++f)
      for (const glm::dvec3& v : scene.faces[f].vertices) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
        const glm::dvec3 o = v - camera.eye;
        const double depth = glm::dot(o, view);
        x_lo = std::min(x_lo, glm::dot(o, right) / (depth * tan_h));
        x_hi = std::max(x_hi, glm::dot(o, right) / (depth * tan_h));
        y_lo = std::min(y_lo, glm::dot(o, up) / (depth * tan_v));
        y_hi = std::max(y_hi, glm::dot(o, up) / (depth * tan_v));
      }
    boxes.emplace_back(lo, hi);
  }
  const double extent = std::max(0.5 * (x_hi - x_lo), 0.5 * (y_hi - y_lo));
  std::printf("boxes: %.0f%% of the frame's width, %.0f%% of its height\n", 50 * (x_hi - x_lo), 50 * (y_hi - y_lo));
  EXPECT_GE(extent, 0.6);
  EXPECT_LE(std::max({-x_lo, x_hi, -y_lo, y_hi}), 1.0);  // and all in view

  // Lit and shadowed ground tell apart: mean luminance of open ground pixels (seen directly,
  // 2 pixels from any shadow edge) in the sun and in the boxes' shadows. With the palette's
  // k_a = 0.25, k_d = 0.75 and the sun 41.8 degrees up (sin = 0.667), Lambert alone gives
  // (0.25 + 0.75 * 0.667) / 0.25 = 3.0; Blinn-Phong's highlight (k_s = 0.1) adds to the lit side.
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  std::vector<const shadow::Fragment*> ground;
  for (const shadow::Fragment& f : result.fragments)
    if (f.face_id == 0) ground.push_back(&f);
  double lit_sum = 0, shadow_sum = 0;
  std::size_t lit_count = 0, shadow_count = 0;
  for (int py = 0; py < now.height; py += 2)
    for (int px = 0; px < now.width; px += 2) {
      const glm::dvec3 ray = view + (2.0 * (px + 0.5) / now.width - 1.0) * tan_h * right +
                             (1.0 - 2.0 * (py + 0.5) / now.height) * tan_v * up;
      if (!(ray.z < 0)) continue;
      const glm::dvec3 hit = camera.eye + ray * (-camera.eye.z / ray.z);
      if (std::abs(hit.x) > 29 || std::abs(hit.y) > 29) continue;
      bool hidden = false;
      for (const auto& [lo, hi] : boxes) hidden = hidden || segment_meets_box(camera.eye, hit, lo - 0.3, hi + 0.3);
      if (hidden) continue;
      const double pixel = 2.0 * glm::length(hit - camera.eye) * tan_v / now.height;
      bool near_edge = false, lit = false, found = false;
      for (const shadow::Fragment* f : ground) {
        for (std::size_t i = 0; i < f->polygon.size(); ++i)
          near_edge = near_edge || plan_distance(f->polygon[i], f->polygon[(i + 1) % f->polygon.size()], hit.x, hit.y) < 3 * pixel;
        if (inside_plan(f->polygon, hit.x, hit.y)) {
          found = true;
          lit = f->lit;
        }
      }
      if (near_edge || !found) continue;
      const double l = luminance(now.pixel(px, py));
      if (lit) {
        lit_sum += l;
        ++lit_count;
      } else {
        shadow_sum += l;
        ++shadow_count;
      }
    }
  ASSERT_GT(lit_count, 1000u);
  ASSERT_GT(shadow_count, 500u);
  const double ratio = (lit_sum / lit_count) / (shadow_sum / shadow_count);
  std::printf("ground: lit/shadowed luminance %.2f (%zu and %zu pixels sampled)\n", ratio, lit_count, shadow_count);
  EXPECT_GT(ratio, 2.5);
  EXPECT_LT(ratio, 4.5);
}

// ---- the camera shared by the raster and vector views (shadow/render/camera.hpp) --------------------

TEST(Camera, TheGroundIsFoundByNameOrByShape) {
  shadow::Scene scene = roof_scene(false);  // "ground" and "roof"
  EXPECT_EQ(sr::ground_mesh(scene), std::optional<std::size_t>(0));
  const auto roles = sr::mesh_roles(scene);
  EXPECT_EQ(roles[0], sr::MeshRole::Ground);
  EXPECT_EQ(roles[1], sr::MeshRole::Building);  // "roof" is named like a building
  // Renamed: found by shape (upward, lowest, larger in plan than the rest).
  scene.meshes[0].name = "mesh A";
  scene.meshes[1].name = "mesh B";
  EXPECT_EQ(sr::ground_mesh(scene), std::optional<std::size_t>(0));
  EXPECT_EQ(sr::mesh_roles(scene)[1], sr::MeshRole::Other);
  // A roof larger than the ground is not a ground under it; nor is a lone mesh.
  for (glm::dvec3& v : scene.faces[1].vertices) v *= glm::dvec3(10.0, 10.0, 1.0);
  EXPECT_FALSE(sr::ground_mesh(scene).has_value());
  scene.meshes.resize(1);
  scene.faces.resize(1);
  EXPECT_FALSE(sr::ground_mesh(scene).has_value());
}

TEST(Camera, TheDefaultFramesTheModelAndItsShadowsNotTheWholeGround) {
  // The roof's shadow under the sun along (1, 0, 1) lies on x in [-2, 0], |y| <= 1: framed are the
  // roof's corners and its shadow, within [-2, 1] x [-1, 1], not the 10 x 10 ground.
  const shadow::Scene scene = roof_scene(false);
  const std::vector<glm::dvec3> points = sr::framed_points(scene, sr::Framing::Shadows);
  ASSERT_FALSE(points.empty());
  for (const glm::dvec3& p : points) {
    EXPECT_GE(p.x, -2.0 - 1e-12);
    EXPECT_LE(p.x, 1.0 + 1e-12);
    EXPECT_LE(std::abs(p.y), 1.0 + 1e-12);
  }
  bool shadow_tip = false;  // the far end of the shadow is among them
  for (const glm::dvec3& p : points) shadow_tip = shadow_tip || (std::abs(p.x + 2.0) < 1e-12 && p.z == 0.0);
  EXPECT_TRUE(shadow_tip);
  EXPECT_EQ(sr::framed_points(scene, sr::Framing::Scene).size(), 8u);  // every vertex
  // The shadows' framing comes closer than the whole-scene framing.
  const sr::Camera near = sr::resolve_camera(scene, sr::CameraRequest{}, 4.0 / 3.0);
  sr::CameraRequest whole;
  whole.framing = sr::Framing::Scene;
  const sr::Camera far = sr::resolve_camera(scene, whole, 4.0 / 3.0);
  EXPECT_LT(glm::length(near.eye - near.target), 0.6 * glm::length(far.eye - far.target));
}

TEST(Camera, TheSceneCameraThenTheRequestReplaceTheDefaultAndBadViewsAreInputErrors) {
  shadow::Scene scene = roof_scene(false);
  shadow::Camera given;
  given.eye = glm::dvec3(0, -20, 5);
  given.fov_degrees = 50.0;
  scene.camera = given;
  sr::CameraRequest request;
  request.scene_file = "scene.json";
  sr::Camera camera = sr::resolve_camera(scene, request, 1.0);
  EXPECT_EQ(camera.eye, glm::dvec3(0, -20, 5));
  EXPECT_EQ(camera.fov_degrees, 50.0);
  request.eye = glm::dvec3(3, 3, 3);
  request.fov_degrees = 20.0;
  camera = sr::resolve_camera(scene, request, 1.0);
  EXPECT_EQ(camera.eye, glm::dvec3(3, 3, 3));
  EXPECT_EQ(camera.fov_degrees, 20.0);
  request.target = glm::dvec3(3, 3, 3);
  try {
    (void)sr::resolve_camera(scene, request, 1.0);
    FAIL() << "no error";
  } catch (const shadow::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--eye/--target"), std::string::npos) << e.what();
  }
  request = sr::CameraRequest{};
  request.scene_file = "scene.json";
  scene.camera->up = glm::dvec3(0, 0, 0);
  try {
    (void)sr::resolve_camera(scene, request, 1.0);
    FAIL() << "no error";
  } catch (const shadow::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json: camera.up"), std::string::npos) << e.what();
  }
}

TEST(Palette, SceneMaterialsWinAndMeshesWithoutOneGetColoursByRole) {
  shadow::Scene scene = roof_scene(false);
  const sr::Palette palette;
  std::vector<shadow::Material> materials = sr::display_materials(scene, palette);
  EXPECT_EQ(materials[0].color, palette.ground);
  EXPECT_EQ(materials[1].color, palette.building);
  EXPECT_EQ(materials[0].k_a, palette.k_a);
  // Without the palette: the models' white default.
  EXPECT_EQ(sr::display_materials(scene, std::nullopt)[0].color, glm::dvec3(1.0));
  // A named material wins.
  shadow::Material red;
  red.name = "red";
  red.color = {1, 0, 0};
  scene.materials = {red};
  scene.meshes[1].material = "red";
  materials = sr::display_materials(scene, palette);
  EXPECT_EQ(materials[1].color, glm::dvec3(1, 0, 0));
  EXPECT_EQ(materials[0].color, palette.ground);
}

TEST_F(RenderTest, TheLegendAndTheCompassAreDrawnInTheirCorners) {
  const fs::path scene_file = fs::path(LIBSHADOW_EXAMPLES_DIR) / "gallery" / "sun_and_lamp.json";
  const fs::path dir = fs::temp_directory_path() / ("libshadow-test_render-legend-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string base = "render '" + scene_file.string() + "' --width 400 --height 300 -o '";
  ASSERT_EQ(run_shadow(base + (dir / "plain.png").string() + "' --compass off"), 0);
  ASSERT_EQ(run_shadow(base + (dir / "marked.png").string() + "' --legend --compass on"), 0);
  const Png plain = read_png(dir / "plain.png"), marked = read_png(dir / "marked.png");
  fs::remove_all(dir);
  // The legend's white panel top left, the compass's white disk bottom right.
  auto white_share = [](const Png& png, int x0, int y0, int x1, int y1) {
    std::size_t white = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const std::uint8_t* p = png.pixel(x, y);
        white += p[0] == 255 && p[1] == 255 && p[2] == 255;
      }
    return static_cast<double>(white) / ((x1 - x0) * (y1 - y0));
  };
  EXPECT_GT(white_share(marked, 5, 5, 60, 30), 0.3);
  EXPECT_LT(white_share(plain, 5, 5, 60, 30), 0.01);
  // The compass: radius 16 at 300 pixels high, 7 from the corner; its disk around the centre.
  const int cx = 400 - 16 - 7, cy = 300 - 16 - 7;
  EXPECT_GT(white_share(marked, cx - 14, cy - 14, cx + 14, cy + 14), 0.3);
  EXPECT_LT(white_share(plain, cx - 14, cy - 14, cx + 14, cy + 14), 0.01);
}

// The exact overlay against the engine's own areas, two methods: on every face of examples/sun
// (17 suns) and examples/default (a sun and a lamp, a wall with a window), the cells cover the
// face once (their areas add up to the face's), and for every light the cells lit by it add up
// to the engine's exact lit area (FaceLighting::lit_area, computed from the exact regions, not
// from the fragments).
TEST(Overlay, TheExactOverlayAddsUpToTheEnginesAreasForEveryLight) {
  for (const char* name : {"sun", "default"}) {
    const shadow::Scene scene = shadow::load_scene(fs::path(LIBSHADOW_EXAMPLES_DIR) / name / "scene.json");
    const shadow::ShadowResult result = shadow::compute_shadows(scene);
    const std::vector<sr::OverlayCell> cells = sr::overlay_fragments(scene, result);
    std::vector<double> covered(scene.faces.size(), 0.0);
    std::vector<std::vector<double>> lit(scene.faces.size(), std::vector<double>(scene.lights.size(), 0.0));
    for (const sr::OverlayCell& cell : cells) {
      const double a = area(cell.polygon);
      covered[cell.face_id] += a;
      for (std::size_t k = 0; k < scene.lights.size(); ++k)
        if (cell.lit[k]) lit[cell.face_id][k] += a;
    }
    for (const shadow::FaceLighting& entry : result.lighting) {
      const double tolerance = 1e-9 * std::max(1.0, entry.area) + entry.dropped_area;
      EXPECT_NEAR(covered[entry.face_id], entry.area, tolerance) << name << " face " << entry.face_id;
      EXPECT_NEAR(lit[entry.face_id][entry.light_id], entry.lit_area, tolerance)
          << name << " face " << entry.face_id << " light " << entry.light_id;
    }
  }
}

// ---- colours by what the model says a face is (issue 31, item 12) ----------------------------------

namespace {

/// A small CityJSON 2.0 city written as real ones are (transform, integer vertices, semantics):
/// a 40 x 40 m TINRelief at z = 0, a 6 m Building (a Solid with roof, wall and ground semantic
/// surfaces) at x, y in [-10, -4], and 0.3 m high slabs of a PlantCover at x in [4, 10],
/// y in [-10, -4], a WaterBody at x in [-10, -4], y in [4, 10] and a Road at x, y in [4, 10].
/// Every city object id is a UUID-like name that says nothing of its type.
std::string small_city() {
  std::vector<glm::dvec3> vertices;
  auto v = [&](double x, double y, double z) {
    vertices.emplace_back(x, y, z);
    return std::to_string(vertices.size() - 1);
  };
  auto quad = [&](double x0, double y0, double x1, double y1, double z) {  // upward
    return "[[" + v(x0, y0, z) + "," + v(x1, y0, z) + "," + v(x1, y1, z) + "," + v(x0, y1, z) + "]]";
  };
  std::string objects;
  auto object = [&](const std::string& id, const std::string& type, const std::string& geometry) {
    objects += std::string(objects.empty() ? "" : ",") + "\"" + id + "\":{\"type\":\"" + type +
               "\",\"geometry\":[" + geometry + "]}";
  };
  object("{0A1B2C3D-0000-4000-8000-000000000001}", "TINRelief",
         "{\"type\":\"CompositeSurface\",\"lod\":\"1\",\"boundaries\":[" + quad(-20, -20, 20, 20, 0) + "]}");
  // The building: a box, its faces outward, with semantics.
  {
    const double x0 = -10, y0 = -10, x1 = -4, y1 = -4, h = 6;
    const std::string a = v(x0, y0, 0), b = v(x1, y0, 0), c = v(x1, y1, 0), d = v(x0, y1, 0);
    const std::string e = v(x0, y0, h), f = v(x1, y0, h), g = v(x1, y1, h), k = v(x0, y1, h);
    const std::string shell = "[[[" + a + "," + d + "," + c + "," + b + "]],[[" + e + "," + f + "," + g + "," + k +
                              "]],[[" + a + "," + b + "," + f + "," + e + "]],[[" + b + "," + c + "," + g + "," + f +
                              "]],[[" + c + "," + d + "," + k + "," + g + "]],[[" + d + "," + a + "," + e + "," + k + "]]]";
    object("{0A1B2C3D-0000-4000-8000-000000000002}", "Building",
           "{\"type\":\"Solid\",\"lod\":\"2.2\",\"boundaries\":[" + shell +
               "],\"semantics\":{\"surfaces\":[{\"type\":\"GroundSurface\"},{\"type\":\"RoofSurface\"},"
               "{\"type\":\"WallSurface\"}],\"values\":[[0,1,2,2,2,2]]}}");
  }
  object("{0A1B2C3D-0000-4000-8000-000000000003}", "PlantCover",
         "{\"type\":\"MultiSurface\",\"lod\":\"1\",\"boundaries\":[" + quad(4, -10, 10, -4, 0.3) + "]}");
  object("{0A1B2C3D-0000-4000-8000-000000000004}", "WaterBody",
         "{\"type\":\"MultiSurface\",\"lod\":\"1\",\"boundaries\":[" + quad(-10, 4, -4, 10, 0.3) + "]}");
  object("{0A1B2C3D-0000-4000-8000-000000000005}", "Road",
         "{\"type\":\"MultiSurface\",\"lod\":\"1\",\"boundaries\":[" + quad(4, 4, 10, 10, 0.3) + "]}");
  std::string text = "{\"type\":\"CityJSON\",\"version\":\"2.0\",\"transform\":{\"scale\":[0.001,0.001,0.001],"
                     "\"translate\":[0.0,0.0,0.0]},\"CityObjects\":{" +
                     objects + "},\"vertices\":[";
  for (std::size_t i = 0; i < vertices.size(); ++i)
    text += std::string(i ? "," : "") + "[" + std::to_string(std::lround(vertices[i].x * 1000)) + "," +
            std::to_string(std::lround(vertices[i].y * 1000)) + "," + std::to_string(std::lround(vertices[i].z * 1000)) + "]";
  return text + "]}";
}

/// The small city as a scene with a sun (a CityJSON file brings no lights).
fs::path write_small_city(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "city.city.json") << small_city();
  std::ofstream(dir / "scene.json")
      << R"({"meshes": [{"name": "city", "file": "city.city.json"}],
             "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1.0]}]})";
  return dir / "scene.json";
}

/// The label of each face's display group.
std::vector<std::string> face_labels(const shadow::Scene& scene) {
  const sr::DisplayGroups groups = sr::display_groups(scene, sr::Palette{});
  std::vector<std::string> labels;
  for (std::size_t g : groups.face_group) labels.push_back(groups.groups[g].label);
  return labels;
}

}  // namespace

TEST(Palette, CityObjectsAreColouredAndLabelledByTheirType) {
  const fs::path dir = fs::temp_directory_path() / ("libshadow-test_render-city-" + std::to_string(getpid()));
  const shadow::Scene scene = shadow::load_scene(write_small_city(dir));
  fs::remove_all(dir);
  ASSERT_EQ(scene.meshes.size(), 5u);
  EXPECT_EQ(scene.meshes[0].object_type, "TINRelief");
  EXPECT_EQ(scene.meshes[1].object_type, "Building");
  // The terrain is the ground (the framing's plane), whatever its id.
  EXPECT_EQ(sr::ground_mesh(scene), std::optional<std::size_t>(0));
  const sr::DisplayGroups groups = sr::display_groups(scene, sr::Palette{});
  std::vector<std::string> labels;
  for (const sr::DisplayGroup& g : groups.groups) labels.push_back(g.label);
  // One group per type, labelled by it: no UUID in any label.
  EXPECT_EQ(labels, (std::vector<std::string>{"terrain", "buildings", "roofs", "vegetation", "water", "roads"}));
  const sr::Palette palette;
  auto colour_of = [&](std::size_t mesh) {
    return groups.groups[groups.face_group[scene.meshes[mesh].first_face]].material.color;
  };
  EXPECT_EQ(colour_of(0), palette.ground);
  EXPECT_EQ(colour_of(2), palette.vegetation);
  EXPECT_EQ(colour_of(3), palette.water);
  EXPECT_EQ(colour_of(4), palette.road);
  // The building's roof in the roof colour, its walls in the building colour.
  for (std::size_t f = scene.meshes[1].first_face; f < scene.meshes[1].first_face + scene.meshes[1].face_count; ++f) {
    const glm::dvec3 c = groups.groups[groups.face_group[f]].material.color;
    EXPECT_EQ(c, scene.faces[f].kind == "RoofSurface" ? palette.roof : palette.building) << scene.faces[f].kind;
  }
  // Without the palette: white, labelled by the meshes as before.
  const sr::DisplayGroups white = sr::display_groups(scene, std::nullopt);
  ASSERT_EQ(white.groups.size(), 1u);
  EXPECT_EQ(white.groups[0].material.color, glm::dvec3(1.0));
}

TEST(Palette, EnergyPlusWindowsAreGlassAndShadingIsShadingNotGround) {
  const shadow::Scene scene = shadow::load_scene(fs::path(LIBSHADOW_EXAMPLES_DIR) / "energyplus" / "scene.json");
  const std::vector<std::string> labels = face_labels(scene);
  const sr::DisplayGroups groups = sr::display_groups(scene, sr::Palette{});
  std::size_t windows = 0, walls = 0, shading = 0;
  glm::dvec3 window_colour(-1.0), wall_colour(-1.0);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const std::string& kind = scene.faces[f].kind;
    const shadow::Material& m = groups.groups[groups.face_group[f]].material;
    if (kind == "Window") {
      ++windows;
      EXPECT_EQ(labels[f], "windows (glass)");
      window_colour = m.color;
      EXPECT_GT(m.k_s, sr::Palette{}.k_s);  // glass shines
    } else if (kind == "Wall") {
      ++walls;
      EXPECT_EQ(labels[f], "walls");
      wall_colour = m.color;
    } else if (kind == "Shading") {
      ++shading;
      EXPECT_EQ(labels[f], "shading");
    } else if (kind == "Roof") {
      EXPECT_EQ(labels[f], "roofs");
    } else if (kind == "Door") {
      EXPECT_EQ(labels[f], "doors");
    }
  }
  EXPECT_EQ(windows, 2u);
  EXPECT_GE(walls, 4u);
  EXPECT_GE(shading, 5u);
  // Windows and walls far apart in colour: blue glass, sand walls.
  EXPECT_GT(glm::length(window_colour - wall_colour), 0.3);
  EXPECT_GT(window_colour.b, window_colour.r);
  // "Shading:Site" is a name like a site, but the model says it is shading: not the ground.
  const std::optional<std::size_t> ground = sr::ground_mesh(scene);
  if (ground) EXPECT_EQ(scene.meshes[*ground].name.find("Shading"), std::string::npos) << scene.meshes[*ground].name;
  // The legend lists the types, not the meshes.
  sr::RenderOptions options;
  options.legend = true;
  options.shade.palette = sr::Palette{};
  const sr::Decorations d = sr::make_decorations(scene, options, 1.0);
  std::vector<std::string> rows;
  for (const sr::LegendEntry& e : d.legend) rows.push_back(e.label);
  for (const char* type : {"walls", "roofs", "windows (glass)", "doors", "shading"})
    EXPECT_NE(std::find(rows.begin(), rows.end(), type), rows.end()) << type;
  for (const std::string& row : rows) EXPECT_EQ(row.find("ground"), std::string::npos) << row;
}

// Seen from straight above, each city object's pixels have its type's colour: terrain sage,
// vegetation green, water blue, road grey, the roof terracotta (not a colour per mesh in turn).
TEST_F(RenderTest, ACityIsDrawnInTheColoursOfItsObjectTypes) {
  const fs::path dir = fs::temp_directory_path() / ("libshadow-test_render-city-png-" + std::to_string(getpid()));
  const fs::path scene = write_small_city(dir);
  const fs::path png_file = dir / "city.png";
  // 20 m above the slabs' tops (z = 0.3): world (x, y) at pixel 100 + 100 x / (59.7 tan 20).
  ASSERT_EQ(run_shadow("render '" + scene.string() + "' -o '" + png_file.string() +
                       "' --width 200 --height 200 --eye 0,0,60 --target 0,0,0 --up 0,1,0 --fov 40 "
                       "--compass off --shading flat --model lambert"),
            0);
  const Png png = read_png(png_file);
  fs::remove_all(dir);
  auto at = [&](double x, double y, double z) {
    const double half = (60.0 - z) * std::tan(20.0 * M_PI / 180.0);
    const std::uint8_t* p = png.pixel(static_cast<int>(100 + 100 * x / half), static_cast<int>(100 - 100 * y / half));
    return glm::ivec3(p[0], p[1], p[2]);
  };
  const glm::ivec3 terrain = at(0, 0, 0), vegetation = at(7, -7, 0.3), water = at(-7, 7, 0.3), road = at(7, 7, 0.3),
                   roof = at(-7, -7, 6);
  // Each type in its hue.
  EXPECT_GT(vegetation.g, vegetation.r + 20);
  EXPECT_GT(vegetation.g, vegetation.b + 20);
  EXPECT_GT(water.b, water.r + 40);
  EXPECT_GT(water.b, water.g + 20);
  EXPECT_LT(std::abs(road.r - road.b), 12);  // grey
  EXPECT_GT(roof.r, roof.g + 30);            // terracotta
  EXPECT_GT(terrain.g, terrain.b + 15);      // sage
  // And every pair apart.
  const std::vector<glm::ivec3> all = {terrain, vegetation, water, road, roof};
  for (std::size_t i = 0; i < all.size(); ++i)
    for (std::size_t j = i + 1; j < all.size(); ++j) {
      const glm::ivec3 d = all[i] - all[j];
      EXPECT_GT(std::abs(d.r) + std::abs(d.g) + std::abs(d.b), 30) << i << " " << j;
    }
}

// A city sample with one building far from the rest (cjio's Rotterdam subset: 15 buildings in
// 80 m, one 650 m away) is framed on the rest; Framing::Scene still frames every vertex.
TEST(Camera, AStrayMeshFarFromTheRestIsLeftOutOfTheDefaultFraming) {
  auto strays = [](const shadow::Scene& s) {
    const std::vector<char> stray = sr::stray_meshes(s, std::nullopt);
    return std::count(stray.begin(), stray.end(), 1);
  };
  shadow::Scene scene;
  auto add_roof = [&](double x, double y) {
    shadow::Mesh mesh;
    mesh.name = "b" + std::to_string(scene.meshes.size());
    mesh.first_face = scene.faces.size();
    mesh.face_count = 1;
    shadow::Face face;
    face.vertices = {{x, y, 10}, {x + 8, y, 10}, {x + 8, y + 8, 10}, {x, y + 8, 10}};
    face.mesh = scene.meshes.size();
    scene.faces.push_back(face);
    scene.meshes.push_back(mesh);
  };
  for (int i = 0; i < 15; ++i) add_roof(20.0 * (i % 5), 20.0 * (i / 5));
  shadow::Light sun;
  sun.to_light = {0.3, 0.2, 1.0};
  scene.lights = {sun};
  shadow::validate_scene(scene);
  EXPECT_EQ(strays(scene), 0);
  add_roof(-600.0, 500.0);
  shadow::validate_scene(scene);
  const std::vector<char> stray = sr::stray_meshes(scene, std::nullopt);
  ASSERT_EQ(stray.size(), 16u);
  EXPECT_EQ(stray[15], 1);
  EXPECT_EQ(std::count(stray.begin(), stray.end(), 1), 1);
  for (const glm::dvec3& p : sr::framed_points(scene, sr::Framing::Shadows)) EXPECT_GE(p.x, 0.0);
  EXPECT_EQ(sr::framed_points(scene, sr::Framing::Scene).size(), 64u);
  // Three far meshes of eighteen: more than a tenth, the scene is spread out and framed whole.
  add_roof(600.0, -500.0);
  add_roof(-700.0, -500.0);
  shadow::validate_scene(scene);
  EXPECT_EQ(strays(scene), 0);
}
