// SPDX-License-Identifier: GPL-3.0-or-later
// radiosity.vtp and report.json read back (read_radiosity_files, check_radiosity_files), for
// `shadow render --radiosity`: every array as written, the scene's origin added back, the
// materials' RGB reflectance, and the refusals (another kind of result, files of two runs,
// another scene, a missing directory).
#include <shadow/radiosity_output.hpp>
#include <shadow/error.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

/// Two unit squares: a red floor (face 0) and a grey wall (face 1), far from 0 (origin set).
shadow::Scene two_faces() {
  shadow::Scene scene;
  shadow::Material red;
  red.name = "red";
  red.reflectance_rgb = {0.6, 0.1, 0.05};
  red.reflectance = 0.25;
  shadow::Material grey;
  grey.name = "grey";
  grey.reflectance_rgb = {0.5, 0.5, 0.5};
  grey.reflectance = 0.5;
  grey.emittance = 7.0;
  scene.materials = {red, grey};
  const glm::dvec3 o(500000.0, 5400000.0, 100.0);
  auto add = [&](const std::string& name, const std::string& material, std::vector<glm::dvec3> v) {
    shadow::Mesh mesh;
    mesh.name = name;
    mesh.first_face = scene.faces.size();
    mesh.face_count = 1;
    mesh.material = material;
    scene.meshes.push_back(mesh);
    shadow::Face face;
    face.name = name;
    for (glm::dvec3& p : v) p += o;
    face.vertices = std::move(v);
    face.mesh = scene.meshes.size() - 1;
    scene.faces.push_back(face);
  };
  add("floor", "red", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  add("wall", "grey", {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}});
  scene.origin = o;
  return scene;
}

/// A made-up solution: each face two triangles with distinct values.
shadow::RadiosityResult solution(const shadow::Scene& scene) {
  shadow::RadiosityResult result;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const auto& v = scene.faces[f].vertices;
    for (int half = 0; half < 2; ++half) {
      shadow::RadiosityElement e;
      e.face_id = f;
      e.polygon = half == 0 ? std::vector<glm::dvec3>{v[0], v[1], v[2]} : std::vector<glm::dvec3>{v[0], v[2], v[3]};
      e.area = 0.5;
      e.irradiance = 10.0 * static_cast<double>(f + 1) + half;
      e.direct_irradiance = 8.0;
      e.reflectance = scene.material_of(f).reflectance;
      e.emittance = scene.material_of(f).emittance;
      e.radiosity = e.emittance + e.reflectance * e.irradiance;
      result.elements.push_back(e);
    }
    shadow::FaceRadiosity face;
    face.face_id = f;
    face.area = 1.0;
    face.elements = 2;
    result.faces.push_back(face);
  }
  return result;
}

class RadiosityFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("radiosity-files-" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    scene_ = two_faces();
    shadow::write_radiosity_outputs(dir_, scene_, solution(scene_), shadow::RadiosityRunInfo{});
  }
  void TearDown() override { fs::remove_all(dir_); }
  void rewrite_report(const std::string& from, const std::string& to) {
    std::ifstream in(dir_ / "report.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(dir_ / "report.json") << text;
  }
  fs::path dir_;
  shadow::Scene scene_;
};

