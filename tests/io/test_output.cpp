// SPDX-License-Identifier: GPL-3.0-or-later
// Output files, read back with VTK's own readers and nlohmann::json. The scene and the
// ShadowResult are built by hand, so these tests do not depend on the shadow computation.
#include <shadow/output.hpp>
#include <shadow/version.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <vtkCellData.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkType.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace fs = std::filesystem;
using shadow::Face;
using shadow::FaceLighting;
using shadow::Fragment;
using shadow::PlaneShadow;
using shadow::Light;
using shadow::LightType;
using shadow::Mesh;
using shadow::OutputError;
using shadow::Scene;
using shadow::ShadowResult;

namespace {

// ---- a hand-made scene and result --------------------------------------------------------------

// Values with no short decimal form: they only survive a write and read at full precision.
const double kThird = 1.0 / 3.0;
const double kFarX = 1.0e6 + 0.1234567890123;  // georeferenced size, sub-millimetre detail

/// Faces: 0 "wall" (receiver), 1 "roof tile" (receiver), 2 "tree" (casts only, no results).
/// Lights: 0 "sun" (directional), 1 "desk lamp" (point).
Scene make_scene() {
  Scene scene;
  scene.source = "/data/city/scene.json";
  scene.meshes = {Mesh{"wall", "wall.obj", 0, 1, true},
                  Mesh{"roof tile", "", 1, 1, true},
                  Mesh{"tree", "tree.obj", 2, 1, false}};
  Face wall;
  wall.vertices = {{kFarX, 0.1, 0.0}, {kFarX + 4.0, 0.1, 0.0}, {kFarX + 4.0, 0.1, 3.0},
                   {kFarX, 0.1, 3.0}};
  wall.mesh = 0;
  Face roof;
  roof.vertices = {{kFarX, 1.0, 3.0}, {kFarX + 4.0, 1.0, 3.0}, {kFarX + 4.0, 2.0, 3.0 + kThird}};
  roof.mesh = 1;
  Face tree;
  tree.vertices = {{kFarX + 1.0, 5.0, 0.0}, {kFarX + 2.0, 5.0, 0.0}, {kFarX + 1.5, 5.0, 6.0}};
  tree.mesh = 2;
  scene.faces = {wall, roof, tree};

  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.to_light = {0.4, 0.3, 0.85};
  Light lamp;
  lamp.name = "desk lamp";
  lamp.type = LightType::Point;
  lamp.position = {kFarX + 1.0, 2.0, 9.5};
  scene.lights = {sun, lamp};

  scene.warnings.push_back({{"/data/city/tree.obj", "line 7"}, "face has a repeated vertex"});
  scene.warnings.push_back({{"/data/city/scene.json", "meshes[1]"}, "mesh has a single face"});
  scene.planes.push_back({"ground", {kFarX, 0.0, 0.0}, {0.0, 0.0, 1.0}, 0.0});
  return scene;
}

FaceLighting lighting(std::size_t face, std::size_t light, double area, double lit,
                      bool faces_light) {
  FaceLighting e;
  e.face_id = face;
  e.light_id = light;
  e.area = area;
  e.lit_area = lit;
  e.shadow_area = area - lit;
  e.lit_fraction = lit / area;
  e.faces_light = faces_light;
  return e;
}

Fragment fragment(std::size_t face, std::size_t light, std::size_t id, bool lit, double area,
                  std::vector<glm::dvec3> polygon) {
  Fragment f;
  f.face_id = face;
  f.light_id = light;
  f.fragment_id = id;
  f.lit = lit;
  f.area = area;
  f.polygon = std::move(polygon);
  return f;
}

const double kWallArea = 12.000000000000002;  // one ulp above 12
const double kRoofArea = 2.1081851067789197;

ShadowResult make_result() {
  ShadowResult r;
  r.lighting = {lighting(0, 0, kWallArea, 0.1 + 0.2, true),
                lighting(0, 1, kWallArea, kWallArea, true),
                lighting(1, 0, kRoofArea, kThird, true),
                lighting(1, 1, kRoofArea, 0.0, false)};
  // Face 0, sun: a lit region with a hole needs two cells that share fragment_id 0.
  r.fragments = {
      fragment(0, 0, 0, true, 0.1, {{kFarX, 0.1, 0.0}, {kFarX + 1.0, 0.1, 0.0}, {kFarX, 0.1, 1.0}}),
      fragment(0, 0, 0, true, 0.2,
               {{kFarX + 1.0, 0.1, 0.0}, {kFarX + 4.0, 0.1, 0.0}, {kFarX + 4.0, 0.1, kThird},
                {kFarX + 1.0, 0.1, kThird}}),
      fragment(0, 0, 1, false, kWallArea - 0.3,
               {{kFarX + 1.0, 0.1, 1.0}, {kFarX + 4.0, 0.1, 1.0}, {kFarX + 4.0, 0.1, 3.0}}),
      fragment(0, 1, 2, true, kWallArea, make_scene().faces[0].vertices),
      fragment(1, 0, 3, false, kRoofArea - kThird,
               {{kFarX, 1.0, 3.0}, {kFarX + 4.0, 1.0, 3.0}, {kFarX + 4.0, 2.0, 3.0 + kThird}}),
  };
  // The lamp's shadow on the ground plane: a region with a hole, as two cells of region 0.
  PlaneShadow ground;
  ground.plane_id = 0;
  ground.light_id = 1;
  ground.polygons = {{{kFarX, 0.0, 0.0}, {kFarX + 2.0, 0.0, 0.0}, {kFarX, kThird, 0.0}},
                     {{kFarX + 2.0, 0.0, 0.0}, {kFarX + 2.0, 1.0, 0.0}, {kFarX, kThird, 0.0}}};
  ground.region_id = {0, 0};
  ground.polygon_area = {kThird, 0.1 + 0.2};
  ground.area = kThird + (0.1 + 0.2);
  ground.window_half_size = 50.0;
  r.plane_shadows.push_back(ground);
  r.stats.receivers = 4;
  r.stats.back_facing = 1;
  r.stats.candidate_pairs = 7;
  r.stats.casting_pairs = 3;
  r.stats.unshadowed = 1;
  return r;
}

// ---- reading back ------------------------------------------------------------------------------

/// A fresh directory under the system's temp dir, removed with everything in it at the end.
class OutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("libshadow-test_output-" + std::to_string(getpid()) + "-" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }
  fs::path root_;
  Scene scene_ = make_scene();
  ShadowResult result_ = make_result();
};

vtkSmartPointer<vtkPolyData> read_vtp(const fs::path& path) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.string().c_str());
  reader->Update();
  EXPECT_EQ(reader->GetErrorCode(), 0u) << path;
  vtkSmartPointer<vtkPolyData> data = reader->GetOutput();
  return data;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

