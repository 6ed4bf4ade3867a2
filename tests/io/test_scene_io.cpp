// SPDX-License-Identifier: GPL-3.0-or-later
// Reading scenes and OBJ meshes: what is accepted, and that every kind of bad input is an
// InputError naming the file, the place (JSON path or OBJ line) and the problem.
#include <shadow/generators.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/shadows.hpp>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using shadow::InputError;
using shadow::LoadOptions;
using shadow::Scene;
using glm::dvec3;

const fs::path kData = LIBSHADOW_TEST_DATA;
const fs::path kScenes = kData / "scenes";
const fs::path kMeshes = kData / "meshes";

/// Passes when `action` throws an InputError whose one-line message contains every part.
::testing::AssertionResult ThrowsInputError(const std::function<void()>& action,
                                            std::initializer_list<std::string> parts) {
  try {
    action();
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.find('\n') != std::string::npos)
      return ::testing::AssertionFailure() << "message is not one line: " << what;
    for (const std::string& part : parts)
      if (what.find(part) == std::string::npos)
        return ::testing::AssertionFailure() << "message lacks \"" << part << "\": " << what;
    return ::testing::AssertionSuccess() << what;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "threw something else than InputError: " << e.what();
  }
  return ::testing::AssertionFailure() << "no exception";
}

/// A scene with one inline triangle mesh and one directional light, plus `extra` JSON text
/// spliced into the top-level object (a leading comma included by the caller).
std::string minimal_scene(const std::string& light = R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})",
                          const std::string& extra = "") {
  return R"({"meshes": [{"name": "wall", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0]]]}], "lights": [)" +
         light + "]" + extra + "}";
}

Scene parse(const std::string& json, const LoadOptions& options = {}) {
  return shadow::parse_scene(json, "inline.json", options);
}

/// A temporary directory for scenes and meshes written by a test; removed afterwards.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "libshadow-scene-io-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

using Polygon = std::vector<dvec3>;

// ================================================================================================
// OBJ reading
// ================================================================================================

TEST(ObjReader, ReadsVerticesAndFacesInFileOrder) {
  const auto faces = shadow::parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n", "t.obj");
  ASSERT_EQ(faces.size(), 2u);
  EXPECT_EQ(faces[0], (Polygon{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}));
  EXPECT_EQ(faces[1], (Polygon{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
}

TEST(ObjReader, AcceptsAllFourVertexReferenceForms) {
  const std::string vertices = "v 0 0 0\nv 2 0 0\nv 0 3 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n";
  const Polygon expected{{0, 0, 0}, {2, 0, 0}, {0, 3, 0}};
  for (const std::string face : {"f 1 2 3", "f 1/1 2/2 3/3", "f 1//1 2//1 3//1", "f 1/1/1 2/2/1 3/3/1",
                                 "f 1 2/2 3//1"}) {
    const auto faces = shadow::parse_obj(vertices + face + "\n", "t.obj");
    ASSERT_EQ(faces.size(), 1u) << face;
    EXPECT_EQ(faces[0], expected) << face;
  }
}

TEST(ObjReader, NegativeIndicesCountBackFromTheLastVertexDefinedSoFar) {
  const auto faces = shadow::parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
      "f -3 -2 -1\n"
      "v 5 5 5\n"
      "f -4/-1 -3//-1 -1/1/1\n",  // -1 is now the fourth vertex
      "t.obj");
  ASSERT_EQ(faces.size(), 2u);
  EXPECT_EQ(faces[0], (Polygon{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(faces[1], (Polygon{{0, 0, 0}, {1, 0, 0}, {5, 5, 5}}));
}

TEST(ObjReader, KeepsPolygonsWithAnyNumberOfVertices) {
  const auto faces = shadow::parse_obj(
      "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 3 0\nv -1 1 0\nv -1 0.5 0\n"
      "f 1 2 3 4 5\nf 1 2 3 4 5 6\n",
      "t.obj");
  ASSERT_EQ(faces.size(), 2u);
  EXPECT_EQ(faces[0].size(), 5u);
  EXPECT_EQ(faces[1].size(), 6u);
  EXPECT_EQ(faces[1][5], dvec3(-1, 0.5, 0));
}

TEST(ObjReader, IgnoresTheOptionalWCoordinateAndTrailingVertexColours) {
  const auto faces = shadow::parse_obj("v 0 0 0 1\nv 1 0 0 1.0\nv 0 1 0 0.5 0.2 0.3\nf 1 2 3\n", "t.obj");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(faces[0], (Polygon{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
}

TEST(ObjReader, ReadsCrlfLineEndings) {
  const auto faces = shadow::parse_obj("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n", "t.obj");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(faces[0][2], dvec3(0, 1, 0));
  // An error after CRLF lines still has the right line number.
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 0\r\nv 1 0 0\r\nf 1 2 3\r\n", "crlf.obj"); },
                               {"crlf.obj", "line 3", "vertex index 3 is out of range"}));
}

TEST(ObjReader, JoinsBackslashContinuationLines) {
  const auto faces = shadow::parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 \\\n  3 \\\r\n 4\n", "t.obj");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(faces[0].size(), 4u);
  // Line numbers keep counting physical lines: the bad face starts on line 4.
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 \\\n 0\nv 1 0 0\nf 1 \\\n 2\n", "cont.obj"); },
                               {"cont.obj", "line 4", "face has 2 vertices"}));
}

TEST(ObjReader, IgnoresCommentsBlankLinesAndStatementsThatAreNotGeometry) {
  const auto faces = shadow::parse_obj(
      "# a comment\n"
      "\n"
      "mtllib scene.mtl\n"
      "o object\n"
      "g group\n"
      "s 1\n"
      "usemtl red\n"
      "v 0 0 0\n"
      "v 1 0 0  # trailing comment\n"
      "v 0 1 0\n"
      "vt 0.5 0.5\n"
      "vn 0 0 1\n"
      "vp 0.2 0.3\n"
      "l 1 2\n"
      "p 1\n"
      "curv 0 1 1 2\n"
      "s off\n"
      "   \n"
      "f 1 2 3 # the only face\n",
      "t.obj");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(faces[0], (Polygon{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
}

TEST(ObjReader, ToleratesTabsRepeatedSpacesAndNumberSpellings) {
  const auto faces = shadow::parse_obj("v\t0   0\t\t0\n  v +1.5 0 0\nv 0 1e0 -0\nf\t1  2 \t3\n", "t.obj");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(faces[0], (Polygon{{0, 0, 0}, {1.5, 0, 0}, {0, 1, 0}}));
}

TEST(ObjReader, AcceptsAUtf8ByteOrderMark) {
  const auto faces = shadow::parse_obj("\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(faces[0][0], dvec3(0, 0, 0));
}

TEST(ObjReader, AFileWithoutFacesGivesNoFaces) {
  EXPECT_TRUE(shadow::parse_obj("v 0 0 0\n# nothing else\n", "t.obj").empty());
  EXPECT_TRUE(shadow::parse_obj("", "t.obj").empty());
}

TEST(ObjReader, VertexIndexOutOfRangeIsAnErrorNamingTheLine) {
  EXPECT_TRUE(ThrowsInputError(
      [] { shadow::read_obj(kMeshes / "index_out_of_range.obj", "tiles.obj"); },
      {"tiles.obj", "line 8", "vertex index 12 is out of range (the file has 4 vertices so far)"}));
}

TEST(ObjReader, VertexIndexZeroIsAnError) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "z.obj"); },
                               {"z.obj", "line 4", "vertex index 0", "start at 1"}));
}

TEST(ObjReader, ForwardReferencesAreErrors) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", "fwd.obj"); },
                               {"fwd.obj", "line 3", "vertex index 3 is out of range (the file has 2 vertices so far)"}));
}

TEST(ObjReader, NegativeIndexBeforeTheFirstVertexIsAnError) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "neg.obj"); },
                               {"neg.obj", "line 4", "vertex index -4 is out of range"}));
}

TEST(ObjReader, HugeIndexIsOutOfRangeNotACrash) {
  EXPECT_TRUE(ThrowsInputError(
      [] { shadow::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n", "big.obj"); },
      {"big.obj", "line 4", "out of range"}));
}

TEST(ObjReader, FaceWithFewerThanThreeReferencesIsAnError) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::read_obj(kMeshes / "two_vertex_face.obj", "sliver.obj"); },
                               {"sliver.obj", "line 6", "face has 2 vertices; at least 3 are needed"}));
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 0\nf\n", "empty_face.obj"); },
                               {"empty_face.obj", "line 2", "face has 0 vertices"}));
}

TEST(ObjReader, VertexWithFewerThanThreeCoordinatesIsAnError) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 0\nv 1 2\n", "short.obj"); },
                               {"short.obj", "line 2", "vertex has 2 coordinates; 3 are needed"}));
}