std::string error_of(const fs::path& path, const shadow::Scene* scene = nullptr) {
  try {
    const shadow::RadiosityFiles files = shadow::read_radiosity_files(path);
    if (scene != nullptr) shadow::check_radiosity_files(*scene, files);
  } catch (const shadow::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_F(RadiosityFiles, EveryArrayComesBackAsWrittenInTheScenesCoordinates) {
  const shadow::RadiosityResult written = solution(scene_);
  for (const fs::path& path : {dir_, dir_ / "radiosity.vtp", dir_ / "report.json"}) {
    const shadow::RadiosityFiles files = shadow::read_radiosity_files(path);
    EXPECT_EQ(files.vtp, dir_ / "radiosity.vtp");
    EXPECT_EQ(files.report, dir_ / "report.json");
    ASSERT_EQ(files.elements.size(), written.elements.size());
    ASSERT_EQ(files.reflectance_rgb.size(), written.elements.size());
    for (std::size_t i = 0; i < written.elements.size(); ++i) {
      const shadow::RadiosityElement& a = files.elements[i];
      const shadow::RadiosityElement& b = written.elements[i];
      EXPECT_EQ(a.face_id, b.face_id);
      EXPECT_EQ(a.radiosity, b.radiosity);
      EXPECT_EQ(a.irradiance, b.irradiance);
      EXPECT_EQ(a.direct_irradiance, b.direct_irradiance);
      EXPECT_EQ(a.reflectance, b.reflectance);
      EXPECT_EQ(a.emittance, b.emittance);
      EXPECT_NEAR(a.area, 0.5, 1e-9);
      ASSERT_EQ(a.polygon.size(), 3u);
      for (std::size_t k = 0; k < 3; ++k)  // shifted by the origin in the file, back here
        EXPECT_LT(glm::length(a.polygon[k] - b.polygon[k]), 1e-9) << "element " << i << " vertex " << k;
      EXPECT_EQ(files.reflectance_rgb[i], scene_.material_of(b.face_id).reflectance_rgb);
    }
    ASSERT_EQ(files.report_faces.size(), 2u);
    EXPECT_EQ(files.report_faces[1].name, "wall");
    EXPECT_EQ(files.report_faces[1].mesh, "wall");
    EXPECT_NO_THROW(shadow::check_radiosity_files(scene_, files));
  }
}

TEST_F(RadiosityFiles, AReportWithoutAKindIsReadByItsElementCount) {
  rewrite_report("\"kind\": \"radiosity\",", "");
  EXPECT_EQ(error_of(dir_), "");
}

TEST_F(RadiosityFiles, AnotherKindOfResultIsRefused) {
  rewrite_report("\"kind\": \"radiosity\"", "\"kind\": \"irradiance\"");
  const std::string e = error_of(dir_);
  EXPECT_NE(e.find("report.json: kind: not the report of `shadow radiosity`"), std::string::npos) << e;
}

TEST_F(RadiosityFiles, FilesOfTwoRunsAreRefused) {
  rewrite_report("\"elements\": 4", "\"elements\": 5");
  const std::string e = error_of(dir_);
  EXPECT_NE(e.find("radiosity.vtp: 4 cells but report.json counts 5 elements"), std::string::npos) << e;
}

TEST_F(RadiosityFiles, AResultOfAnotherSceneIsRefused) {
  shadow::Scene other = scene_;
  other.faces[1].name = "door";
  std::string e = error_of(dir_, &other);
  EXPECT_NE(e.find("faces[1].name: face 1 is named \"wall\" in the result but \"door\" in the scene"), std::string::npos)
      << e;
  other.faces[1].name = "wall";
  other.meshes[1].name = "door";
  e = error_of(dir_, &other);
  EXPECT_NE(e.find("faces[1].mesh: face 1 is of mesh \"wall\" in the result but of mesh \"door\" in the scene"),
            std::string::npos)
      << e;
  other.faces.pop_back();
  e = error_of(dir_, &other);
  EXPECT_NE(e.find("radiosity.vtp: cell 2 face_id: face 1 is not in the scene (1 faces)"), std::string::npos) << e;
}

TEST_F(RadiosityFiles, AMissingResultNamesWhatToGive) {
  std::string e = error_of(dir_ / "nothing-here");
  EXPECT_NE(e.find("nothing-here: not found: give the OUTDIR of `shadow radiosity`"), std::string::npos) << e;
  std::ofstream(dir_ / "picture.png") << "not a result";
  e = error_of(dir_ / "picture.png");
  EXPECT_NE(e.find("picture.png: expected the OUTDIR of `shadow radiosity`"), std::string::npos) << e;
  fs::remove(dir_ / "radiosity.vtp");
  e = error_of(dir_);
  EXPECT_NE(e.find("radiosity.vtp: missing beside report.json"), std::string::npos) << e;
  fs::remove(dir_ / "report.json");
  e = error_of(dir_);
  EXPECT_NE(e.find("radiosity.vtp: not found: give the OUTDIR of `shadow radiosity`"), std::string::npos) << e;
  std::ofstream(dir_ / "radiosity.vtp") << "<VTKFile type=\"PolyData\"><broken";
  e = error_of(dir_ / "radiosity.vtp");
  EXPECT_NE(e.find("radiosity.vtp: "), std::string::npos) << e;
}