nlohmann::json read_report(const fs::path& dir) {
  return nlohmann::json::parse(read_text(dir / "report.json"));
}

std::set<std::string> directory_listing(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.insert(entry.path().filename().string());
  return names;
}

bool is_int32(vtkAbstractArray* a) { return a != nullptr && a->GetDataType() == VTK_INT; }
bool is_int64(vtkAbstractArray* a) {
  return a != nullptr && a->GetDataTypeSize() == 8 &&
         (a->GetDataType() == VTK_LONG || a->GetDataType() == VTK_LONG_LONG ||
          a->GetDataType() == VTK_ID_TYPE);
}
bool is_float64(vtkAbstractArray* a) { return a != nullptr && a->GetDataType() == VTK_DOUBLE; }

/// Bitwise equality: NaN equals NaN, and 0.1 + 0.2 must not come back as 0.3.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Cell `c`'s points, exactly as stored.
std::vector<glm::dvec3> cell_points(vtkPolyData* data, vtkIdType c) {
  vtkNew<vtkIdList> ids;
  data->GetCellPoints(c, ids);
  std::vector<glm::dvec3> points;
  for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i) {
    double p[3];
    data->GetPoint(ids->GetId(i), p);
    points.emplace_back(p[0], p[1], p[2]);
  }
  return points;
}

// ---- write_outputs: the set of files -----------------------------------------------------------

TEST_F(OutputTest, WritesEveryFileAndPlacesReportJsonLast) {
  const fs::path out = root_ / "out";
  const std::vector<fs::path> written = shadow::write_outputs(out, scene_, result_);
  const std::vector<fs::path> expected = {out / "fragments.vtp", out / "faces.vtp",
                                          out / "plane_shadows.vtp", out / "lights.vtp",
                                          out / "scene.vtm", out / "report.json"};
  EXPECT_EQ(written, expected);
  for (const fs::path& p : expected) EXPECT_TRUE(fs::is_regular_file(p)) << p;
}

TEST_F(OutputTest, LeavesNoTemporaryFilesBehind) {
  shadow::write_outputs(root_, scene_, result_);
  EXPECT_EQ(directory_listing(root_),
            (std::set<std::string>{"faces.vtp", "fragments.vtp", "lights.vtp", "plane_shadows.vtp",
                                   "report.json", "scene.vtm"}));
}

TEST_F(OutputTest, CreatesAMissingOutputDirectoryAndItsParents) {
  const fs::path out = root_ / "a" / "b" / "c";
  shadow::write_outputs(out, scene_, result_);
  EXPECT_TRUE(fs::is_regular_file(out / "report.json"));
}

TEST_F(OutputTest, OverwritesTheFilesOfAnEarlierRun) {
  shadow::write_outputs(root_, Scene{}, ShadowResult{});
  shadow::write_outputs(root_, scene_, result_);
  EXPECT_EQ(read_vtp(root_ / "fragments.vtp")->GetNumberOfCells(), 5);
  EXPECT_EQ(read_report(root_)["faces"].size(), 2u);
}

// ---- fragments.vtp -----------------------------------------------------------------------------

TEST_F(OutputTest, FragmentsVtpHasOneFloat64PolygonPerFragmentWithItsExactVertices) {
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "fragments.vtp");
  ASSERT_EQ(data->GetNumberOfCells(), static_cast<vtkIdType>(result_.fragments.size()));
  EXPECT_EQ(data->GetNumberOfPolys(), data->GetNumberOfCells());
  EXPECT_EQ(data->GetPoints()->GetData()->GetDataType(), VTK_DOUBLE);
  for (std::size_t c = 0; c < result_.fragments.size(); ++c) {
    const auto points = cell_points(data, static_cast<vtkIdType>(c));
    const auto& polygon = result_.fragments[c].polygon;
    ASSERT_EQ(points.size(), polygon.size()) << "cell " << c;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      // Exact: coordinates near 1e6 keep their last bit (Float32 would lose about 0.06).
      EXPECT_TRUE(same_bits(points[i].x, polygon[i].x) && same_bits(points[i].y, polygon[i].y) &&
                  same_bits(points[i].z, polygon[i].z))
          << "cell " << c << " vertex " << i;
    }
  }
}

TEST_F(OutputTest, FragmentsVtpCarriesFaceLightLitAreaAndFragmentIdPerCell) {
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "fragments.vtp");
  vtkCellData* cd = data->GetCellData();
  vtkDataArray* face_id = cd->GetArray("face_id");
  vtkDataArray* light_id = cd->GetArray("light_id");
  vtkDataArray* lit = cd->GetArray("lit");
  vtkDataArray* area = cd->GetArray("area");
  vtkDataArray* fragment_id = cd->GetArray("fragment_id");
  ASSERT_TRUE(is_int64(face_id));
  ASSERT_TRUE(is_int32(light_id));
  ASSERT_TRUE(is_int32(lit));
  ASSERT_TRUE(is_float64(area));
  ASSERT_TRUE(is_int64(fragment_id));
  for (std::size_t c = 0; c < result_.fragments.size(); ++c) {
    const Fragment& f = result_.fragments[c];
    const auto i = static_cast<vtkIdType>(c);
    EXPECT_EQ(face_id->GetTuple1(i), static_cast<double>(f.face_id)) << c;
    EXPECT_EQ(light_id->GetTuple1(i), static_cast<double>(f.light_id)) << c;
    EXPECT_EQ(lit->GetTuple1(i), f.lit ? 1.0 : 0.0) << c;
    EXPECT_TRUE(same_bits(area->GetTuple1(i), f.area)) << c;
    EXPECT_EQ(fragment_id->GetTuple1(i), static_cast<double>(f.fragment_id)) << c;
  }
  // The two pieces of the lit region with a hole keep one fragment_id.
  EXPECT_EQ(fragment_id->GetTuple1(0), fragment_id->GetTuple1(1));
}