TEST(ObjReader, MalformedNumbersAreErrors) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 0\nv 1.2.3 0 0\n", "m.obj"); },
                               {"m.obj", "line 2", "x coordinate \"1.2.3\" is not a number"}));
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 zero 0\n", "m.obj"); },
                               {"m.obj", "line 1", "y coordinate \"zero\" is not a number"}));
  EXPECT_TRUE(ThrowsInputError([] { shadow::parse_obj("v 0 0 1,5\n", "m.obj"); },
                               {"m.obj", "line 1", "z coordinate \"1,5\" is not a number"}));
}

TEST(ObjReader, NanAndInfiniteCoordinatesAreErrors) {
  for (const std::string bad : {"nan", "NaN", "inf", "-infinity", "1e999"}) {
    EXPECT_TRUE(ThrowsInputError([&] { shadow::parse_obj("v 0 0 0\nv 1 " + bad + " 0\n", "nan.obj"); },
                                 {"nan.obj", "line 2", "is not finite"}))
        << bad;
  }
  // Underflow is harmless: the coordinate is just (nearly) zero.
  const auto faces = shadow::parse_obj("v 0 0 1e-999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj");
  EXPECT_EQ(faces[0][0], dvec3(0, 0, 0));
}

TEST(ObjReader, MalformedFaceReferencesAreErrors) {
  for (const std::string bad : {"f 1 2 x", "f 1 2 3/1/1/1", "f 1 2 /3", "f 1 2 3.0", "f 1 2 3//"}) {
    EXPECT_TRUE(ThrowsInputError([&] { shadow::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\n" + bad + "\n", "ref.obj"); },
                                 {"ref.obj", "line 4", "is malformed"}))
        << bad;
  }
}

TEST(ObjReader, MissingFileIsAnErrorNamingTheFile) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::read_obj(kMeshes / "no_such_file.obj", "meshes/no_such_file.obj"); },
                               {"meshes/no_such_file.obj", "cannot open", "No such file"}));
  EXPECT_TRUE(ThrowsInputError([] { shadow::read_obj(kMeshes, "meshes"); }, {"meshes", "cannot open"}));
}

TEST(ObjReader, ReadsAMillionLineFileQuickly) {
  // 250k vertices on a grid and 750k triangles: a realistic large mesh.
  std::string text;
  text.reserve(30u << 20);
  const int side = 500;
  char line[128];
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", i * 0.01, j * 0.01, 0.001 * ((i * j) % 7));
      text += line;
    }
  std::size_t faces_written = 0;
  for (int i = 0; faces_written < 750000; ++i)
    for (int j = 0; j + 1 < side && faces_written < 750000; ++j, ++faces_written) {
      const int a = (i % (side - 1)) * side + j + 1;
      std::snprintf(line, sizeof line, "f %d/%d %d/%d %d/%d\n", a, a, a + 1, a + 1, a + side, a + side);
      text += line;
    }
  const auto start = std::chrono::steady_clock::now();
  const auto faces = shadow::parse_obj(text, "big.obj");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(faces.size(), 750000u);
  RecordProperty("seconds", std::to_string(seconds));
  // Well under a second on one core; the bound only guards against pathological slowness
  // on a busy machine.
  EXPECT_LT(seconds, 5.0);
}

// ================================================================================================
// Scene files: what loads
// ================================================================================================

TEST(SceneLoading, NumbersFacesAcrossTwoObjMeshesAndAnInlineMeshInInputOrder) {
  const Scene scene = shadow::load_scene(kScenes / "three_meshes.json");
  ASSERT_EQ(scene.meshes.size(), 3u);
  ASSERT_EQ(scene.faces.size(), 5u);
  EXPECT_EQ(scene.source, kScenes / "three_meshes.json");

  EXPECT_EQ(scene.meshes[0].name, "ground");
  EXPECT_EQ(scene.meshes[0].file, "../meshes/ground.obj");
  EXPECT_EQ(scene.meshes[0].first_face, 0u);
  EXPECT_EQ(scene.meshes[0].face_count, 2u);
  EXPECT_EQ(scene.meshes[1].name, "roof");
  EXPECT_EQ(scene.meshes[1].first_face, 2u);
  EXPECT_EQ(scene.meshes[1].face_count, 1u);
  EXPECT_EQ(scene.meshes[2].name, "wall");
  EXPECT_EQ(scene.meshes[2].file, "");
  EXPECT_EQ(scene.meshes[2].first_face, 3u);
  EXPECT_EQ(scene.meshes[2].face_count, 2u);

  const std::vector<std::size_t> mesh_of_face{0, 0, 1, 2, 2};
  for (std::size_t f = 0; f < 5; ++f) EXPECT_EQ(scene.faces[f].mesh, mesh_of_face[f]) << f;
  EXPECT_EQ(scene.faces[1].vertices, (Polygon{{1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}}));
  EXPECT_EQ(scene.faces[2].vertices, (Polygon{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}));
  EXPECT_EQ(scene.faces[4].vertices, (Polygon{{1, 2, 0}, {2, 2, 0}, {2, 2, 1}, {1, 2, 1}}));
  for (const auto& face : scene.faces) EXPECT_FALSE(face.degenerate);
  EXPECT_TRUE(scene.warnings.empty());
}

TEST(SceneLoading, FaceSourcesNameTheObjFileAndLineOrTheJsonPath) {
  const Scene scene = shadow::load_scene(kScenes / "three_meshes.json");
  ASSERT_EQ(scene.faces.size(), 5u);
  // OBJ faces: the mesh path joined to the scene's directory, as a user would find the file.
  EXPECT_EQ(fs::path(scene.faces[0].source.file), (kMeshes / "ground.obj").lexically_normal());
  EXPECT_EQ(scene.faces[0].source.place, "line 9");
  EXPECT_EQ(scene.faces[1].source.place, "line 10");
  EXPECT_EQ(fs::path(scene.faces[2].source.file), (kMeshes / "roof.obj").lexically_normal());
  EXPECT_EQ(scene.faces[2].source.place, "line 8");
  // Inline faces: the scene file and the JSON path of the polygon.
  EXPECT_EQ(fs::path(scene.faces[3].source.file), kScenes / "three_meshes.json");
  EXPECT_EQ(scene.faces[3].source.place, "meshes[2].polygons[0]");
  EXPECT_EQ(scene.faces[4].source.place, "meshes[2].polygons[1]");
}

TEST(SceneLoading, ReadsLightsWithTheirDefaultsAndPlanes) {
  const Scene scene = shadow::load_scene(kScenes / "three_meshes.json");
  ASSERT_EQ(scene.lights.size(), 2u);
  EXPECT_EQ(scene.lights[0].name, "sun");
  EXPECT_EQ(scene.lights[0].type, shadow::LightType::Directional);
  EXPECT_EQ(scene.lights[0].to_light, dvec3(0.4, 0.3, 0.85));
  EXPECT_EQ(scene.lights[0].intensity, 1.0);
  EXPECT_EQ(scene.lights[0].color, dvec3(1, 1, 1));
  EXPECT_EQ(scene.lights[1].name, "lamp");
  EXPECT_EQ(scene.lights[1].type, shadow::LightType::Point);
  EXPECT_EQ(scene.lights[1].position, dvec3(1.0, 2.0, 9.5));
  EXPECT_EQ(scene.lights[1].intensity, 2.5);
  EXPECT_EQ(scene.lights[1].color, dvec3(1, 0.5, 0));
  ASSERT_EQ(scene.planes.size(), 1u);
  EXPECT_EQ(scene.planes[0].name, "floor");
  EXPECT_EQ(scene.planes[0].point, dvec3(0, 0, -1));
  EXPECT_EQ(scene.planes[0].normal, dvec3(0, 0, 1));
}

TEST(SceneLoading, ReceiversListRestrictsWhichMeshesReceiveLight) {
  const Scene scene = shadow::load_scene(kScenes / "three_meshes.json");
  EXPECT_TRUE(scene.meshes[0].receiver);
  EXPECT_FALSE(scene.meshes[1].receiver);
  EXPECT_TRUE(scene.meshes[2].receiver);
  EXPECT_TRUE(scene.is_receiver(0));
  EXPECT_FALSE(scene.is_receiver(2));
  EXPECT_TRUE(scene.is_receiver(4));
}

TEST(SceneLoading, EveryMeshReceivesLightWhenNoReceiversAreGiven) {
  const Scene scene = parse(minimal_scene());
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_TRUE(scene.meshes[0].receiver);
  EXPECT_TRUE(scene.planes.empty());
}

TEST(SceneLoading, AnEmptyReceiversListMeansNoMeshReceives) {
  const Scene scene = parse(minimal_scene(R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})",
                                          R"(, "receivers": [])"));
  EXPECT_FALSE(scene.meshes[0].receiver);
}

TEST(SceneLoading, UnknownReceiverNameIsAnError) {
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})",
                               R"(, "receivers": ["wall", "wal"])")); },
      {"inline.json", "receivers[1]", "no mesh is named \"wal\""}));
}

TEST(SceneLoading, AllowsMaterialsCameraCommentAndSchemaKeys) {
  const Scene scene = parse(R"({
    "$schema": "https://example.org/scene.schema.json",
    "_comment": "ignored",
    "materials": [{"name": "plaster"}],
    "camera": {"eye": [0, 0, 10]},
    "meshes": [{"name": "wall", "_note": "ok", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0]]]}],
    "lights": [{"name": "sun", "_note": "ok", "type": "directional", "to_light": [0, 0, 1]}],
    "planes": [{"name": "ground", "$ref": "x", "point": [0, 0, 0], "normal": [0, 0, 2]}]
  })");
  EXPECT_EQ(scene.faces.size(), 1u);
  EXPECT_EQ(scene.planes.size(), 1u);
}

TEST(SceneLoading, ReadsTheCameraKeyByKey) {
  const std::string sun = R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})";
  EXPECT_FALSE(parse(minimal_scene()).camera.has_value());

  const Scene full = parse(minimal_scene(
      sun, R"(, "camera": {"eye": [1, 2, 3], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45, "_why": "x"})"));
  ASSERT_TRUE(full.camera.has_value());
  EXPECT_EQ(full.camera->eye, std::optional<glm::dvec3>(glm::dvec3(1, 2, 3)));
  EXPECT_EQ(full.camera->target, std::optional<glm::dvec3>(glm::dvec3(0, 0.5, 0)));
  EXPECT_EQ(full.camera->up, std::optional<glm::dvec3>(glm::dvec3(0, 1, 0)));
  EXPECT_EQ(full.camera->fov_degrees, std::optional<double>(45.0));

  // Keys that are not given stay empty: the renderer's defaults fill them.
  const Scene partial = parse(minimal_scene(sun, R"(, "camera": {"fov": 20})"));
  ASSERT_TRUE(partial.camera.has_value());
  EXPECT_FALSE(partial.camera->eye.has_value());
  EXPECT_FALSE(partial.camera->target.has_value());
  EXPECT_FALSE(partial.camera->up.has_value());
  EXPECT_EQ(partial.camera->fov_degrees, std::optional<double>(20.0));
  EXPECT_TRUE(parse(minimal_scene(sun, R"(, "camera": {})")).camera.has_value());
}

TEST(SceneLoading, BadCameraValuesAreErrorsAtTheirJsonPath) {
  const std::string sun = R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})";
  auto with_camera = [&](const std::string& camera) {
    return [json = minimal_scene(sun, R"(, "camera": )" + camera)] { parse(json); };
  };
  EXPECT_TRUE(ThrowsInputError(with_camera("[0, 0, 1]"),
                               {"inline.json", "camera", "expected an object {\"eye\", \"target\", \"up\", \"fov\"}"}));
  EXPECT_TRUE(ThrowsInputError(with_camera(R"({"pos": [0, 0, 1]})"),
                               {"inline.json", "camera",
                                "unknown key \"pos\" (known: \"eye\", \"target\", \"up\", \"fov\")"}));
  EXPECT_TRUE(ThrowsInputError(with_camera(R"({"eye": [0.5, 0.5]})"),
                               {"inline.json", "camera.eye", "expected 3 numbers [x, y, z]"}));
  EXPECT_TRUE(ThrowsInputError(with_camera(R"({"target": "origin"})"),
                               {"inline.json", "camera.target", "expected 3 numbers [x, y, z]"}));
  EXPECT_TRUE(ThrowsInputError(with_camera(R"({"up": [0, null, 1]})"),
                               {"inline.json", "camera.up[1]", "expected a finite number"}));
  EXPECT_TRUE(ThrowsInputError(with_camera(R"({"fov": 0.5})"),
                               {"inline.json", "camera.fov", "expected a vertical view angle in degrees, in [1, 170]"}));
  EXPECT_TRUE(ThrowsInputError(with_camera(R"({"fov": "wide"})"),
                               {"inline.json", "camera.fov", "expected a vertical view angle in degrees, in [1, 170]"}));
}

TEST(SceneLoading, InlineMeshWithoutFacesLoadsWithAWarning) {
  TempDir dir;
  const fs::path file = dir.write("scene.json", R"({"meshes": [
      {"name": "none", "polygons": []},
      {"name": "wall", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0]]]}],
    "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  const Scene scene = shadow::load_scene(file);
  ASSERT_EQ(scene.faces.size(), 1u);
  EXPECT_EQ(scene.meshes[0].face_count, 0u);
  EXPECT_EQ(scene.meshes[1].first_face, 0u);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0].where.place, "meshes[0]");
  EXPECT_NE(scene.warnings[0].message.find("has no faces"), std::string::npos);
}

TEST(SceneLoading, MeshFileWithoutFacesIsAnError) {
  // An OBJ file (or a file taken for one) with no face would give a silently empty result.
  TempDir dir;
  dir.write("empty.obj", "# nothing here\nv 0 0 0\n");
  const std::string mesh = R"({"meshes": [{"name": "wall", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0]]]},
      {"name": "nothing", "file": "FILE"}], "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})";
  auto scene_naming = [&](const std::string& name) {
    std::string text = mesh;
    text.replace(text.find("FILE"), 4, name);
    return dir.write("scene.json", text);
  };
  EXPECT_TRUE(ThrowsInputError([&] { shadow::load_scene(scene_naming("empty.obj")); },
                               {"scene.json: meshes[1].file", "empty.obj\" has no faces: no f statements"}));
  // JSON that is no model is not read as OBJ either.
  dir.write("points.json", R"({"points": [[0, 0, 0], [1, 0, 0]]})");
  EXPECT_TRUE(ThrowsInputError([&] { shadow::load_scene(scene_naming("points.json")); },
                               {"scene.json: meshes[1].file", "points.json\" is JSON but neither CityJSON",
                                "nor EnergyPlus epJSON"}));
}

TEST(SceneLoading, EnergyPlusShadingKeyAndMeshModel) {
  const Scene unasked = parse(minimal_scene());
  EXPECT_FALSE(unasked.energyplus_shading.has_value());
  EXPECT_EQ(unasked.meshes[0].model, "");
  const Scene asked = parse(minimal_scene(R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})",
                                          R"(, "energyplus_shading": true)"));
  EXPECT_EQ(asked.energyplus_shading, std::optional<bool>(true));
  EXPECT_TRUE(ThrowsInputError([] { parse(minimal_scene(R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})",
                                                         R"(, "energyplus_shading": "yes")")); },
                               {"inline.json: energyplus_shading", "expected true or false, got"}));
}

TEST(SceneLoading, IntegerAndFloatingPointCoordinatesAreBothNumbers) {
  const Scene scene = parse(R"({"meshes": [{"name": "m", "polygons": [[[0, 0, 0], [1.5, 0, 0], [1, 1e0, -0.0]]]}],
                                "lights": [{"name": "p", "type": "point", "position": [-3, 2, 1e2]}]})");
  EXPECT_EQ(scene.faces[0].vertices[1], dvec3(1.5, 0, 0));
  EXPECT_EQ(scene.lights[0].position, dvec3(-3, 2, 100));
}

TEST(SceneLoading, RemovesConsecutiveDuplicateVerticesIncludingTheClosingRepeat) {
  const Scene scene = parse(R"({"meshes": [{"name": "m", "polygons": [
      [[0, 0, 0], [0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 0], [1, 1, 0], [0, 1, 0], [0, 0, 0]]]}],
    "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  EXPECT_EQ(scene.faces[0].vertices, (Polygon{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));

  TempDir dir;
  dir.write("dup.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2 3 1\n");
  const fs::path file = dir.write("scene.json", R"({"meshes": [{"name": "m", "file": "dup.obj"}],
      "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  EXPECT_EQ(shadow::load_scene(file).faces[0].vertices, (Polygon{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
}

TEST(SceneLoading, FaceWithFewerThanThreeDistinctVerticesAfterRemovingRepeatsIsAnError) {
  EXPECT_TRUE(ThrowsInputError(
      [] {
        parse(R"({"meshes": [{"name": "m", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0]],
                                                           [[0, 0, 0], [1, 0, 0], [1, 0, 0], [0, 0, 0]]]}],
                  "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
      },
      {"inline.json", "meshes[0].polygons[1]", "face has 2 distinct vertices; at least 3 are needed"}));

  TempDir dir;
  dir.write("dup.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 2\n");
  const fs::path file = dir.write("scene.json", R"({"meshes": [{"name": "m", "file": "dup.obj"}],
      "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  EXPECT_TRUE(ThrowsInputError([&] { shadow::load_scene(file); },
                               {"dup.obj", "line 5", "face has 2 distinct vertices"}));
}

TEST(SceneLoading, ZeroAreaFaceIsKeptInTheNumberingMarkedDegenerateWithAWarning) {
  const Scene scene = shadow::load_scene(kScenes / "collinear.json");
  ASSERT_EQ(scene.faces.size(), 3u);  // the collinear face keeps face_id 1
  EXPECT_FALSE(scene.faces[0].degenerate);
  EXPECT_TRUE(scene.faces[1].degenerate);
  EXPECT_FALSE(scene.faces[2].degenerate);
  EXPECT_EQ(scene.meshes[1].first_face, 2u);
  ASSERT_EQ(scene.warnings.size(), 1u);
  const std::string warning = scene.warnings[0].to_string();
  EXPECT_NE(warning.find("collinear.obj: line 9"), std::string::npos) << warning;
  EXPECT_NE(warning.find("face has zero area"), std::string::npos) << warning;
}