TEST_F(OutputTest, FragmentsVtpHasPerPointIrradianceFromEachCellsOwnLight) {
  // A unit ground square (normal +z) under a sun of intensity 2 at 60 degrees from the zenith
  // (2 cos 60 = 1) and a lamp of intensity 8 two units above the corner (0, 0).
  Scene scene;
  scene.meshes = {Mesh{"ground", "", 0, 1, true}};
  Face ground;
  ground.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  scene.faces = {ground};
  Light sun;
  sun.name = "sun";
  sun.to_light = {std::sqrt(3.0), 0.0, 1.0};  // 60 degrees from +z
  sun.intensity = 2.0;
  Light lamp;
  lamp.name = "lamp";
  lamp.type = LightType::Point;
  lamp.position = {0.0, 0.0, 2.0};
  lamp.intensity = 8.0;
  scene.lights = {sun, lamp};

  ShadowResult result;
  result.lighting = {lighting(0, 0, 1.0, 0.5, true), lighting(0, 1, 1.0, 0.5, true)};
  const std::vector<glm::dvec3> left = {{0, 0, 0}, {0.5, 0, 0}, {0.5, 1, 0}, {0, 1, 0}};
  const std::vector<glm::dvec3> right = {{0.5, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0.5, 1, 0}};
  result.fragments = {fragment(0, 0, 0, true, 0.5, left), fragment(0, 0, 1, false, 0.5, right),
                      fragment(0, 1, 0, true, 0.5, left), fragment(0, 1, 1, false, 0.5, right),
                      fragment(0, 7, 0, true, 1.0, ground.vertices)};  // light 7: not in the scene
  shadow::write_outputs(root_, scene, result);
  auto data = read_vtp(root_ / "fragments.vtp");
  vtkDataArray* irradiance = data->GetPointData()->GetArray("irradiance");
  ASSERT_TRUE(is_float64(irradiance));
  ASSERT_EQ(irradiance->GetNumberOfTuples(), data->GetNumberOfPoints());

  auto values = [&](vtkIdType cell) {
    vtkNew<vtkIdList> ids;
    data->GetCellPoints(cell, ids);
    std::vector<double> v;
    for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i) v.push_back(irradiance->GetTuple1(ids->GetId(i)));
    return v;
  };
  // Sun, lit: I cos = 1 at every vertex. Shadowed: 0.
  for (double v : values(0)) EXPECT_NEAR(v, 1.0, 1e-12);
  for (double v : values(1)) EXPECT_EQ(v, 0.0);
  // Lamp, lit: I cos / r^2 = I h / r^3 with h = 2. (0,0): 8/4 = 2; (0.5,0): 8*2/(4.25)^1.5;
  // (0.5,1): 16/(5.25)^1.5; (0,1): 16/5^1.5.
  const std::vector<double> lamp_values = values(2);
  ASSERT_EQ(lamp_values.size(), 4u);
  EXPECT_NEAR(lamp_values[0], 2.0, 1e-12);
  EXPECT_NEAR(lamp_values[1], 16.0 / std::pow(4.25, 1.5), 1e-12);
  EXPECT_NEAR(lamp_values[2], 16.0 / std::pow(5.25, 1.5), 1e-12);
  EXPECT_NEAR(lamp_values[3], 16.0 / std::pow(5.0, 1.5), 1e-12);
  for (double v : values(3)) EXPECT_EQ(v, 0.0);
  // The same point (0.5, 0) has different values in the sun's and the lamp's cells: points
  // are not shared between cells.
  EXPECT_NE(values(0)[1], lamp_values[1]);
  for (double v : values(4)) EXPECT_TRUE(std::isnan(v));
  // The existing cell arrays are still there.
  EXPECT_NE(data->GetCellData()->GetArray("lit"), nullptr);
}

TEST_F(OutputTest, AnEmptyResultStillWritesReadableFiles) {
  shadow::write_outputs(root_, scene_, ShadowResult{});
  auto fragments = read_vtp(root_ / "fragments.vtp");
  EXPECT_EQ(fragments->GetNumberOfCells(), 0);
  auto faces = read_vtp(root_ / "faces.vtp");
  EXPECT_EQ(faces->GetNumberOfCells(), 3);
  EXPECT_TRUE(std::isnan(faces->GetCellData()->GetArray("area")->GetTuple1(0)));
  const auto report = read_report(root_);
  EXPECT_TRUE(report["faces"].empty());
  EXPECT_EQ(report["summary"]["receiving_faces"], 0);
  EXPECT_EQ(report["summary"]["total_area"], 0.0);
}

// ---- faces.vtp ---------------------------------------------------------------------------------

TEST_F(OutputTest, FacesVtpHasEveryInputFaceWithItsMeshAndReceiverFlag) {
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "faces.vtp");
  ASSERT_EQ(data->GetNumberOfCells(), 3);
  EXPECT_EQ(data->GetPoints()->GetData()->GetDataType(), VTK_DOUBLE);
  for (vtkIdType c = 0; c < 3; ++c) {
    const auto points = cell_points(data, c);
    const auto& vertices = scene_.faces[static_cast<std::size_t>(c)].vertices;
    ASSERT_EQ(points.size(), vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i)
      EXPECT_TRUE(same_bits(points[i].x, vertices[i].x) && same_bits(points[i].z, vertices[i].z));
  }
  vtkCellData* cd = data->GetCellData();
  ASSERT_TRUE(is_int64(cd->GetArray("face_id")));
  ASSERT_TRUE(is_int32(cd->GetArray("mesh_id")));
  ASSERT_TRUE(is_int32(cd->GetArray("receiver")));
  auto* mesh = vtkStringArray::SafeDownCast(cd->GetAbstractArray("mesh"));
  ASSERT_NE(mesh, nullptr);
  const std::vector<std::string> names = {"wall", "roof tile", "tree"};
  const std::vector<double> receiver = {1, 1, 0};
  for (vtkIdType c = 0; c < 3; ++c) {
    EXPECT_EQ(cd->GetArray("face_id")->GetTuple1(c), static_cast<double>(c));
    EXPECT_EQ(cd->GetArray("mesh_id")->GetTuple1(c), static_cast<double>(c));
    EXPECT_EQ(mesh->GetValue(c), names[static_cast<std::size_t>(c)]);
    EXPECT_EQ(cd->GetArray("receiver")->GetTuple1(c), receiver[static_cast<std::size_t>(c)]);
  }
}

TEST_F(OutputTest, FacesVtpHasPerLightResultsWithNaNWhereNothingWasComputed) {
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "faces.vtp");
  vtkCellData* cd = data->GetCellData();
  vtkDataArray* area = cd->GetArray("area");
  ASSERT_TRUE(is_float64(area));
  EXPECT_TRUE(same_bits(area->GetTuple1(0), kWallArea));
  EXPECT_TRUE(same_bits(area->GetTuple1(1), kRoofArea));
  EXPECT_TRUE(std::isnan(area->GetTuple1(2)));  // the tree only casts shadows

  // "desk lamp" is not a valid array-name part: it becomes "desk_lamp".
  for (const char* name : {"lit_fraction_sun", "lit_area_sun", "lit_fraction_desk_lamp",
                           "lit_area_desk_lamp"})
    ASSERT_TRUE(is_float64(cd->GetArray(name))) << name;
  for (const FaceLighting& e : result_.lighting) {
    const std::string light = e.light_id == 0 ? "sun" : "desk_lamp";
    const auto c = static_cast<vtkIdType>(e.face_id);
    EXPECT_TRUE(same_bits(cd->GetArray(("lit_fraction_" + light).c_str())->GetTuple1(c),
                          e.lit_fraction));
    EXPECT_TRUE(same_bits(cd->GetArray(("lit_area_" + light).c_str())->GetTuple1(c), e.lit_area));
  }
  EXPECT_TRUE(std::isnan(cd->GetArray("lit_fraction_sun")->GetTuple1(2)));
  EXPECT_TRUE(std::isnan(cd->GetArray("lit_area_desk_lamp")->GetTuple1(2)));
}