TEST(SceneLoading, FaceWithinThePlanarityToleranceIsAccepted) {
  // One corner 1e-8 off the plane of a unit square: well within 1e-6 x diameter.
  const Scene scene = parse(R"({"meshes": [{"name": "m", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 1e-8], [0, 1, 0]]]}],
                                "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  EXPECT_EQ(scene.faces.size(), 1u);
  EXPECT_FALSE(scene.faces[0].degenerate);
}

TEST(SceneLoading, FaceBeyondThePlanarityToleranceIsAnError) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "nonplanar.json"); },
                               {"nonplanar.obj", "line 7", "face is not planar", "a vertex is 0.0249",
                                "tolerance 1e-06 x diameter 1 = 1e-06"}));
  EXPECT_TRUE(ThrowsInputError(
      [] {
        parse(R"({"meshes": [{"name": "m", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 1e-5], [0, 1, 0]]]}],
                  "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
      },
      {"inline.json", "meshes[0].polygons[0]", "face is not planar"}));
}

TEST(SceneLoading, PlanarityToleranceIsAnOption) {
  LoadOptions lenient;
  lenient.planarity_tolerance = 0.1;
  const Scene scene = shadow::load_scene(kScenes / "nonplanar.json", lenient);
  EXPECT_EQ(scene.faces.size(), 1u);
}

TEST(SceneLoading, PlanarityIsJudgedRelativeToTheFaceSizeFarFromTheOrigin) {
  // A tilted planar quad of size 1e-3 at 1e6 from the origin: rounding must not make it
  // look non-planar.
  const Scene scene = parse(R"({"meshes": [{"name": "m", "polygons": [
      [[1000000.0, 2000000.0, 3000000.0], [1000000.001, 2000000.0, 3000000.0005],
       [1000000.001, 2000000.001, 3000000.0015], [1000000.0, 2000000.001, 3000000.001]]]}],
    "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  EXPECT_EQ(scene.faces.size(), 1u);
}

TEST(SceneLoading, SelfIntersectingFaceIsAnError) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "bowtie.json"); },
                               {"bowtie.obj", "line 7", "face boundary intersects itself"}));
}

// ================================================================================================
// Scene files: errors name the file, the place and the problem
// ================================================================================================

TEST(SceneErrors, MalformedJsonNamesLineAndColumn) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "malformed.json"); },
                               {"malformed.json", "line 5, column 5", "malformed JSON", "expected ']'"}));
  EXPECT_TRUE(ThrowsInputError([] { parse("{\n  \"meshes\": [1, 2,\n"); },
                               {"inline.json", "line 3, column 1", "unexpected end of input"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(""); }, {"inline.json", "line 1, column 1", "malformed JSON"}));
  EXPECT_TRUE(ThrowsInputError([] { parse("{\"meshes\": tru}"); },
                               {"inline.json", "line 1, column 15", "invalid literal"}));
}

TEST(SceneErrors, MalformedJsonMessageStaysOnOneLine) {
  EXPECT_TRUE(ThrowsInputError([] { parse("{\"meshes\": \"a\nb\"}"); }, {"inline.json", "line 1", "control character"}));
}

TEST(SceneErrors, UnreadableSceneFileIsAnErrorNamingIt) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "no_such_scene.json"); },
                               {"no_such_scene.json", "cannot open", "No such file"}));
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes); }, {"scenes", "cannot open"}));
}

TEST(SceneErrors, TopLevelMustBeAnObjectWithMeshesAndLights) {
  EXPECT_TRUE(ThrowsInputError([] { parse("[1, 2]"); }, {"inline.json", "must be a JSON object", "got an array"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(R"({"lights": []})"); }, {"inline.json", "missing \"meshes\""}));
  EXPECT_TRUE(ThrowsInputError([] { parse(R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0],[0,1,0]]]}]})"); },
                               {"inline.json", "missing \"lights\""}));
  EXPECT_TRUE(ThrowsInputError([] { parse(R"({"meshes": [], "lights": []})"); },
                               {"inline.json", "meshes", "at least one is needed"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(R"({"meshes": {}, "lights": []})"); },
                               {"inline.json", "meshes", "expected an array, got an object"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0],[0,1,0]]]}], "lights": []})"); },
      {"inline.json", "lights", "no lights; at least one is needed"}));
}

TEST(SceneErrors, UnknownKeysAreErrorsNamingTheirPlace) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "unknown_key.json"); },
                               {"unknown_key.json", "lights[1]", "unknown key \"postion\"", "did you mean \"position\"?"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(minimal_scene(R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})",
                                                       R"(, "plane": [])")); },
                               {"inline.json", "unknown key \"plane\"", "did you mean \"planes\"?"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(R"({"meshes": [{"name": "m", "polygon": []}], "lights": []})"); },
      {"inline.json", "meshes[0]", "unknown key \"polygon\""}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})",
                               R"(, "planes": [{"name": "g", "point": [0,0,0], "normal": [0,0,1], "offset": 2}])")); },
      {"inline.json", "planes[0]", "unknown key \"offset\""}));
}

TEST(SceneErrors, KeysThatAreNotPlainNamesAreQuotedInPaths) {
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(R"({"meshes": [{"name": "m", "poly\ngons": []}], "lights": []})"); },
      {"inline.json", "meshes[0]", "unknown key \"poly\\ngons\""}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(R"({"meshes": [{"name": "m", "polygons": []}], "lights": [], "a b": {"c": 1e999}})"); },
      {"inline.json", "[\"a b\"].c", "not finite"}));
}

TEST(SceneErrors, DuplicateKeysAreErrors) {
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(R"({"meshes": [{"name": "a", "name": "b", "polygons": []}], "lights": []})"); },
      {"inline.json", "meshes[0]", "duplicate key \"name\""}));
}

TEST(SceneErrors, MeshNeedsAUniqueNameAndExactlyOneOfFileOrPolygons) {
  const std::string light = R"(, "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})";
  EXPECT_TRUE(ThrowsInputError([&] { parse(R"({"meshes": [{"polygons": []}])" + light); },
                               {"inline.json", "meshes[0]", "missing \"name\""}));
  EXPECT_TRUE(ThrowsInputError([&] { parse(R"({"meshes": [{"name": 7, "polygons": []}])" + light); },
                               {"inline.json", "meshes[0].name", "expected a string"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "a", "polygons": []}, {"name": "a", "polygons": []}])" + light); },
      {"inline.json", "meshes[1].name", "mesh name \"a\" is already used by meshes[0]"}));
  EXPECT_TRUE(ThrowsInputError([&] { parse(R"({"meshes": [{"name": "a", "file": "x.obj", "polygons": []}])" + light); },
                               {"inline.json", "meshes[0]", "not both"}));
  EXPECT_TRUE(ThrowsInputError([&] { parse(R"({"meshes": [{"name": "a"}])" + light); },
                               {"inline.json", "meshes[0]", "missing \"file\"", "\"polygons\""}));
  EXPECT_TRUE(ThrowsInputError([&] { parse(R"({"meshes": [{"name": "a", "file": 3}])" + light); },
                               {"inline.json", "meshes[0].file", "expected a file name"}));
  EXPECT_TRUE(ThrowsInputError([&] { parse(R"({"meshes": ["a"])" + light); },
                               {"inline.json", "meshes[0]", "expected a mesh", "got string \"a\""}));
}

TEST(SceneErrors, InlinePolygonsAreCheckedVertexByVertex) {
  const std::string light = R"(, "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})";
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0],[0,1,0],[0,"1",0]]]}])" + light); },
      {"inline.json", "meshes[0].polygons[0][3][1]", "expected a number, got string \"1\""}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0],[0,1,null]]]}])" + light); },
      {"inline.json", "meshes[0].polygons[0][2][2]", "got null"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0],[0,1,0]]]}])" + light); },
      {"inline.json", "meshes[0].polygons[0][1]", "expected 3 numbers [x, y, z], got 2 elements"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0]]]}])" + light); },
      {"inline.json", "meshes[0].polygons[0]", "polygon has 2 vertices; at least 3 are needed"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "m", "polygons": [{"a": 1}]}])" + light); },
      {"inline.json", "meshes[0].polygons[0]", "unknown key \"a\""}));  // the object form: {"vertices", "name", ...}
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "m", "polygons": [{"name": "w"}]}])" + light); },
      {"inline.json", "meshes[0].polygons[0]", "missing \"vertices\""}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "m", "polygons": [7]}])" + light); },
      {"inline.json", "meshes[0].polygons[0]", "expected a polygon"}));
  // A common slip: one level of brackets too few.
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(R"({"meshes": [{"name": "m", "polygons": [[0,0,0],[1,0,0],[0,1,0]]}])" + light); },
      {"inline.json", "meshes[0].polygons[0]", "got an array of numbers"}));
}