TEST_F(OutputTest, LightNamesThatSanitizeAlikeGetDistinctArrays) {
  scene_.lights[0].name = "sun 1";
  scene_.lights[1].name = "sun_1";
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "faces.vtp");
  vtkCellData* cd = data->GetCellData();
  EXPECT_NE(cd->GetArray("lit_fraction_sun_1_0"), nullptr);
  EXPECT_NE(cd->GetArray("lit_fraction_sun_1_1"), nullptr);
  EXPECT_EQ(cd->GetArray("lit_fraction_sun_1"), nullptr);
}

TEST_F(OutputTest, FacesVtpHasNoPerLightArraysForLightsWithoutResults) {
  result_.lighting.erase(result_.lighting.begin() + 1);  // drop (face 0, lamp)
  result_.lighting.pop_back();                            // and (face 1, lamp)
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "faces.vtp");
  vtkCellData* cd = data->GetCellData();
  EXPECT_NE(cd->GetArray("lit_fraction_sun"), nullptr);
  EXPECT_EQ(cd->GetArray("lit_fraction_desk_lamp"), nullptr);
}

// ---- lights.vtp --------------------------------------------------------------------------------

TEST_F(OutputTest, LightsVtpPutsPointLightsAtTheirPositionAndTheSunOneDiagonalAboveTheScene) {
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "lights.vtp");
  ASSERT_EQ(data->GetNumberOfPoints(), 2);
  ASSERT_EQ(data->GetNumberOfVerts(), 2);
  EXPECT_EQ(data->GetPoints()->GetData()->GetDataType(), VTK_DOUBLE);

  // Bounding box of all faces: x [kFarX, kFarX + 4], y [0.1, 5], z [0, 6].
  const glm::dvec3 lo(kFarX, 0.1, 0.0), hi(kFarX + 4.0, 5.0, 6.0);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const glm::dvec3 sun_dir = glm::normalize(scene_.lights[0].to_light);
  const glm::dvec3 sun_at = centre + sun_dir * glm::length(hi - lo);
  double p[3];
  data->GetPoint(0, p);
  EXPECT_NEAR(p[0], sun_at.x, 1e-9);
  EXPECT_NEAR(p[1], sun_at.y, 1e-9);
  EXPECT_NEAR(p[2], sun_at.z, 1e-9);
  data->GetPoint(1, p);
  EXPECT_TRUE(same_bits(p[0], kFarX + 1.0) && p[1] == 2.0 && p[2] == 9.5);

  vtkPointData* pd = data->GetPointData();
  ASSERT_TRUE(is_int32(pd->GetArray("light_id")));
  ASSERT_TRUE(is_int32(pd->GetArray("type")));
  vtkDataArray* to_light = pd->GetArray("to_light");
  vtkDataArray* direction = pd->GetArray("direction");
  ASSERT_TRUE(is_float64(to_light));
  ASSERT_TRUE(is_float64(direction));
  ASSERT_EQ(to_light->GetNumberOfComponents(), 3);
  ASSERT_EQ(direction->GetNumberOfComponents(), 3);
  auto* name = vtkStringArray::SafeDownCast(pd->GetAbstractArray("name"));
  ASSERT_NE(name, nullptr);

  const glm::dvec3 lamp_dir = glm::normalize(scene_.lights[1].position - centre);
  const std::vector<glm::dvec3> expected_to_light = {sun_dir, lamp_dir};
  for (vtkIdType i = 0; i < 2; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_EQ(pd->GetArray("light_id")->GetTuple1(i), static_cast<double>(i));
    EXPECT_EQ(pd->GetArray("type")->GetTuple1(i), i == 0 ? 0.0 : 1.0);  // 0 directional, 1 point
    EXPECT_EQ(name->GetValue(i), scene_.lights[k].name);
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(to_light->GetComponent(i, j), expected_to_light[k][j], 1e-12);
      EXPECT_EQ(direction->GetComponent(i, j), -to_light->GetComponent(i, j));
    }
  }
}

TEST_F(OutputTest, LightsVtpCarriesIntensityAndColour) {
  scene_.lights[1].intensity = 2.5;
  scene_.lights[1].color = {1.0, 0.5, kThird};
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "lights.vtp");
  vtkPointData* pd = data->GetPointData();
  vtkDataArray* intensity = pd->GetArray("intensity");
  vtkDataArray* color = pd->GetArray("color");
  ASSERT_TRUE(is_float64(intensity));
  ASSERT_TRUE(is_float64(color));
  ASSERT_EQ(color->GetNumberOfComponents(), 3);
  EXPECT_EQ(intensity->GetTuple1(0), 1.0);  // the defaults
  EXPECT_EQ(color->GetComponent(0, 0), 1.0);
  EXPECT_EQ(intensity->GetTuple1(1), 2.5);
  EXPECT_EQ(color->GetComponent(1, 1), 0.5);
  EXPECT_TRUE(same_bits(color->GetComponent(1, 2), kThird));
}

// ---- scene.vtm ---------------------------------------------------------------------------------

TEST_F(OutputTest, SceneVtmOpensFacesFragmentsPlaneShadowsAndLightsAsNamedBlocks) {
  shadow::write_outputs(root_, scene_, result_);
  vtkNew<vtkXMLMultiBlockDataReader> reader;
  reader->SetFileName((root_ / "scene.vtm").string().c_str());
  reader->Update();
  ASSERT_EQ(reader->GetErrorCode(), 0u);
  auto* blocks = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutput());
  ASSERT_NE(blocks, nullptr);
  ASSERT_EQ(blocks->GetNumberOfBlocks(), 4u);
  const std::vector<std::string> names = {"faces", "fragments", "plane_shadows", "lights"};
  const std::vector<vtkIdType> points_or_cells = {3, 5, 2, 2};
  for (unsigned b = 0; b < 4; ++b) {
    ASSERT_TRUE(blocks->HasMetaData(b));
    EXPECT_EQ(std::string(blocks->GetMetaData(b)->Get(vtkCompositeDataSet::NAME())), names[b]);
    auto* poly = vtkPolyData::SafeDownCast(blocks->GetBlock(b));
    ASSERT_NE(poly, nullptr) << names[b];
    EXPECT_EQ(poly->GetNumberOfCells(), points_or_cells[b]) << names[b];
  }
}

// ---- report.json -------------------------------------------------------------------------------

TEST_F(OutputTest, ReportHasVersionSceneAndLights) {
  shadow::write_outputs(root_, scene_, result_);
  const auto report = read_report(root_);
  EXPECT_EQ(report["libshadow_version"], shadow::version());
  EXPECT_EQ(report["scene"], "/data/city/scene.json");
  ASSERT_EQ(report["lights"].size(), 2u);
  const auto& sun = report["lights"][0];
  EXPECT_EQ(sun["id"], 0);
  EXPECT_EQ(sun["name"], "sun");
  EXPECT_EQ(sun["type"], "directional");
  EXPECT_EQ(sun["to_light"], (nlohmann::json{0.4, 0.3, 0.85}));
  EXPECT_FALSE(sun.contains("position"));
  const auto& lamp = report["lights"][1];
  EXPECT_EQ(lamp["id"], 1);
  EXPECT_EQ(lamp["name"], "desk lamp");
  EXPECT_EQ(lamp["type"], "point");
  EXPECT_TRUE(same_bits(lamp["position"][0].get<double>(), kFarX + 1.0));
  EXPECT_FALSE(lamp.contains("to_light"));
}

TEST_F(OutputTest, ReportListsEachReceivingFaceWithResultsAndItsAreasBitForBit) {
  shadow::write_outputs(root_, scene_, result_);
  const auto report = read_report(root_);
  const auto& faces = report["faces"];
  ASSERT_EQ(faces.size(), 2u);  // the tree has no results and no entry
  const std::vector<std::string> meshes = {"wall", "roof tile"};
  std::size_t next = 0;
  for (std::size_t f = 0; f < 2; ++f) {
    EXPECT_EQ(faces[f]["id"], f);
    EXPECT_EQ(faces[f]["mesh"], meshes[f]);
    ASSERT_EQ(faces[f]["lights"].size(), 2u);
    for (std::size_t l = 0; l < 2; ++l) {
      const FaceLighting& e = result_.lighting[next++];
      const auto& entry = faces[f]["lights"][l];
      EXPECT_TRUE(same_bits(faces[f]["area"].get<double>(), e.area));
      EXPECT_EQ(entry["light"], e.light_id);
      EXPECT_EQ(entry["light_name"], scene_.lights[e.light_id].name);
      EXPECT_TRUE(same_bits(entry["lit_area"].get<double>(), e.lit_area)) << f << "," << l;
      EXPECT_TRUE(same_bits(entry["shadow_area"].get<double>(), e.shadow_area)) << f << "," << l;
      EXPECT_TRUE(same_bits(entry["lit_fraction"].get<double>(), e.lit_fraction)) << f << "," << l;
      EXPECT_EQ(entry["faces_light"], e.faces_light);
    }
  }
}

TEST_F(OutputTest, ReportOrdersFacesAndLightsByIdWhateverTheInputOrder) {
  std::swap(result_.lighting[0], result_.lighting[3]);
  std::swap(result_.lighting[1], result_.lighting[2]);
  shadow::write_outputs(root_, scene_, result_);
  const auto faces = read_report(root_)["faces"];
  ASSERT_EQ(faces.size(), 2u);
  for (std::size_t f = 0; f < 2; ++f) {
    EXPECT_EQ(faces[f]["id"], f);
    EXPECT_EQ(faces[f]["lights"][0]["light"], 0);
    EXPECT_EQ(faces[f]["lights"][1]["light"], 1);
  }
}

TEST_F(OutputTest, ReportHasOnePlanesEntryPerPlaneShadow) {
  shadow::write_outputs(root_, scene_, result_);
  const auto report = read_report(root_);
  ASSERT_TRUE(report["planes"].is_array());
  ASSERT_EQ(report["planes"].size(), 1u);
  const auto& entry = report["planes"][0];
  EXPECT_EQ(entry["name"], "ground");
  EXPECT_EQ(entry["light"], 1);
  EXPECT_EQ(entry["shadow_area"].get<double>(), result_.plane_shadows[0].area);
  EXPECT_EQ(entry["reaches_window"], false);
}

TEST_F(OutputTest, PlaneShadowsVtpHoldsEveryPolygonWithItsPlaneLightRegionAndArea) {
  shadow::write_outputs(root_, scene_, result_);
  auto data = read_vtp(root_ / "plane_shadows.vtp");
  const PlaneShadow& shadow = result_.plane_shadows[0];
  ASSERT_EQ(data->GetNumberOfCells(), static_cast<vtkIdType>(shadow.polygons.size()));
  EXPECT_EQ(data->GetPoints()->GetDataType(), VTK_DOUBLE);
  vtkCellData* cd = data->GetCellData();
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c) {
    EXPECT_EQ(cd->GetArray("plane_id")->GetTuple1(c), 0.0);
    EXPECT_EQ(cd->GetArray("light_id")->GetTuple1(c), 1.0);
    EXPECT_EQ(cd->GetArray("region_id")->GetTuple1(c), static_cast<double>(shadow.region_id[c]));
    EXPECT_EQ(cd->GetArray("area")->GetTuple1(c), shadow.polygon_area[c]);
    vtkCell* cell = data->GetCell(c);
    ASSERT_EQ(cell->GetNumberOfPoints(), static_cast<vtkIdType>(shadow.polygons[c].size()));
    for (vtkIdType i = 0; i < cell->GetNumberOfPoints(); ++i) {
      double x[3];
      data->GetPoint(cell->GetPointId(i), x);
      EXPECT_EQ(x[0], shadow.polygons[c][i].x);
      EXPECT_EQ(x[1], shadow.polygons[c][i].y);
      EXPECT_EQ(x[2], shadow.polygons[c][i].z);
    }
  }
}

TEST_F(OutputTest, ReportSummaryTotalsAreasPerLight) {
  shadow::write_outputs(root_, scene_, result_);
  const auto summary = read_report(root_)["summary"];
  EXPECT_EQ(summary["faces"], 3);
  EXPECT_EQ(summary["receiving_faces"], 2);
  EXPECT_EQ(summary["lights"], 2);
  EXPECT_EQ(summary["fragments"], 5);
  const double total = kWallArea + kRoofArea;
  EXPECT_DOUBLE_EQ(summary["total_area"].get<double>(), total);
  ASSERT_EQ(summary["per_light"].size(), 2u);
  const double sun_lit = (0.1 + 0.2) + kThird;
  EXPECT_EQ(summary["per_light"][0]["light"], 0);
  EXPECT_DOUBLE_EQ(summary["per_light"][0]["lit_area"].get<double>(), sun_lit);
  EXPECT_DOUBLE_EQ(summary["per_light"][0]["lit_fraction"].get<double>(), sun_lit / total);
  EXPECT_EQ(summary["per_light"][1]["light"], 1);
  EXPECT_DOUBLE_EQ(summary["per_light"][1]["lit_area"].get<double>(), kWallArea);
  EXPECT_DOUBLE_EQ(summary["per_light"][1]["lit_fraction"].get<double>(), kWallArea / total);
}