TEST(SceneErrors, NumberTooLargeForADoubleIsANonFiniteCoordinateAtItsPath) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "huge_coordinate.json"); },
                               {"huge_coordinate.json", "meshes[0].polygons[0][1][2]", "1e999", "not finite"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "sun", "type": "directional", "to_light": [0, -1e400, 1]})")); },
      {"inline.json", "lights[0].to_light[1]", "not finite"}));
}

TEST(SceneErrors, MissingMeshFileNamesTheSceneTheMeshAndTheFile) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "missing_mesh_file.json"); },
                               {"missing_mesh_file.json", "meshes[1].file", "cannot open",
                                (kMeshes / "no_such_statue.obj").lexically_normal().string(), "No such file"}));
}

TEST(SceneErrors, ErrorsInsideAnObjFileNameThatFileAndLine) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "index_out_of_range.json"); },
                               {(kMeshes / "index_out_of_range.obj").lexically_normal().string(), "line 8",
                                "vertex index 12 is out of range (the file has 4 vertices so far)"}));
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "two_vertex_face.json"); },
                               {"two_vertex_face.obj", "line 6", "face has 2 vertices"}));
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "nan_vertex.json"); },
                               {"nan_vertex.obj", "line 4", "\"nan\" is not finite"}));
}

TEST(SceneErrors, MeshFilesAreRelativeToTheSceneFile) {
  TempDir dir;
  dir.write("meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const fs::path scene_file = dir.write("sub/scene.json", R"({"meshes": [{"name": "m", "file": "../meshes/tri.obj"}],
      "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  const Scene scene = shadow::load_scene(scene_file);
  ASSERT_EQ(scene.faces.size(), 1u);
  EXPECT_EQ(fs::path(scene.faces[0].source.file), (dir.path() / "meshes/tri.obj").lexically_normal());
  EXPECT_EQ(scene.faces[0].source.place, "line 4");
}

TEST(SceneErrors, DirectionalLightToLightMustBeNonZero) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "zero_to_light.json"); },
                               {"zero_to_light.json", "lights[1].to_light", "direction has zero length"}));
}

TEST(SceneErrors, UnknownLightTypeNamesTheKnownTypes) {
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene(kScenes / "unknown_light_type.json"); },
                               {"unknown_light_type.json", "lights[0].type", "unknown light type \"spot\"",
                                "\"directional\", \"point\""}));
  EXPECT_TRUE(ThrowsInputError([] { parse(minimal_scene(R"({"name": "s", "type": "Directional", "to_light": [0, 0, 1]})")); },
                               {"lights[0].type", "did you mean \"directional\"?"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(minimal_scene(R"({"name": "s", "to_light": [0, 0, 1]})")); },
                               {"inline.json", "lights[0]", "missing \"type\""}));
  EXPECT_TRUE(ThrowsInputError([] { parse(minimal_scene(R"({"name": "s", "type": 1, "to_light": [0, 0, 1]})")); },
                               {"inline.json", "lights[0].type", "got number"}));
}

TEST(SceneErrors, LightVectorsMustMatchTheLightType) {
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "directional", "to_light": [0, 0, 1], "position": [0, 0, 1]})")); },
      {"inline.json", "lights[0].position", "a directional light has no position"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "point", "position": [0, 0, 1], "to_light": [0, 0, 1]})")); },
      {"inline.json", "lights[0].to_light", "a point light has no \"to_light\""}));
  EXPECT_TRUE(ThrowsInputError([] { parse(minimal_scene(R"({"name": "s", "type": "directional"})")); },
                               {"inline.json", "lights[0]", "missing \"to_light\""}));
  EXPECT_TRUE(ThrowsInputError([] { parse(minimal_scene(R"({"name": "s", "type": "point"})")); },
                               {"inline.json", "lights[0]", "missing \"position\""}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "point", "position": [0, 0]})")); },
      {"inline.json", "lights[0].position", "expected 3 numbers [x, y, z], got 2 elements"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "point", "position": "0 0 1"})")); },
      {"inline.json", "lights[0].position", "expected an array of 3 numbers"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "directional", "to_light": [0, true, 1]})")); },
      {"inline.json", "lights[0].to_light[1]", "expected a number, got true"}));
}

TEST(SceneErrors, LightIntensityAndColorAreChecked) {
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "directional", "to_light": [0, 0, 1], "intensity": -1})")); },
      {"inline.json", "lights[0].intensity", "must be >= 0"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "directional", "to_light": [0, 0, 1], "intensity": "high"})")); },
      {"inline.json", "lights[0].intensity", "expected a number"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "directional", "to_light": [0, 0, 1], "color": [1, 1.5, 0]})")); },
      {"inline.json", "lights[0].color[1]", "must be in [0, 1]"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(minimal_scene(R"({"name": "s", "type": "directional", "to_light": [0, 0, 1], "color": [1, 1]})")); },
      {"inline.json", "lights[0].color", "expected 3 numbers [r, g, b]"}));
  const Scene scene =
      parse(minimal_scene(R"({"name": "s", "type": "directional", "to_light": [0, 0, 1], "intensity": 0, "color": [0, 0, 0]})"));
  EXPECT_EQ(scene.lights[0].intensity, 0.0);
}

TEST(SceneErrors, LightsNeedUniqueNames) {
  EXPECT_TRUE(ThrowsInputError([] { parse(minimal_scene(R"({"type": "directional", "to_light": [0, 0, 1]})")); },
                               {"inline.json", "lights[0]", "missing \"name\""}));
  EXPECT_TRUE(ThrowsInputError(
      [] {
        parse(minimal_scene(R"({"name": "s", "type": "directional", "to_light": [0, 0, 1]},
                               {"name": "s", "type": "point", "position": [0, 0, 1]})"));
      },
      {"inline.json", "lights[1].name", "light name \"s\" is already used by lights[0]"}));
}

TEST(SceneErrors, PlanesNeedAUniqueNameAPointAndANonZeroNormal) {
  const std::string sun = R"({"name": "sun", "type": "directional", "to_light": [0, 0, 1]})";
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(minimal_scene(sun, R"(, "planes": [{"name": "g", "point": [0,0,0], "normal": [0,0,0]}])")); },
      {"inline.json", "planes[0].normal", "zero length"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(minimal_scene(sun, R"(, "planes": [{"name": "g", "normal": [0,0,1]}])")); },
      {"inline.json", "planes[0]", "missing \"point\""}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(minimal_scene(sun, R"(, "planes": [{"name": "g", "point": [0,0,0]}])")); },
      {"inline.json", "planes[0]", "missing \"normal\""}));
  EXPECT_TRUE(ThrowsInputError(
      [&] {
        parse(minimal_scene(sun, R"(, "planes": [{"name": "g", "point": [0,0,0], "normal": [0,0,1]},
                                                 {"name": "g", "point": [0,0,1], "normal": [0,0,1]}])"));
      },
      {"inline.json", "planes[1].name", "already used by planes[0]"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(minimal_scene(sun, R"(, "planes": {"name": "g"})")); },
      {"inline.json", "planes", "expected an array"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse(minimal_scene(sun, R"(, "planes": [{"name": "g", "point": [0,0,0], "normal": [0,0,1], "window": 0}])")); },
      {"inline.json", "planes[0].window", "must be > 0"}));
  const Scene scene =
      parse(minimal_scene(sun, R"(, "planes": [{"name": "g", "point": [0,0,0], "normal": [0,0,1], "window": 25}])"));
  EXPECT_EQ(scene.planes.at(0).window, 25.0);
}

// ================================================================================================
// validate_scene on scenes built in code
// ================================================================================================

Scene scene_in_code(std::vector<Polygon> polygons) {
  Scene scene;
  shadow::Mesh mesh;
  mesh.name = "m";
  mesh.face_count = polygons.size();
  scene.meshes.push_back(mesh);
  for (Polygon& p : polygons) {
    shadow::Face face;
    face.vertices = std::move(p);
    scene.faces.push_back(std::move(face));
  }
  shadow::Light sun;
  sun.name = "sun";
  sun.to_light = {0, 0, 1};
  scene.lights.push_back(sun);
  return scene;
}

const Polygon kSquare{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

TEST(ValidateScene, AcceptsAGoodSceneBuiltInCode) {
  Scene scene = scene_in_code({kSquare});
  shadow::validate_scene(scene);
  EXPECT_FALSE(scene.faces[0].degenerate);
  EXPECT_TRUE(scene.warnings.empty());
}

TEST(ValidateScene, NamesFacesBuiltInCodeByFaceId) {
  Scene scene = scene_in_code({kSquare, {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(scene); }, {"face 1", "intersects itself"}));
}

TEST(ValidateScene, RejectsNonFiniteCoordinates) {
  Scene scene = scene_in_code({{{0, 0, 0}, {1, 0, 0}, {0, std::nan(""), 0}}});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(scene); }, {"face 0", "vertex 2", "not finite"}));
  Scene inf = scene_in_code({{{0, 0, 0}, {1, 0, HUGE_VAL}, {0, 1, 0}}});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(inf); }, {"face 0", "vertex 1", "not finite"}));
}