TEST_F(OutputTest, ReportCarriesTheSceneWarnings) {
  shadow::write_outputs(root_, scene_, result_);
  const auto warnings = read_report(root_)["warnings"];
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0], "/data/city/tree.obj: line 7: face has a repeated vertex");
  EXPECT_EQ(warnings[1], "/data/city/scene.json: meshes[1]: mesh has a single face");
}

TEST_F(OutputTest, ReportIsPrettyPrintedWithTwoSpaceIndentInAFixedKeyOrder) {
  std::ostringstream text;
  shadow::write_report_json(text, scene_, result_);
  // Streamed piece by piece, but identical to printing the whole document at once.
  const auto parsed = nlohmann::ordered_json::parse(text.str());
  EXPECT_EQ(text.str(), parsed.dump(2) + "\n");
  std::vector<std::string> keys;
  for (const auto& item : parsed.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"libshadow_version", "scene", "run", "lights", "faces",
                                            "planes", "summary", "stats", "warnings"}));
}

TEST_F(OutputTest, ReportNumbersAreNlohmannsOwnWholeOrNot) {
  // Whole numbers are written without nlohmann's digit search (report_json.cpp): the text is
  // still its dump(2), at the edges of that shortcut (-0.0, 1e15 and just below, 2^53) too.
  const double numbers[] = {0.0, -0.0, 1.0, -1.0, 90.0, 270.0, 41925349.0, 999999999999999.0, 1e15,
                            -999999999999999.0, 123456789012345.0, 9007199254740992.0, 1e21, 1e-5,
                            -2.5e-300, 3.0000000000000004};
  std::size_t k = 0;
  for (FaceLighting& e : result_.lighting) {
    e.lit_area = numbers[k++ % std::size(numbers)];
    e.shadow_area = numbers[k++ % std::size(numbers)];
    e.lit_fraction = numbers[k++ % std::size(numbers)];
    e.area = numbers[k++ % std::size(numbers)];
  }
  ASSERT_GE(k, std::size(numbers));
  std::ostringstream text;
  shadow::write_report_json(text, scene_, result_);
  EXPECT_EQ(text.str(), nlohmann::ordered_json::parse(text.str()).dump(2) + "\n");
  EXPECT_NE(text.str().find("-0.0,"), std::string::npos);
  EXPECT_NE(text.str().find("999999999999999.0,"), std::string::npos);
  EXPECT_NE(text.str().find("1e+15,"), std::string::npos);
}

TEST_F(OutputTest, ReportStatsNameTilesOnlyWhenReceiversWereSplit) {
  std::ostringstream whole;
  shadow::write_report_json(whole, scene_, result_);
  const auto stats = nlohmann::json::parse(whole.str())["stats"];
  EXPECT_FALSE(stats.contains("tiled_receivers"));  // additive keys: earlier reports unchanged
  EXPECT_FALSE(stats.contains("tiles"));
  ShadowResult tiled = result_;
  tiled.stats.tiled_receivers = 2;
  tiled.stats.tiles = 17;
  std::ostringstream text;
  shadow::write_report_json(text, scene_, tiled);
  const auto with = nlohmann::json::parse(text.str())["stats"];
  EXPECT_EQ(with["tiled_receivers"], 2);
  EXPECT_EQ(with["tiles"], 17);
}

TEST_F(OutputTest, ReportWithoutFacesIsStillPrettyPrinted) {
  std::ostringstream text;
  shadow::write_report_json(text, Scene{}, ShadowResult{});
  EXPECT_EQ(text.str(), nlohmann::ordered_json::parse(text.str()).dump(2) + "\n");
}

// ---- failures ----------------------------------------------------------------------------------

TEST_F(OutputTest, AnOutputPathThatIsARegularFileIsAnOutputErrorAndNothingIsLeftBehind) {
  const fs::path file = root_ / "not-a-directory";
  std::ofstream(file) << "keep me";
  try {
    shadow::write_outputs(file, scene_, result_);
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_text(file), "keep me");
  EXPECT_EQ(directory_listing(root_), std::set<std::string>{"not-a-directory"});
}

TEST_F(OutputTest, AnOutputPathBelowARegularFileIsAnOutputError) {
  const fs::path file = root_ / "plain-file";
  std::ofstream(file) << "x";
  EXPECT_THROW(shadow::write_outputs(file / "sub", scene_, result_), OutputError);
  EXPECT_EQ(directory_listing(root_), std::set<std::string>{"plain-file"});
}

TEST_F(OutputTest, AStaleReportIsReplacedByTheNewOne) {
  std::ofstream(root_ / "report.json") << R"({"stale": true})";
  shadow::write_outputs(root_, scene_, result_);
  const auto report = read_report(root_);
  EXPECT_FALSE(report.contains("stale"));
  EXPECT_EQ(report["faces"].size(), 2u);
}

TEST_F(OutputTest, TheStaleReportIsGoneOnceTheDirectoryIsOpenedAndItsRemovalLeavesNothing) {
  // A large report: it is moved aside at once and removed in the background (staged_files.hpp).
  std::ofstream(root_ / "report.json") << std::string(std::size_t{8} << 20, ' ') << R"({"stale": true})";
  {
    shadow::OutputDirectory output(root_);
    EXPECT_FALSE(fs::exists(root_ / "report.json"));
    output.write(scene_, result_);
    EXPECT_FALSE(read_report(root_).contains("stale"));
  }
  // Neither the old report nor its hidden name stays behind.
  EXPECT_EQ(directory_listing(root_),
            (std::set<std::string>{"faces.vtp", "fragments.vtp", "lights.vtp", "plane_shadows.vtp", "report.json",
                                   "scene.vtm"}));
}

TEST_F(OutputTest, AStaleReportThatIsALinkGoesWithoutItsTarget) {
  // The link itself is moved aside and removed; the file it points to is not ours to remove.
  const fs::path target = root_ / "kept.json";
  std::ofstream(target) << R"({"someone else's": true})";
  fs::create_symlink(target, root_ / "report.json");
  {
    shadow::OutputDirectory output(root_);
    EXPECT_FALSE(fs::exists(fs::symlink_status(root_ / "report.json")));
  }
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(target)));
  EXPECT_EQ(directory_listing(root_), std::set<std::string>{"kept.json"});
}

TEST_F(OutputTest, AFailedRunRemovesTheStaleReportAndItsOwnTemporaries) {
  // An old, complete-looking run, and an obstacle that makes the new one fail at the end:
  // a directory where scene.vtm has to go.
  for (const char* name : {"report.json", "faces.vtp", "fragments.vtp", "lights.vtp"})
    std::ofstream(root_ / name) << "old";
  fs::create_directories(root_ / "scene.vtm" / "keep");
  try {
    shadow::write_outputs(root_, scene_, result_);
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find((root_ / "scene.vtm").string()), std::string::npos)
        << e.what();
  }
  const auto names = directory_listing(root_);
  EXPECT_EQ(names.count("report.json"), 0u) << "an old report.json next to new files";
  for (const std::string& name : names) EXPECT_NE(name.front(), '.') << "temporary left: " << name;
}

TEST_F(OutputTest, AVtkWriteFailureNamesTheFileAndVtksReason) {
  // Something that is not a writable file where fragments.vtp's temporary goes.
  const fs::path blocker = root_ / (".fragments.vtp.tmp-" + std::to_string(getpid()));
  fs::create_directories(blocker / "keep");
  ::testing::internal::CaptureStderr();
  try {
    shadow::write_outputs(root_, scene_, result_);
    ADD_FAILURE() << "expected OutputError";
  } catch (const OutputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find((root_ / "fragments.vtp").string() + ": "), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    EXPECT_EQ(message.find("vtkXMLPolyDataWriter ("), std::string::npos) << message;
    EXPECT_EQ(message.find(".tmp-"), std::string::npos) << "temporary name shown: " << message;
  }
  // The caller prints the one-line error; VTK must not add its own multi-line dumps.
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_FALSE(fs::exists(root_ / "report.json"));
  EXPECT_FALSE(fs::exists(root_ / "fragments.vtp"));
}

// report.json is written on a thread of its own while the VTK files are written (from two
// threads on). Its failure alone, and a VTK failure while it is being written, each give one
// OutputError naming the file, no file put in place and no temporary left, at every thread count.
TEST_F(OutputTest, AReportFailureAloneOrAVtkFailureBesideTheReportLeaveNothingAtAnyThreadCount) {
  for (const unsigned threads : {1u, 2u, 4u}) {
    shadow::RunInfo run;
    run.options.threads = threads;
    for (const char* failing : {"report.json", "fragments.vtp"}) {
      fs::remove_all(root_);
      fs::create_directories(root_);
      std::ofstream(root_ / "report.json") << "old";
      const fs::path blocker = root_ / ("." + std::string(failing) + ".tmp-" + std::to_string(getpid()));
      fs::create_directories(blocker / "keep");
      ::testing::internal::CaptureStderr();
      try {
        shadow::write_outputs(root_, scene_, result_, run);
        ADD_FAILURE() << failing << ", " << threads << " threads: expected OutputError";
      } catch (const OutputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find((root_ / failing).string() + ": "), 0u) << threads << " threads: " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      }
      EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
      fs::remove_all(blocker);
      EXPECT_TRUE(directory_listing(root_).empty())
          << failing << ", " << threads << " threads: a file or temporary left behind";
    }
  }
}

TEST_F(OutputTest, AFailedWriteIsAnOutputErrorThatSaysSoAndLeavesNoReport) {
  // Every write past 64 bytes of a regular file fails (EFBIG) under this limit, as on a full
  // disk: SIGXFSZ ignored, so that write() returns the error instead of killing the process.
  std::ofstream(root_ / "report.json") << "old";
  rlimit old_limit{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old_limit;
  small.rlim_cur = 64;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string message;
  bool thrown = false;
  ::testing::internal::CaptureStderr();
  try {
    shadow::write_outputs(root_, scene_, result_);
  } catch (const OutputError& e) {
    thrown = true;
    message = e.what();
  }
  const std::string captured = ::testing::internal::GetCapturedStderr();
  setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  ASSERT_TRUE(thrown) << "expected OutputError";
  EXPECT_EQ(message.find((root_ / "fragments.vtp").string() + ": "), 0u) << message;
  EXPECT_NE(message.find(std::strerror(EFBIG)), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  EXPECT_EQ(captured, "");
  EXPECT_TRUE(directory_listing(root_).empty()) << "old report or temporaries left behind";
}

TEST_F(OutputTest, ATemporaryNameIsNeverFollowedThroughAPlantedLink) {
  // A symbolic link planted at the name of a temporary file must not make the writer overwrite
  // what it points to.
  const fs::path victim = root_.parent_path() / (root_.filename().string() + "-victim.txt");
  std::ofstream(victim) << "precious";
  const fs::path temporary = root_ / (".fragments.vtp.tmp-" + std::to_string(getpid()));
  fs::create_symlink(victim, temporary);
  shadow::write_outputs(root_, scene_, result_);
  std::ifstream in(victim);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "precious");
  EXPECT_TRUE(fs::is_regular_file(root_ / "fragments.vtp"));
  EXPECT_FALSE(fs::exists(fs::symlink_status(temporary)));
  fs::remove(victim);
}

}  // namespace

// ---- issue 11, item 12: the output directory across runs --------------------------------------