TEST(ValidateScene, RejectsFacesWithFewerThanThreeVertices) {
  Scene scene = scene_in_code({kSquare, {{0, 0, 0}, {1, 0, 0}}});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(scene); },
                               {"face 1", "face has 2 distinct vertices; at least 3 are needed"}));
}

TEST(ValidateScene, RemovesConsecutiveDuplicatesOfFacesBuiltInCode) {
  Scene scene = scene_in_code({{{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}}});
  shadow::validate_scene(scene);
  EXPECT_EQ(scene.faces[0].vertices, (Polygon{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}));
}

TEST(ValidateScene, RejectsBadLightsAndPlanesByTheirIndex) {
  Scene zero = scene_in_code({kSquare});
  zero.lights[0].to_light = {0, 0, 0};
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(zero); }, {"lights[0].to_light", "zero length"}));

  Scene nan_point = scene_in_code({kSquare});
  shadow::Light lamp;
  lamp.type = shadow::LightType::Point;
  lamp.position = {0, std::nan(""), 1};
  nan_point.lights.push_back(lamp);
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(nan_point); }, {"lights[1].position", "not finite"}));

  Scene dark = scene_in_code({kSquare});
  dark.lights[0].intensity = -2;
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(dark); }, {"lights[0].intensity", ">= 0"}));

  Scene flat = scene_in_code({kSquare});
  flat.planes.push_back({"ground", {0, 0, 0}, {0, 0, 0}});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(flat); }, {"planes[0].normal", "zero length"}));
}

TEST(ValidateScene, RejectsAFaceOfAMeshThatDoesNotExist) {
  Scene scene = scene_in_code({kSquare});
  scene.faces[0].mesh = 3;
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(scene); }, {"face 0", "mesh 3"}));
}

TEST(ValidateScene, ZeroAreaFaceIsMarkedOnceEvenWhenValidatedTwice) {
  Scene scene = scene_in_code({kSquare, {{0, 0, 0}, {1, 1, 1}, {3, 3, 3}}});
  shadow::validate_scene(scene);
  shadow::validate_scene(scene);
  EXPECT_TRUE(scene.faces[1].degenerate);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0].where.place, "face 1");
}

TEST(ValidateScene, RejectsANonPositivePlanarityTolerance) {
  Scene scene = scene_in_code({kSquare});
  LoadOptions options;
  options.planarity_tolerance = 0;
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(scene, options); }, {"planarity tolerance"}));
}

}  // namespace

// ---- materials ---------------------------------------------------------------------------------

namespace {

/// A scene with a wall mesh that may name a material, and `materials` JSON text.
std::string scene_with_materials(const std::string& materials, const std::string& mesh_material = "") {
  return R"({"materials": )" + materials + R"(, "meshes": [{"name": "wall", )" +
         (mesh_material.empty() ? std::string() : R"("material": )" + mesh_material + ", ") +
         R"("polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0]]]}, {"name": "floor", "polygons": [[[0, 0, 1], [1, 0, 1], [1, 1, 1]]]}],
      "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})";
}

}  // namespace

TEST(SceneMaterials, ReadsEveryKeyAndAssignsMaterialsToMeshes) {
  const Scene scene = parse(scene_with_materials(
      R"([{"name": "brick", "k_a": 0.1, "k_d": 0.6, "k_s": 0.05, "shininess": 8,
           "color": [0.7, 0.3, 0.2], "specular_color": [1, 1, 0.5]},
          {"name": "glass"}])",
      R"("brick")"));
  ASSERT_EQ(scene.materials.size(), 2u);
  const shadow::Material& brick = scene.materials[0];
  EXPECT_EQ(brick.name, "brick");
  EXPECT_EQ(brick.k_a, 0.1);
  EXPECT_EQ(brick.k_d, 0.6);
  EXPECT_EQ(brick.k_s, 0.05);
  EXPECT_EQ(brick.shininess, 8.0);
  EXPECT_EQ(brick.color, dvec3(0.7, 0.3, 0.2));
  EXPECT_EQ(brick.specular_color, dvec3(1, 1, 0.5));
  // Keys not given keep the defaults of Material{}.
  const shadow::Material defaults{};
  EXPECT_EQ(scene.materials[1].k_d, defaults.k_d);
  EXPECT_EQ(scene.materials[1].shininess, defaults.shininess);
  EXPECT_EQ(scene.meshes[0].material, "brick");
  EXPECT_EQ(scene.meshes[1].material, "");
  EXPECT_EQ(&scene.material_of(0), &scene.materials[0]);
  EXPECT_EQ(scene.material_of(1).name, "");
  EXPECT_EQ(scene.material_of(1).k_d, defaults.k_d);
}

TEST(SceneMaterials, AnUnknownMaterialNameIsAnErrorWithASuggestion) {
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "brick"}])", R"("brik")")); },
                               {"inline.json", "meshes[0].material", "no material is named \"brik\"", "brick"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials("[]", R"("brick")")); },
                               {"inline.json", "meshes[0].material", "no material is named \"brick\""}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "brick"}])", "3")); },
                               {"inline.json", "meshes[0].material", "expected a material name"}));
}

TEST(SceneMaterials, BadMaterialsNameThePlaceAndTheProblem) {
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"({"name": "brick"})")); },
                               {"inline.json", "materials", "expected an array"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"k_d": 0.5}])")); },
                               {"inline.json", "materials[0]", "missing \"name\""}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a"}, {"name": "a"}])")); },
                               {"inline.json", "materials[1].name", "already used by materials[0]"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "k_d": -0.5}])")); },
                               {"inline.json", "materials[0].k_d", "k_d must be >= 0"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "shininess": "high"}])")); },
                               {"inline.json", "materials[0].shininess", "expected a number"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "color": [1, 2, 0]}])")); },
                               {"inline.json", "materials[0].color[1]", "must be in [0, 1]"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "specular_color": [1]}])")); },
                               {"inline.json", "materials[0].specular_color", "expected 3 numbers"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "kd": 0.5}])")); },
                               {"inline.json", "materials[0]", "unknown key \"kd\""}));
}

TEST(SceneMaterials, ReflectanceAndEmittanceForRadiosity) {
  const Scene scene = parse(scene_with_materials(
      R"([{"name": "white", "reflectance": 0.75, "emittance": 12.5},
          {"name": "red", "reflectance": [0.6, 0.3, 0.0]}, {"name": "plain"}])",
      R"("white")"));
  ASSERT_EQ(scene.materials.size(), 3u);
  EXPECT_EQ(scene.materials[0].reflectance, 0.75);
  EXPECT_EQ(scene.materials[0].reflectance_rgb, dvec3(0.75));
  EXPECT_EQ(scene.materials[0].emittance, 12.5);
  EXPECT_DOUBLE_EQ(scene.materials[1].reflectance, 0.3);
  EXPECT_EQ(scene.materials[1].reflectance_rgb, dvec3(0.6, 0.3, 0.0));
  EXPECT_EQ(scene.materials[1].emittance, 0.0);
  // Not given: black and dark, so that scenes written before radiosity mean what they meant.
  EXPECT_EQ(scene.materials[2].reflectance, 0.0);
  EXPECT_EQ(scene.materials[2].emittance, 0.0);
}

TEST(SceneMaterials, BadReflectanceOrEmittanceNamesThePlace) {
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "reflectance": 1}])")); },
                               {"inline.json", "materials[0].reflectance", "must be in [0, 1)"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "reflectance": -0.1}])")); },
                               {"inline.json", "materials[0].reflectance", "must be in [0, 1)"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "reflectance": [0.2, 1.5, 0]}])")); },
                               {"inline.json", "materials[0].reflectance[1]", "must be in [0, 1)"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "reflectance": [0.2, 0.5]}])")); },
                               {"inline.json", "materials[0].reflectance", "3 numbers"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "reflectance": "grey"}])")); },
                               {"inline.json", "materials[0].reflectance", "expected a number"}));
  EXPECT_TRUE(ThrowsInputError([] { parse(scene_with_materials(R"([{"name": "a", "emittance": -3}])")); },
                               {"inline.json", "materials[0].emittance", "emittance must be >= 0"}));
}

// ================================================================================================
// Issue 11: orientation warnings, the coordinate range, hostile files, escaped control bytes,
// and the library's own checks on scenes that were never validated
// ================================================================================================

namespace issue11 {

using shadow::add_mesh;
using shadow::box_faces;
using shadow::room_faces;

std::vector<Polygon> reversed(std::vector<Polygon> faces) {
  for (Polygon& p : faces) std::reverse(p.begin(), p.end());
  return faces;
}

std::size_t count_warnings(const Scene& scene, const std::string& part) {
  std::size_t n = 0;
  for (const shadow::Warning& w : scene.warnings) n += w.to_string().find(part) != std::string::npos ? 1 : 0;
  return n;
}

Scene with_sun() {
  Scene scene;
  scene.lights.push_back(shadow::directional_light("sun", {0.3, 0.2, 1}));
  return scene;
}

TEST(Orientation, ClosedMeshWoundInwardWarnsOnce) {
  Scene scene = with_sun();
  add_mesh(scene, "outward", box_faces({0, 0, 0}, {1, 1, 1}));
  add_mesh(scene, "inward", reversed(box_faces({2, 0, 0}, {3, 1, 1})));
  shadow::validate_scene(scene);
  shadow::validate_scene(scene);  // not twice
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0].where.place, "meshes[1]");
  EXPECT_NE(scene.warnings[0].message.find("\"inward\" is closed, and its faces point inward"), std::string::npos);
  EXPECT_NE(scene.warnings[0].message.find("room seen from within"), std::string::npos);
}

TEST(Orientation, RoomsSeenFromInsideGetTheSameWarningAndNothingElse) {
  Scene scene = with_sun();
  add_mesh(scene, "room", room_faces({0, 0, 0}, {4, 3, 2.5}));
  shadow::validate_scene(scene);
  EXPECT_EQ(count_warnings(scene, "point inward"), 1u);
  EXPECT_EQ(scene.warnings.size(), 1u);
}

TEST(Orientation, InconsistentClosedMeshWarns) {
  Scene scene = with_sun();
  std::vector<Polygon> faces = box_faces({0, 0, 0}, {1, 1, 1});
  std::reverse(faces[2].begin(), faces[2].end());
  add_mesh(scene, "mixed", faces);
  shadow::validate_scene(scene);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NE(scene.warnings[0].message.find("inconsistent face orientation"), std::string::npos);
}

TEST(Orientation, OpenMeshesNeverWarn) {
  Scene scene = with_sun();
  std::vector<Polygon> open = reversed(box_faces({0, 0, 0}, {1, 1, 1}));
  open.pop_back();  // no lid: open, whatever the winding
  add_mesh(scene, "open", open);
  std::vector<Polygon> mixed_open = box_faces({2, 0, 0}, {3, 1, 1});
  std::reverse(mixed_open[0].begin(), mixed_open[0].end());
  mixed_open.pop_back();
  add_mesh(scene, "mixed_open", mixed_open);
  add_mesh(scene, "ground", {shadow::rectangle_z(-5, -5, 5, 5, 0, false)});
  shadow::validate_scene(scene);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings[0].to_string();
}

TEST(Orientation, OneInwardBoxAmongManyOutwardInOneMeshIsFound) {
  // Parts are checked one by one: the outward boxes must not outvote the inward one.
  Scene scene = with_sun();
  std::vector<Polygon> city;
  for (int b = 0; b < 20; ++b) {
    std::vector<Polygon> box = box_faces({3.0 * b, 0, 0}, {3.0 * b + 1, 1, 2});
    if (b == 7) box = reversed(box);
    if (b == 12) std::reverse(box[4].begin(), box[4].end());  // one wall wound the wrong way
    city.insert(city.end(), box.begin(), box.end());
  }
  city.push_back(shadow::rectangle_z(-5, -5, 70, 5, 0));  // an open part: never warns
  add_mesh(scene, "city", city);
  shadow::validate_scene(scene);
  ASSERT_EQ(scene.warnings.size(), 2u);
  EXPECT_NE(scene.warnings[0].message.find("has 1 closed part (of 21; the first has faces 72"), std::string::npos)
      << scene.warnings[0].to_string();
  EXPECT_NE(scene.warnings[0].message.find("inconsistent face orientation"), std::string::npos);
  EXPECT_NE(scene.warnings[1].message.find("has 1 closed part (of 21; the first has faces 42"), std::string::npos)
      << scene.warnings[1].to_string();
  EXPECT_NE(scene.warnings[1].message.find("whose faces point inward"), std::string::npos);
}

TEST(Orientation, TheDocumentedRoomGeneratorWarnsOnlyAboutItsRoom) {
  Scene scene = shadow::make_furnished_room(3, 7);
  shadow::validate_scene(scene);
  EXPECT_EQ(count_warnings(scene, "point inward"), 1u);
  for (const shadow::Warning& w : scene.warnings)
    EXPECT_NE(w.message.find("point inward"), std::string::npos) << w.to_string();
}

TEST(CoordinateRange, AcceptsTwoToThe500AndRejectsBeyond) {
  const double top = shadow::max_coordinate;
  EXPECT_EQ(top, std::ldexp(1.0, 500));
  Scene ok = scene_in_code({{{-top, 0, 0}, {top, 0, 0}, {0, top, 0}}});
  EXPECT_NO_THROW(shadow::validate_scene(ok));
  Scene huge = scene_in_code({{{0, 0, 0}, {1e308, 0, 0}, {0, 1, 0}}});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(huge); }, {"face 0", "vertex 1", "2^500"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse(R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0],[0,-1e200,0]]]}],
                     "lights": [{"name": "s", "type": "directional", "to_light": [0,0,1]}]})"); },
      {"inline.json", "meshes[0].polygons[0]", "vertex 2", "2^500"}));
  // The OBJ reader reads any finite double ...
  EXPECT_NO_THROW((void)shadow::parse_obj("v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n", "big.obj"));
  Scene obj = scene_in_code({{{0, 0, 0}, {1e300, 0, 0}, {0, 1, 0}}});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(obj); }, {"vertex 1", "2^500"}));  // ... validation refuses
}

TEST(CoordinateRange, LightsAndPlanesAreCheckedTheSameWay) {
  Scene far_lamp = scene_in_code({kSquare});
  far_lamp.lights.push_back(shadow::point_light("lamp", {0, 0, -1e300}));
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(far_lamp); }, {"lights[1].position", "2^500"}));
  // Directions and normals are scale-free (normalised safely, exact elsewhere): any finite
  // non-zero vector, however long, is accepted and gives the shadow of its unit vector.
  Scene long_sun = scene_in_code({kSquare});
  long_sun.lights[0].to_light = {1.7e308, 0, 1e308};
  long_sun.planes.push_back({"ground", {0, 0, -1}, {0, 1.7e308, 1.7e308}});
  EXPECT_NO_THROW(shadow::validate_scene(long_sun));
  Scene unit_sun = long_sun;
  unit_sun.lights[0].to_light = {1.7, 0, 1};
  unit_sun.planes[0].normal = {0, 1, 1};
  EXPECT_EQ(shadow::compute_plane_shadows(long_sun)[0].area, shadow::compute_plane_shadows(unit_sun)[0].area);
  EXPECT_GT(shadow::compute_plane_shadows(unit_sun)[0].area, 0.0);
  Scene far_plane = scene_in_code({kSquare});
  far_plane.planes.push_back({"ground", {0, 0, 1e160}, {0, 0, 1}});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(far_plane); }, {"planes[0].point", "2^500"}));
  Scene wide = scene_in_code({kSquare});
  wide.planes.push_back({"ground", {0, 0, 0}, {0, 0, 1}, 1e300});
  EXPECT_TRUE(ThrowsInputError([&] { shadow::validate_scene(wide); }, {"planes[0].window", "2^500"}));
}

TEST(CoordinateRange, SceneAtTheTopOfTheRangeComputesFiniteAreas) {
  // Boxes and a point light near 2^500: before the range was stated, 1e308 crashed CGAL or the
  // double culling. At the top of the accepted range, exact and fast agree and stay finite.
  const double s = shadow::max_coordinate / 8;
  Scene scene = with_sun();
  scene.lights.push_back(shadow::point_light("lamp", {3 * s, 3 * s, 5 * s}));
  add_mesh(scene, "box", box_faces({0, 0, 0}, {s, s, 2 * s}));
  add_mesh(scene, "ground", {shadow::rectangle_z(-5 * s, -5 * s, 5 * s, 5 * s, 0)});
  scene.planes.push_back({"below", {0, 0, -s}, {0, 0, 1}});
  shadow::validate_scene(scene);
  shadow::ShadowOptions options;
  options.threads = 2;
  const shadow::ShadowResult exact = shadow::compute_shadows(scene, options);
  options.arithmetic = shadow::Arithmetic::Fast;
  const shadow::ShadowResult fast = shadow::compute_shadows(scene, options);
  ASSERT_EQ(exact.lighting.size(), fast.lighting.size());
  for (std::size_t i = 0; i < exact.lighting.size(); ++i) {
    EXPECT_TRUE(std::isfinite(exact.lighting[i].lit_area));
    EXPECT_LE(std::abs(exact.lighting[i].lit_area - fast.lighting[i].lit_area),
              fast.lighting[i].lit_area_error_bound + 1e-12 * exact.lighting[i].area);
  }
  for (const shadow::PlaneShadow& p : exact.plane_shadows) EXPECT_TRUE(std::isfinite(p.area));
}