namespace {

TEST_F(OutputTest, ReportCarriesTheRunsIdentity) {
  shadow::RunInfo run;
  run.scene = "city/scene.json";
  run.started_utc = "2026-11-23T13:40:00Z";
  run.options.threads = 3;
  run.options.lights = {1};
  run.options.plane_window = 25;
  run.options.arithmetic = shadow::Arithmetic::Fast;
  run.planarity_tolerance = 1e-5;
  shadow::write_outputs(root_, scene_, result_, run);
  const auto r = read_report(root_)["run"];
  EXPECT_EQ(r["scene"], "city/scene.json");
  EXPECT_EQ(r["started_utc"], "2026-11-23T13:40:00Z");
  EXPECT_EQ(r["libshadow_version"], shadow::version());
  EXPECT_EQ(r["arithmetic"], "exact");  // what the result was computed with
  EXPECT_EQ(r["options"]["threads"], 3);
  EXPECT_EQ(r["options"]["lights"], nlohmann::json::array({1}));
  EXPECT_EQ(r["options"]["plane_window"], 25.0);
  EXPECT_EQ(r["options"]["arithmetic"], "fast");
  EXPECT_EQ(r["options"]["planarity_tolerance"], 1e-5);
  // Without a RunInfo: the same object, start time unknown, no options.
  shadow::write_outputs(root_, scene_, result_);
  const auto plain = read_report(root_)["run"];
  EXPECT_TRUE(plain["started_utc"].is_null());
  EXPECT_FALSE(plain.contains("options"));
  EXPECT_EQ(plain["scene"], scene_.source.string());
}

TEST(UtcNow, IsIso8601Utc) {
  const std::string now = shadow::utc_now();
  ASSERT_EQ(now.size(), 20u) << now;
  EXPECT_EQ(now[4], '-');
  EXPECT_EQ(now[10], 'T');
  EXPECT_EQ(now.back(), 'Z');
  EXPECT_GE(now.substr(0, 4), "2024");
}

TEST_F(OutputTest, OpeningTheDirectoryRemovesTheOldReportBeforeAnyComputing) {
  shadow::write_outputs(root_, scene_, result_);
  ASSERT_TRUE(fs::exists(root_ / "report.json"));
  {
    shadow::OutputDirectory out(root_);
    // A run killed now (while computing) leaves no report.json: nothing looks complete.
    EXPECT_FALSE(fs::exists(root_ / "report.json"));
    EXPECT_TRUE(fs::exists(root_ / "fragments.vtp"));  // old data stays, without its report
    out.write(scene_, result_);
  }
  EXPECT_TRUE(fs::exists(root_ / "report.json"));
}

TEST_F(OutputTest, ASecondWriterIsRefusedWhileTheFirstHoldsTheDirectory) {
  shadow::OutputDirectory first(root_);
  EXPECT_TRUE(fs::exists(root_ / ".shadow.lock"));
  try {
    shadow::OutputDirectory second(root_);
    FAIL() << "a second writer got the directory";
  } catch (const OutputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("another shadow process is writing to this directory"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  EXPECT_THROW(shadow::write_outputs(root_, scene_, result_), OutputError);
  first.write(scene_, result_);
  EXPECT_TRUE(fs::exists(root_ / "report.json"));
}

TEST_F(OutputTest, TheLockIsReleasedAndItsFileRemovedWhenTheDirectoryIsClosed) {
  { shadow::OutputDirectory first(root_); }
  EXPECT_FALSE(fs::exists(root_ / ".shadow.lock"));
  { shadow::OutputDirectory again(root_); }
  // A lock file left by a killed process (flock dies with it) does not stop the next run.
  std::ofstream(root_ / ".shadow.lock") << "";
  EXPECT_NO_THROW(shadow::write_outputs(root_, scene_, result_));
}

TEST_F(OutputTest, StaleTemporariesOfDeadProcessesAreRemoved) {
  // PID 2147483646 exceeds any pid_max: no such process. Our own PID is alive.
  const std::vector<std::string> dead = {".fragments.vtp.tmp-2147483646", ".report.json.tmp-2147483646",
                                         ".scene.vtm.tmp-2147483646", ".report.json.old-2147483646"};
  const std::string live = ".faces.vtp.tmp-" + std::to_string(getppid());
  const std::string live_aside = ".report.json.old-" + std::to_string(getppid());
  const std::vector<std::string> foreign = {".fragments.vtp.tmp-abc", "notes.tmp-2147483646",
                                            ".other.vtp.tmp-2147483646", ".faces.vtp.old-2147483646"};
  for (const std::string& name : dead) std::ofstream(root_ / name) << "half";
  for (const std::string& name : foreign) std::ofstream(root_ / name) << "mine";
  std::ofstream(root_ / live) << "being written";
  std::ofstream(root_ / live_aside) << "being removed";
  shadow::write_outputs(root_, scene_, result_);
  for (const std::string& name : dead) EXPECT_FALSE(fs::exists(root_ / name)) << name;
  for (const std::string& name : foreign) EXPECT_TRUE(fs::exists(root_ / name)) << name;
  EXPECT_TRUE(fs::exists(root_ / live));
  EXPECT_TRUE(fs::exists(root_ / live_aside));
}

// ---- issue 30, item 10: one file staged like every output (shadow render's images) -------------

/// Writes 64 KiB through write_file_staged under a file size limit of `limit` bytes (SIGXFSZ
/// ignored: write() then fails with EFBIG where a full disk fails with ENOSPC). Returns the
/// OutputError's message, or "" when nothing was thrown.
std::string staged_write_under_limit(const fs::path& path, rlim_t limit) {
  rlimit old_limit{};
  if (getrlimit(RLIMIT_FSIZE, &old_limit) != 0) return "getrlimit failed";
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old_limit;
  small.rlim_cur = limit;
  if (setrlimit(RLIMIT_FSIZE, &small) != 0) return "setrlimit failed";
  std::string message;
  try {
    shadow::write_file_staged(path, [](std::ostream& out) { out << std::string(65536, 'x'); });
  } catch (const OutputError& e) {
    message = e.what();
  }
  setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  return message;
}

TEST_F(OutputTest, AStagedFileIsWrittenWholeUnderItsNameWithNoTemporaryLeft) {
  std::ofstream(root_ / "view.svg") << "old";
  shadow::write_file_staged(root_ / "view.svg", [](std::ostream& out) { out << "<svg/>\n"; });
  EXPECT_EQ(read_text(root_ / "view.svg"), "<svg/>\n");
  EXPECT_EQ(directory_listing(root_), std::set<std::string>{"view.svg"});
}

TEST_F(OutputTest, AStagedFileOnAFullDiskIsAnOutputErrorAndTheOldFileStays) {
  // The limit cuts the file inside the stream's last buffer or before it: either way the
  // failure must come out (the PDF used to be left cut at 4,096 bytes with exit status 0).
  for (const rlim_t limit : {rlim_t{0}, rlim_t{4096}, rlim_t{65535}}) {
    std::ofstream(root_ / "view.pdf") << "old";
    const std::string message = staged_write_under_limit(root_ / "view.pdf", limit);
    EXPECT_EQ(message.find((root_ / "view.pdf").string() + ": "), 0u) << limit << ": " << message;
    EXPECT_NE(message.find(std::strerror(EFBIG)), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(read_text(root_ / "view.pdf"), "old") << limit;
    EXPECT_EQ(directory_listing(root_), std::set<std::string>{"view.pdf"}) << limit << ": a temporary was left";
  }
}

TEST_F(OutputTest, AStagedFileWhoseWriterFailsLeavesNothing) {
  // A stream error set by the writer, and an exception thrown by it.
  EXPECT_THROW(shadow::write_file_staged(root_ / "a.png",
                                         [](std::ostream& out) {
                                           out << "half";
                                           out.setstate(std::ios::badbit);
                                         }),
               OutputError);
  EXPECT_THROW(shadow::write_file_staged(root_ / "b.png",
                                         [](std::ostream& out) {
                                           out << "half";
                                           throw std::runtime_error("drawing failed");
                                         }),
               std::runtime_error);
  EXPECT_TRUE(directory_listing(root_).empty());
}

TEST_F(OutputTest, AStagedFileInAMissingFolderIsAnOutputErrorNamingIt) {
  try {
    shadow::write_file_staged(root_ / "missing" / "view.svg", [](std::ostream& out) { out << "x"; });
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()).find((root_ / "missing" / "view.svg").string() + ": "), 0u) << e.what();
  }
  EXPECT_TRUE(directory_listing(root_).empty());
}

}  // namespace