TEST(LibraryChecks, EngineRejectsANaNVertexOfAnUnvalidatedScene) {
  Scene scene = scene_in_code({kSquare, {{0, 0, 1}, {1, 0, 1}, {0, std::nan(""), 1}}});
  scene.meshes[0].face_count = 2;
  scene.faces[1].source = {"model.obj", "line 12"};
  // No validate_scene: before the fix GMP died of SIGFPE.
  EXPECT_TRUE(ThrowsInputError([&] { shadow::ShadowEngine engine(scene); }, {"model.obj: line 12", "vertex 2", "not finite"}));
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_shadows(scene); }, {"model.obj: line 12", "not finite"}));
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_plane_shadows(scene); }, {"model.obj: line 12"}));
  Scene huge = scene_in_code({{{0, 0, 0}, {1e308, 0, 0}, {0, 1e308, 0}}});
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_shadows(huge); }, {"face 0", "2^500"}));
  // A face of a mesh that does not exist: Scene::is_receiver() would read past the meshes.
  Scene orphan = scene_in_code({kSquare});
  orphan.faces[0].mesh = 3;
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_shadows(orphan); }, {"face 0", "mesh 3", "1 mesh"}));
  // A zero-length edge, which validate_scene() would have removed.
  Scene repeated = scene_in_code({{{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_shadows(repeated); }, {"face 0", "vertices 1 and 2 coincide"}));
}

TEST(LibraryChecks, LightsAreResolvedInOnePlaceForFacesAndPlanes) {
  Scene scene = scene_in_code({kSquare});
  scene.planes.push_back({"ground", {0, 0, -1}, {0, 0, 1}});
  shadow::validate_scene(scene);
  shadow::ShadowOptions options;
  options.lights = {0, 5};
  // Documented as InputError (it was std::out_of_range).
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_shadows(scene, options); },
                               {"ShadowOptions::lights[1]", "no light 5", "1 light"}));
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_plane_shadows(scene, options); }, {"no light 5"}));
  // A zero direction: the plane shadows used to return an empty shadow silently.
  scene.lights[0].to_light = {0, 0, 0};
  options.lights.clear();
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_plane_shadows(scene, options); },
                               {"lights[0].to_light", "zero length"}));
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::ShadowEngine(scene).compute(options); },
                               {"lights[0].to_light", "zero length"}));
  // A light that is not one of the scene's (many sun positions over one engine) is checked too.
  const shadow::Light bad = shadow::directional_light("sun", {0, 0, 0});
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::ShadowEngine(scene).compute(bad, 7, options); },
                               {"lights[7].to_light", "zero length"}));
}

TEST(LibraryChecks, ThreadsAreBounded) {
  Scene scene = scene_in_code({kSquare});
  shadow::validate_scene(scene);
  shadow::ShadowOptions options;
  options.threads = 99999999;
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_shadows(scene, options); },
                               {"ShadowOptions::threads", "1024", "99999999"}));
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::compute_plane_shadows(scene, options); }, {"1024"}));
  EXPECT_TRUE(ThrowsInputError([&] { shadow::ShadowEngine engine(scene, 5000); }, {"1024"}));
  options.threads = 1024;
  EXPECT_NO_THROW((void)shadow::compute_shadows(scene, options));
}

class HostileFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("libshadow-hostile-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write_scene(const std::string& mesh_file) {
    const fs::path scene = dir_ / "scene.json";
    std::ofstream(scene) << R"({"meshes": [{"name": "m", "file": ")" << mesh_file
                         << R"("}], "lights": [{"name": "s", "type": "directional", "to_light": [0, 0, 1]}]})";
    return scene;
  }
  fs::path dir_;
};

TEST_F(HostileFiles, AFifoMeshFileIsRefusedWithoutBlocking) {
  ASSERT_EQ(::mkfifo((dir_ / "pipe.obj").c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(ThrowsInputError([&] { shadow::load_scene(write_scene("pipe.obj")); },
                               {"meshes[0].file", "pipe.obj", "not a regular file"}));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

TEST_F(HostileFiles, DevicesAreRefusedAsScenesAndMeshes) {
  fs::create_symlink("/dev/zero", dir_ / "zero.obj");
  EXPECT_TRUE(ThrowsInputError([&] { shadow::load_scene(write_scene("zero.obj")); },
                               {"meshes[0].file", "zero.obj", "not a regular file"}));
  EXPECT_TRUE(ThrowsInputError([] { shadow::load_scene("/dev/urandom"); }, {"/dev/urandom", "not a regular file"}));
  EXPECT_TRUE(ThrowsInputError([] { (void)shadow::read_obj("/dev/zero", "zero.obj"); }, {"zero.obj", "not a regular file"}));
}

TEST_F(HostileFiles, FilesBeyondTheReadLimitAreRefused) {
  EXPECT_EQ(LoadOptions{}.max_file_bytes, std::uintmax_t{2} << 30);
  // A 1,034-byte mesh under a scene of about 140 bytes.
  std::ofstream(dir_ / "mesh.obj") << "# " << std::string(999, '-') << "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  ASSERT_EQ(fs::file_size(dir_ / "mesh.obj"), 1034u);
  LoadOptions small;
  small.max_file_bytes = 1033;
  EXPECT_TRUE(ThrowsInputError([&] { shadow::load_scene(write_scene("mesh.obj"), small); },
                               {"meshes[0].file", "mesh.obj", "larger than the limit of 1033 bytes"}));
  small.max_file_bytes = 10;
  EXPECT_TRUE(ThrowsInputError([&] { shadow::load_scene(write_scene("mesh.obj"), small); },
                               {"scene.json", "larger than the limit of 10 bytes"}));
  small.max_file_bytes = 1034;
  EXPECT_EQ(shadow::load_scene(write_scene("mesh.obj"), small).faces.size(), 1u);
}

TEST(ErrorText, ControlBytesAreEscapedAndLongTokensTruncated) {
  const std::string obj = std::string("v 0 0 0\nv 1 0 0\nv 1 1") + '\0' + "junk 0\nf 1 2 3\n";
  try {
    (void)shadow::parse_obj(obj, "nul.obj");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string what = e.what();  // as a C string: the whole message survives
    EXPECT_EQ(std::string(e.what()).size(), std::strlen(e.what()));
    EXPECT_NE(what.find("nul.obj: line 3: y coordinate \"1\\x00junk\" is not a number"), std::string::npos) << what;
  }
  const std::string long_token(5000, 'x');
  EXPECT_TRUE(ThrowsInputError([&] { (void)shadow::parse_obj("v 0 0 " + long_token + "\n", "long.obj"); },
                               {"long.obj: line 1", "...\" is not a number"}));
  try {
    (void)shadow::parse_obj("v 0 0 " + long_token + "\n", "long.obj");
  } catch (const InputError& e) {
    EXPECT_LT(std::strlen(e.what()), 200u);
  }
  const shadow::Warning w{{"a\tb.obj", "line\n2"}, std::string("bell\a")};
  EXPECT_EQ(w.to_string(), "a\\x09b.obj: line\\x0a2: bell\\x07");
}

TEST(ErrorText, BytesThatAreNotUtf8AreEscapedAndUtf8IsKept) {
  // A terminal (or Python's str) must not get stray bytes: they are shown as \xHH, like control
  // bytes; well-formed UTF-8 (a name in Greek, an emoji) is kept as it is.
  EXPECT_EQ(shadow::escape_control("caf\xc3\xa9 \xce\xb1 \xf0\x9f\x8c\x9e"), "caf\xc3\xa9 \xce\xb1 \xf0\x9f\x8c\x9e");
  EXPECT_EQ(shadow::escape_control("a\xff" "b"), "a\\xff" "b");           // never in UTF-8
  EXPECT_EQ(shadow::escape_control("\xc3" "("), "\\xc3(");                // a cut sequence
  EXPECT_EQ(shadow::escape_control("\xc0\xaf"), "\\xc0\\xaf");            // an overlong '/'
  EXPECT_EQ(shadow::escape_control("\xed\xa0\x80"), "\\xed\\xa0\\x80");   // a surrogate
  EXPECT_EQ(shadow::escape_control("\xe2\x82"), "\\xe2\\x82");            // cut at the end
  EXPECT_EQ(shadow::escape_control("\x80x"), "\\x80x");                   // a lone continuation byte
  // In a scene file: the JSON reader names the place, and the line holds no raw byte.
  const std::string scene = minimal_scene().substr(0, minimal_scene().size() - 1) + ", \"materials\": {\"m\xe9\": {}}}";
  const std::string what = [&] {
    try {
      parse(scene);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_NE(what.find("inline.json: line 1, column "), std::string::npos) << what;
  EXPECT_NE(what.find("malformed JSON"), std::string::npos) << what;
  EXPECT_NE(what.find("\\xe9"), std::string::npos) << what;
  EXPECT_TRUE(std::all_of(what.begin(), what.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; })) << what;
}

}  // namespace issue11
