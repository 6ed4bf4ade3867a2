// SPDX-License-Identifier: GPL-3.0-or-later
// Models in, named results out (issue 15): CityJSON read exactly and named, the same buildings as
// OBJ and CityJSON giving the same areas bit for bit, mesh placement (transform, up_axis), names
// of OBJ groups and inline polygons, polygons with holes, orienting closed meshes outward, and
// the face identity and orientation written to report.json and faces.vtp.
#include <shadow/output.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun_hours.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <array>
#include <iomanip>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// A fresh directory for one test's files, removed at the end.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(fs::temp_directory_path() / ("libshadow_models_" + name + "_" + std::to_string(getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return path_ / name;
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// The error message of `f`, or "" when it does not throw an InputError.
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const shadow::InputError& e) {
    return e.what();
  }
  return "";
}

// ---- two boxes at Dutch projected coordinates, in millimetres ----------------------------------

struct Box {
  std::string id;
  long long x0, y0, z0, x1, y1, z1;  // millimetres relative to the translate
};

const long long kTx = 90000000, kTy = 435000000, kTz = 1500;  // translate in mm: (90000, 435000, 1.5) m
const std::vector<Box> kBoxes = {{"A", 123, 456, 0, 10123, 6456, 4000}, {"B", 14123, 456, 0, 18123, 6456, 9000}};

/// Corners 0..3 at the bottom (counter-clockwise from above), 4..7 on top; faces outward.
const int kFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
const char* kSemantic[6] = {"GroundSurface", "RoofSurface", "WallSurface", "WallSurface", "WallSurface", "WallSurface"};

std::vector<std::array<long long, 3>> corners(const Box& b) {
  return {{b.x0, b.y0, b.z0}, {b.x1, b.y0, b.z0}, {b.x1, b.y1, b.z0}, {b.x0, b.y1, b.z0},
          {b.x0, b.y0, b.z1}, {b.x1, b.y0, b.z1}, {b.x1, b.y1, b.z1}, {b.x0, b.y1, b.z1}};
}

/// "90000.123": a millimetre count as decimal metres, the text a modeller's OBJ export writes.
std::string metres(long long mm) {
  std::ostringstream s;
  s << (mm < 0 ? "-" : "") << std::llabs(mm) / 1000 << "." << std::setw(3) << std::setfill('0') << std::llabs(mm) % 1000;
  return s.str();
}

std::string boxes_obj() {
  std::string obj;
  int base = 1;
  for (const Box& b : kBoxes) {
    obj += "o " + b.id + "\n";
    for (const auto& c : corners(b))
      obj += "v " + metres(c[0] + kTx) + " " + metres(c[1] + kTy) + " " + metres(c[2] + kTz) + "\n";
    for (const auto& f : kFaces)
      obj += "f " + std::to_string(base + f[0]) + " " + std::to_string(base + f[1]) + " " + std::to_string(base + f[2]) +
             " " + std::to_string(base + f[3]) + "\n";
    base += 8;
  }
  return obj;
}

Json boxes_cityjson(const std::string& version = "2.0") {
  Json vertices = Json::array(), objects = Json::object();
  int base = 0;
  for (const Box& b : kBoxes) {
    for (const auto& c : corners(b)) vertices.push_back({c[0], c[1], c[2]});
    Json shell = Json::array(), values = Json::array();
    for (int f = 0; f < 6; ++f) {
      shell.push_back(Json::array({Json::array({base + kFaces[f][0], base + kFaces[f][1], base + kFaces[f][2], base + kFaces[f][3]})}));
      values.push_back(f == 0 ? 0 : f == 1 ? 1 : 2);
    }
    objects[b.id] = {{"type", "Building"},
                     {"geometry", Json::array({{{"type", "Solid"},
                                                {"lod", "2"},
                                                {"boundaries", Json::array({shell})},
                                                {"semantics",
                                                 {{"surfaces", Json::array({{{"type", "GroundSurface"}},
                                                                            {{"type", "RoofSurface"}},
                                                                            {{"type", "WallSurface"}}})},
                                                  {"values", Json::array({values})}}}}})}};
    base += 8;
  }
  return {{"type", "CityJSON"},
          {"version", version},
          {"transform", {{"scale", {0.001, 0.001, 0.001}}, {"translate", {90000.0, 435000.0, 1.5}}}},
          {"CityObjects", objects},
          {"vertices", vertices}};
}

std::string scene_with(const std::string& file, const std::string& extra = "") {
  return R"({"meshes": [{"name": "city", "file": ")" + file + "\"" + extra +
         R"(}], "lights": [{"name": "sun", "type": "directional", "to_light": [0.8, 0.1, 0.5]}]})";
}

shadow::ShadowResult compute(const shadow::Scene& scene) { return shadow::compute_shadows(scene); }

TEST(CityJson, TheSameBuildingsAsObjGiveTheSameAreasBitForBit) {
  TempDir dir("roundtrip");
  dir.write("boxes.obj", boxes_obj());
  dir.write("boxes.city.json", boxes_cityjson().dump());
  const shadow::Scene obj = shadow::load_scene(dir.write("obj.json", scene_with("boxes.obj")));
  const shadow::Scene city = shadow::load_scene(dir.write("city.json", scene_with("boxes.city.json")));
  ASSERT_EQ(obj.faces.size(), 12u);
  ASSERT_EQ(city.faces.size(), 12u);
  // Exact input: the same doubles (one integer over 1000 is the double nearest the decimal text).
  for (std::size_t f = 0; f < 12; ++f) EXPECT_EQ(obj.faces[f].vertices, city.faces[f].vertices) << "face " << f;
  const shadow::ShadowResult a = compute(obj), b = compute(city);
  ASSERT_EQ(a.lighting.size(), b.lighting.size());
  bool partly_lit = false;
  for (std::size_t i = 0; i < a.lighting.size(); ++i) {
    EXPECT_EQ(a.lighting[i].area, b.lighting[i].area);
    EXPECT_EQ(a.lighting[i].lit_area, b.lighting[i].lit_area);
    partly_lit |= a.lighting[i].lit_fraction > 0.01 && a.lighting[i].lit_fraction < 0.99;
  }
  EXPECT_TRUE(partly_lit) << "B should shade part of A: the comparison would say little otherwise";
  // The faces: an analytic area (A's east wall is 6 m x 4 m).
  EXPECT_NEAR(a.lighting[3].area, 24.0, 1e-9);
}

TEST(CityJson, NamesKindsMeshesAndOrigin) {
  TempDir dir("names");
  dir.write("boxes.city.json", boxes_cityjson("1.1").dump());
  const shadow::Scene scene = shadow::load_scene(dir.write("city.json", scene_with("boxes.city.json")));
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[0].name, "city/A");
  EXPECT_EQ(scene.meshes[1].name, "city/B");
  EXPECT_EQ(scene.faces[1].name, "A/1");
  EXPECT_EQ(scene.faces[7].name, "B/1");
  for (std::size_t f = 0; f < 12; ++f) EXPECT_EQ(scene.faces[f].kind, kSemantic[f % 6]) << f;
  EXPECT_NE(scene.faces[2].source.place.find("CityObjects[\"A\"].geometry[0].boundaries[0][2]"), std::string::npos)
      << scene.faces[2].source.to_string();
  ASSERT_TRUE(scene.origin.has_value());
  EXPECT_EQ(*scene.origin, glm::dvec3(90000, 435000, 1));
  // Placed near (0, 0, 0) by the scene, the model needs no origin any more.
  const shadow::Scene placed = shadow::load_scene(
      dir.write("placed.json", scene_with("boxes.city.json", R"(, "transform": {"translate": [-90000, -435000, 0]})")));
  EXPECT_FALSE(placed.origin.has_value());
  // The translation is exact here (Sterbenz: the difference of two close doubles).
  EXPECT_EQ(placed.faces[1].vertices[0], scene.faces[1].vertices[0] - glm::dvec3(90000, 435000, 0));
  EXPECT_EQ(placed.faces[1].vertices[0].z, 5.5);
  // One building of a model as the only receiver; a name the model lacks is an error at its path.
  const shadow::Scene only_b = shadow::load_scene(dir.write(
      "only_b.json", R"({"meshes": [{"name": "city", "file": "boxes.city.json"}], "receivers": ["city/B"],
                        "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})"));
  EXPECT_FALSE(only_b.meshes[0].receiver);
  EXPECT_TRUE(only_b.meshes[1].receiver);
  EXPECT_NE(error_of([&] {
              shadow::load_scene(dir.write(
                  "only_c.json", R"({"meshes": [{"name": "city", "file": "boxes.city.json"}], "receivers": ["city/C"],
                                    "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})"));
            }).find("only_c.json: receivers[0]: no mesh is named \"city/C\" (the model \"city\" has no mesh \"C\")"),
            std::string::npos);
  // The model read whole: meshes by object id, no lights.
  const shadow::Scene whole = shadow::load_scene(dir.path() / "boxes.city.json");
  ASSERT_EQ(whole.meshes.size(), 2u);
  EXPECT_EQ(whole.meshes[0].name, "A");
  EXPECT_TRUE(whole.lights.empty());
  EXPECT_EQ(whole.faces.size(), 12u);
}

TEST(CityJson, RecognisedByContentUnderAnyName) {
  TempDir dir("content");
  dir.write("model.json", boxes_cityjson().dump());
  dir.write("model.dat", boxes_cityjson().dump());
  EXPECT_EQ(shadow::load_scene(dir.path() / "model.json").meshes.size(), 2u);
  const shadow::Scene scene = shadow::load_scene(dir.write("s.json", scene_with("model.dat")));
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[1].name, "city/B");
  // A scene file that merely mentions CityJSON is still a scene file.
  const shadow::Scene plain = shadow::load_scene(dir.write(
      "plain.json", R"({"_note": "\"CityJSON\"", "meshes": [{"name": "CityJSON", "polygons": [[[0,0,0],[1,0,0],[0,1,0]]]}],
                        "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})"));
  EXPECT_EQ(plain.lights.size(), 1u);
}

TEST(CityJson, RecognisedByParsingWhenTypeComesAfter64KiB) {
  // cjio writes "type" where its dictionary puts it: Delft's sample has it after 1.4 MB. No
  // prefix may decide (read as OBJ it gave an empty result, as a scene `unknown key`).
  TempDir dir("late-type");
  Json doc = boxes_cityjson();
  doc["CityObjects"]["A"]["attributes"] = {{"description", std::string(100000, 'x')}};
  doc.erase("type");
  std::string text = doc.dump();
  text.pop_back();
  text += R"(, "type": "CityJSON"})";
  ASSERT_GT(text.find(R"("type": "CityJSON")"), std::size_t{65536});
  dir.write("delft.json", text);
  const shadow::Scene whole = shadow::load_scene(dir.path() / "delft.json");
  ASSERT_EQ(whole.faces.size(), 12u);
  EXPECT_EQ(whole.meshes[0].model, "cityjson");
  const shadow::Scene scene = shadow::load_scene(dir.write("s.json", scene_with("delft.json")));
  ASSERT_EQ(scene.faces.size(), 12u);
  EXPECT_EQ(scene.meshes[1].name, "city/B");
  EXPECT_EQ(scene.meshes[1].model, "cityjson");
  // The same areas as the file named .city.json.
  dir.write("boxes.city.json", boxes_cityjson().dump());
  const shadow::Scene named = shadow::load_scene(dir.write("n.json", scene_with("boxes.city.json")));
  const shadow::ShadowResult a = compute(scene), b = compute(named);
  ASSERT_EQ(a.lighting.size(), b.lighting.size());
  for (std::size_t i = 0; i < a.lighting.size(); ++i) EXPECT_EQ(a.lighting[i].lit_area, b.lighting[i].lit_area);
}

TEST(CityJson, HighestLodByDefaultOrTheChosenOne) {
  TempDir dir("lod");
  Json doc = boxes_cityjson();
  // A's LoD 1: only its roof, listed first; LoD 2 (the box) must win by default.
  Json lod1 = {{"type", "MultiSurface"}, {"lod", "1.2"}, {"boundaries", Json::array({Json::array({Json::array({4, 5, 6, 7})})})}};
  doc["CityObjects"]["A"]["geometry"].insert(doc["CityObjects"]["A"]["geometry"].begin(), lod1);
  const fs::path file = dir.write("lod.city.json", doc.dump());
  EXPECT_EQ(shadow::load_scene(file).faces.size(), 12u);
  shadow::LoadOptions options;
  options.cityjson_lod = "1.2";
  const shadow::Scene scene = shadow::load_scene(file, options);
  EXPECT_EQ(scene.faces.size(), 1u);  // B has no LoD 1.2: left out with a warning
  EXPECT_EQ(scene.faces[0].name, "A/0");
  ASSERT_FALSE(scene.warnings.empty());
  EXPECT_NE(scene.warnings[0].message.find("1 city objects have no geometry of LoD 1.2"), std::string::npos);
  options.cityjson_lod = "two";
  EXPECT_NE(error_of([&] { shadow::load_scene(file, options); }).find("lod.city.json: the level of detail to read, \"two\", is not one"),
            std::string::npos);
  // A level no object has: an error naming the levels there are, not an empty scene and exit 0.
  options.cityjson_lod = "5";
  EXPECT_NE(error_of([&] { shadow::load_scene(file, options); })
                .find("lod.city.json: CityObjects: no city object has geometry of LoD 5 (the file's: 1.2, 2)"),
            std::string::npos)
      << error_of([&] { shadow::load_scene(file, options); });
  // In a scene of two models, a level one of them lacks (a terrain of LoD 1 beside buildings of
  // LoD 1.2) leaves that one out with its warning; a level neither has is the error.
  Json terrain = boxes_cityjson();
  for (auto& [id, object] : terrain["CityObjects"].items()) object["geometry"][0]["lod"] = "1";
  dir.write("terrain.city.json", terrain.dump());
  const fs::path two = dir.write("two.json", R"({"meshes": [{"name": "b", "file": "lod.city.json"},
    {"name": "t", "file": "terrain.city.json"}], "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  options.cityjson_lod = "1.2";
  EXPECT_EQ(shadow::load_scene(two, options).faces.size(), 1u);
  options.cityjson_lod = "5";
  EXPECT_NE(error_of([&] { shadow::load_scene(two, options); })
                .find("two.json: meshes[0].file: no city object of any model has geometry of LoD 5 (\"lod.city.json\" "
                      "has 1.2, 2)"),
            std::string::npos)
      << error_of([&] { shadow::load_scene(two, options); });
}

// GeometryInstance (trees, street furniture): the template's surfaces placed by the matrix at
// the reference point, at the template's LoD. They were left out, and an object with another
// geometry beside its instance was read at that one's lower LoD, while the warning said the
// object was left out.
TEST(CityJson, GeometryInstancesArePlacedTemplates) {
  TempDir dir("instances");
  const Json square = {{"type", "MultiSurface"}, {"lod", "2"}, {"boundaries", Json::array({Json::array({Json::array({0, 1, 2, 3})})})}};
  Json doc = {{"type", "CityJSON"},
              {"version", "2.0"},
              {"transform", {{"scale", {1, 1, 1}}, {"translate", {0, 0, 0}}}},
              {"vertices", {{100, 200, 0}, {0, 0, 0}, {5, 0, 0}, {5, 5, 0}, {0, 5, 0}}},
              {"geometry-templates", {{"templates", Json::array({square})},
                                      {"vertices-templates", {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}}}},
              {"CityObjects",
               {{"T", {{"type", "SolitaryVegetationObject"},
                       {"geometry", Json::array({{{"type", "GeometryInstance"}, {"template", 0}, {"boundaries", {0}},
                                                  {"transformationMatrix", {2, 0, 0, 3, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1}}},
                                                 {{"type", "MultiSurface"}, {"lod", "1"},
                                                  {"boundaries", Json::array({Json::array({Json::array({1, 2, 3, 4})})})}}})}}},
                {"M", {{"type", "CityFurniture"},
                       {"geometry", Json::array({{{"type", "GeometryInstance"}, {"template", 0}, {"boundaries", {0}},
                                                  {"transformationMatrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}}})}}}}}};
  const fs::path file = dir.write("instances.city.json", doc.dump());
  const shadow::Scene scene = shadow::load_scene(file);
  ASSERT_EQ(scene.faces.size(), 2u);
  EXPECT_TRUE(scene.warnings.empty());
  std::map<std::string, const shadow::Face*> by_name;
  for (const shadow::Face& f : scene.faces) by_name[f.name] = &f;
  ASSERT_TRUE(by_name.count("T/0") == 1 && by_name.count("M/0") == 1);
  // T: the LoD 2 template, doubled and moved 3 in x, at (100, 200, 0): a 2 x 2 square at z = 2.
  const shadow::Face& tree = *by_name.at("T/0");
  EXPECT_EQ(tree.vertices, (std::vector<glm::dvec3>{{103, 200, 2}, {105, 200, 2}, {105, 202, 2}, {103, 202, 2}}));
  EXPECT_EQ(tree.source.place, "CityObjects[\"T\"].geometry[0].template.boundaries[0]");
  // M: mirrored in x, so the ring is reversed and the square still faces up.
  const std::vector<glm::dvec3>& v = by_name.at("M/0")->vertices;
  EXPECT_EQ(v, (std::vector<glm::dvec3>{{100, 201, 1}, {99, 201, 1}, {99, 200, 1}, {100, 200, 1}}));
  double twice_area_up = 0.0;  // counter-clockwise seen from above: facing up
  for (std::size_t i = 0; i < v.size(); ++i)
    twice_area_up += v[i].x * v[(i + 1) % v.size()].y - v[(i + 1) % v.size()].x * v[i].y;
  EXPECT_GT(twice_area_up, 0.0);
  // --lod 1 takes T's own LoD 1 surface; M has none.
  shadow::LoadOptions options;
  options.cityjson_lod = "1";
  const shadow::Scene lod1 = shadow::load_scene(file, options);
  ASSERT_EQ(lod1.faces.size(), 1u);
  EXPECT_EQ(lod1.faces[0].vertices[1], glm::dvec3(5, 0, 0));
  // A template index out of range is an error naming the instance.
  doc["CityObjects"]["M"]["geometry"][0]["template"] = 4;
  dir.write("bad.city.json", doc.dump());
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.path() / "bad.city.json"); })
                .find("CityObjects[\"M\"].geometry[0].template: template 4 out of range (the file has 1)"),
            std::string::npos)
      << error_of([&] { shadow::load_scene(dir.path() / "bad.city.json"); });
  // Only the vertices the template's surfaces use are placed: one that no surface uses and that
  // a matrix would place out of range is no error (it was: every template vertex was placed for
  // every instance); a used one placed out of range is, naming the instance's matrix.
  doc["CityObjects"]["M"]["geometry"][0]["template"] = 0;
  doc["geometry-templates"]["vertices-templates"].push_back({1e300, 0, 0});
  doc["CityObjects"]["M"]["geometry"][0]["transformationMatrix"] = {1e10, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_EQ(shadow::load_scene(dir.write("unused.city.json", doc.dump())).faces.size(), 2u);
  doc["CityObjects"]["M"]["geometry"][0]["transformationMatrix"] = {1e300, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.write("far.city.json", doc.dump())); })
                .find("CityObjects[\"M\"].geometry[0].transformationMatrix: a placed template vertex is out of range"),
            std::string::npos)
      << error_of([&] { shadow::load_scene(dir.path() / "far.city.json"); });
}

// A translation off the decimal grid by less than 1e-6 of a grid unit was snapped onto it (4e-7
// at scale 1 lost); only the decimal's own rounding is.
TEST(CityJson, ATranslationOffTheGridIsKept) {
  TempDir dir("translate");
  const Json doc = {{"type", "CityJSON"},
                    {"version", "2.0"},
                    {"transform", {{"scale", {1, 1, 1}}, {"translate", {4e-7, 0.5, 0}}}},
                    {"vertices", {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}}},
                    {"CityObjects", {{"A", {{"type", "Building"},
                                            {"geometry", Json::array({{{"type", "MultiSurface"}, {"lod", "2"},
                                                                       {"boundaries", Json::array({Json::array({Json::array({0, 1, 2, 3})})})}}})}}}}}};
  const shadow::Scene scene = shadow::load_scene(dir.write("t.city.json", doc.dump()));
  ASSERT_EQ(scene.faces.size(), 1u);
  EXPECT_EQ(scene.faces[0].vertices[0], glm::dvec3(4e-7, 0.5, 0));
}

TEST(CityJson, InnerRingsAreCutOutExactly) {
  TempDir dir("holes");
  // A 10 m x 4 m wall (y = 0) with a 2 m x 1.5 m window, and the window itself as a surface.
  Json doc = {{"type", "CityJSON"},
              {"version", "2.0"},
              {"transform", {{"scale", {0.001, 0.001, 0.001}}, {"translate", {120000.0, 480000.0, 0.0}}}},
              {"vertices", {{0, 0, 0}, {10000, 0, 0}, {10000, 0, 4000}, {0, 0, 4000},
                            {3000, 0, 1000}, {3000, 0, 2500}, {5000, 0, 2500}, {5000, 0, 1000}}},
              {"CityObjects",
               {{"W", {{"type", "BuildingPart"},
                       {"geometry", {{{"type", "MultiSurface"},
                                      {"lod", 2},
                                      {"boundaries", {{{0, 1, 2, 3}, {4, 5, 6, 7}}, {{4, 7, 6, 5}}}},
                                      {"semantics", {{"surfaces", {{{"type", "WallSurface"}}, {{"type", "Window"}}}},
                                                     {"values", {0, 1}}}}}}}}}}}};
  const shadow::Scene scene = shadow::load_scene(dir.write("wall.city.json", doc.dump()));
  double wall = 0, window = 0;
  std::size_t wall_pieces = 0;
  for (const shadow::Face& f : scene.faces) {
    // Area of a face in the plane y = 0 (shoelace in x, z).
    double a = 0;
    for (std::size_t i = 0; i < f.vertices.size(); ++i) {
      const glm::dvec3 &p = f.vertices[i], &q = f.vertices[(i + 1) % f.vertices.size()];
      a += (p.x - 120000) * (q.z) - (q.x - 120000) * (p.z);
    }
    a = std::fabs(a) / 2;
    if (f.name == "W/0") {
      wall += a;
      ++wall_pieces;
      EXPECT_EQ(f.kind, "WallSurface");
    } else {
      window += a;
      EXPECT_EQ(f.kind, "Window");
    }
  }
  EXPECT_GE(wall_pieces, 2u);
  EXPECT_DOUBLE_EQ(wall, 40.0 - 3.0);
  EXPECT_DOUBLE_EQ(window, 3.0);
  // The engine agrees: the wall's pieces add up to its area with the window cut out.
  shadow::Scene lit = scene;
  lit.lights.push_back(shadow::Light{"sun", shadow::LightType::Directional, {0.2, -1, 0.3}});
  double engine_wall = 0;
  for (const shadow::FaceLighting& fl : compute(lit).lighting)
    if (lit.faces[fl.face_id].name == "W/0") engine_wall += fl.area;
  EXPECT_NEAR(engine_wall, 37.0, 1e-9);
}

TEST(CityJson, ErrorsNameTheJsonPath) {
  TempDir dir("errors");
  Json doc = boxes_cityjson();
  doc["CityObjects"]["B"]["geometry"][0]["boundaries"][0][2][0][1] = 999;
  dir.write("bad.city.json", doc.dump());
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.path() / "bad.city.json"); })
                .find("bad.city.json: CityObjects[\"B\"].geometry[0].boundaries[0][2][0][1]: vertex index 999 out of "
                      "range (the file has 16 vertices)"),
            std::string::npos);
  doc = boxes_cityjson();
  doc["version"] = "3.0";
  dir.write("v3.city.json", doc.dump());
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.path() / "v3.city.json"); }).find("v3.city.json: version: CityJSON version"),
            std::string::npos);
  doc = boxes_cityjson();
  doc["CityObjects"]["A"]["geometry"][0]["semantics"]["values"][0][3] = 7;
  dir.write("sem.city.json", doc.dump());
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.path() / "sem.city.json"); })
                .find("CityObjects[\"A\"].geometry[0].semantics.values[0][3]: semantic surface index 7 out of range"),
            std::string::npos);
  // A hole outside its surface: the inner ring's path.
  doc = boxes_cityjson();
  doc["vertices"].push_back({-5000, -5000, 0});
  doc["vertices"].push_back({-4000, -5000, 0});
  doc["vertices"].push_back({-4000, -4000, 0});
  doc["CityObjects"]["A"]["geometry"][0]["boundaries"][0][0].push_back({16, 18, 17});
  dir.write("hole.city.json", doc.dump());
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.path() / "hole.city.json"); })
                .find("CityObjects[\"A\"].geometry[0].boundaries[0][0][1]: inner ring 1 is outside the outer ring"),
            std::string::npos)
      << error_of([&] { shadow::load_scene(dir.path() / "hole.city.json"); });
  // A misspelt geometry type: the object was left out without a word (a building fewer).
  doc = boxes_cityjson();
  doc["CityObjects"]["B"]["geometry"][0]["type"] = "Multisurface";
  dir.write("typo.city.json", doc.dump());
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.path() / "typo.city.json"); })
                .find("typo.city.json: CityObjects[\"B\"].geometry[0].type: unknown geometry type \"Multisurface\""),
            std::string::npos);
  // Without its transform a 2.0 file's integer vertices are read as metres, and the scene says so.
  doc = boxes_cityjson();
  doc.erase("transform");
  dir.write("bare.city.json", doc.dump());
  const shadow::Scene bare = shadow::load_scene(dir.path() / "bare.city.json");
  ASSERT_FALSE(bare.faces.empty());
  bool warned = false;
  for (const shadow::Warning& w : bare.warnings)
    warned |= w.to_string().find("bare.city.json: transform: missing, which CityJSON 2.0 requires") != std::string::npos;
  EXPECT_TRUE(warned);
  dir.write("broken.city.json", "{\"type\": \"CityJSON\",\n \"version\": ");
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.path() / "broken.city.json"); }).find("broken.city.json: line 2"),
            std::string::npos);
}

TEST(CityJson, MessagesNamePlaceAndProblemInWords) {
  TempDir dir("messages");
  const fs::path file = dir.path() / "m.city.json";
  auto message = [&](const std::string& text) {
    std::ofstream(file, std::ios::binary) << text;
    return error_of([&] { shadow::load_scene(file); });
  };
  // A syntax error: line and column, the problem in words, none of the JSON library's tags.
  std::string m = message("{\"type\": \"CityJSON\", \"version\": \"2.0\",\n \"vertices\": [[1, 2 3]]}");
  EXPECT_NE(m.find("m.city.json: line 2, column 21: malformed JSON: "), std::string::npos) << m;
  EXPECT_EQ(m.find("json.exception"), std::string::npos) << m;
  // A number beyond a double: its JSON path.
  Json doc = boxes_cityjson();
  std::string text = doc.dump();
  const std::string first_vertex = "\"vertices\":[[123,456,0]";
  ASSERT_NE(text.find(first_vertex), std::string::npos) << text.substr(0, 200);
  text.replace(text.find(first_vertex), first_vertex.size(), "\"vertices\":[[123,456,1e999]");
  m = message(text);
  EXPECT_NE(m.find("m.city.json: vertices[0][2]: number 1e999 is not finite"), std::string::npos) << m;
  // Bytes that are not UTF-8: shown as \xHH, never raw.
  m = message("{\"type\": \"CityJSON\", \"version\": \"2.0\xc3\x28\"}");
  EXPECT_NE(m.find("m.city.json: line 1, column 38: malformed JSON: "), std::string::npos) << m;
  EXPECT_NE(m.find("\\xc3"), std::string::npos) << m;
  EXPECT_TRUE(std::all_of(m.begin(), m.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; })) << m;
  // A city object written twice: JSON would keep one, a building would vanish.
  text = doc.dump();
  ASSERT_NE(text.find("\"B\":{"), std::string::npos);
  text.replace(text.find("\"B\":{"), 5, "\"A\":{");
  m = message(text);
  EXPECT_NE(m.find("m.city.json: CityObjects: duplicate key \"A\""), std::string::npos) << m;
  // A Solid's boundaries written as a MultiSurface's (one array too few): the nesting is named,
  // not the semantic values that no longer line up with it.
  doc = boxes_cityjson();
  doc["CityObjects"]["A"]["geometry"][0]["boundaries"] = doc["CityObjects"]["A"]["geometry"][0]["boundaries"][0];
  m = message(doc.dump());
  EXPECT_NE(m.find("m.city.json: CityObjects[\"A\"].geometry[0].boundaries[0][0][0]: boundaries nested at the wrong "
                   "depth: a Solid's vertex indices are 4 arrays deep (shells, surfaces, rings, vertex indices), but "
                   "here number 0 is 3 deep"),
            std::string::npos)
      << m;
  EXPECT_EQ(m.find("semantic"), std::string::npos) << m;
  // And one array too many.
  doc = boxes_cityjson();
  doc["CityObjects"]["B"]["geometry"][0]["type"] = "MultiSurface";
  doc["CityObjects"]["B"]["geometry"][0]["semantics"]["values"] = doc["CityObjects"]["B"]["geometry"][0]["semantics"]["values"][0];
  m = message(doc.dump());
  EXPECT_NE(m.find("CityObjects[\"B\"].geometry[0].boundaries[0][0][0]: boundaries nested at the wrong depth: a "
                   "MultiSurface's vertex indices are 3 arrays deep (surfaces, rings, vertex indices), but here an "
                   "array is 3 deep"),
            std::string::npos)
      << m;
}

// ---- placement -----------------------------------------------------------------------------------

std::string unit_cube_polygons() {
  return R"([[[0,0,0],[0,1,0],[1,1,0],[1,0,0]], [[0,0,1],[1,0,1],[1,1,1],[0,1,1]], [[0,0,0],[1,0,0],[1,0,1],[0,0,1]],
            [[1,0,0],[1,1,0],[1,1,1],[1,0,1]], [[1,1,0],[0,1,0],[0,1,1],[1,1,1]], [[0,1,0],[0,0,0],[0,0,1],[0,1,1]]])";
}

shadow::Scene parse(const std::string& meshes) {
  return shadow::parse_scene(R"({"meshes": )" + meshes +
                                 R"(, "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1]}]})",
                             "placed.json");
}

TEST(Placement, TranslateRotateScaleAndMatrixGiveTheSameExactVertices) {
  const shadow::Scene object_form = parse(R"([{"name": "c", "polygons": )" + unit_cube_polygons() +
                                          R"(, "transform": {"scale": 2, "rotate": {"axis": [0,0,1], "degrees": 90},
                                                             "translate": [100, 200, 3]}}])");
  const shadow::Scene matrix_form = parse(R"([{"name": "c", "polygons": )" + unit_cube_polygons() +
                                          R"(, "transform": [[0,-2,0,100],[2,0,0,200],[0,0,2,3],[0,0,0,1]]}])");
  const shadow::Scene euler_form = parse(R"([{"name": "c", "polygons": )" + unit_cube_polygons() +
                                         R"(, "transform": {"scale": [2,2,2], "rotate": [0, 0, 90], "translate": [100, 200, 3]}}])");
  // (1, 0, 0) scaled to (2, 0, 0), turned a quarter counter-clockwise to (0, 2, 0), moved.
  EXPECT_EQ(object_form.faces[0].vertices[3], glm::dvec3(100, 202, 3));
  for (std::size_t f = 0; f < 6; ++f) {
    EXPECT_EQ(object_form.faces[f].vertices, matrix_form.faces[f].vertices);
    EXPECT_EQ(object_form.faces[f].vertices, euler_form.faces[f].vertices);
  }
  EXPECT_TRUE(object_form.warnings.empty());  // still outward: no orientation warning
}

TEST(Placement, AMirrorReversesTheFacesAndSaysSo) {
  const shadow::Scene scene = parse(R"([{"name": "c", "polygons": )" + unit_cube_polygons() +
                                    R"(, "transform": {"scale": [-1, 1, 1]}}])");
  ASSERT_EQ(scene.warnings.size(), 1u) << scene.warnings[0].to_string();
  EXPECT_NE(scene.warnings[0].message.find("mirrors"), std::string::npos);
  EXPECT_EQ(scene.warnings[0].where.place, "meshes[0].transform");
  // The mirrored cube's top still faces up: +z front, counter-clockwise seen from above.
  const auto& top = scene.faces[1].vertices;
  const glm::dvec3 n = glm::cross(top[1] - top[0], top[2] - top[0]);
  EXPECT_GT(n.z, 0);
}

TEST(Placement, YUpObjIsTurnedToZUpAndShadesTheSame) {
  TempDir dir("yup");
  // The same unit box as OBJ, Z-up and Y-up (the export of (x, y, z) is (x, z, -y)).
  std::string z_up, y_up;
  const std::vector<glm::dvec3> c = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (const glm::dvec3& v : c) {
    z_up += "v " + std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + "\n";
    y_up += "v " + std::to_string(v.x) + " " + std::to_string(v.z) + " " + std::to_string(-v.y) + "\n";
  }
  std::string faces;
  for (const auto& f : kFaces)
    faces += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + " " +
             std::to_string(f[3] + 1) + "\n";
  dir.write("z.obj", z_up + faces);
  dir.write("y.obj", y_up + faces);
  const std::string ground = R"({"name": "ground", "polygons": [[[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]]]})";
  auto scene = [&](const std::string& file, const std::string& extra) {
    return shadow::load_scene(dir.write(file + ".json", R"({"meshes": [{"name": "box", "file": ")" + file + "\"" + extra +
                                                            "}, " + ground +
                                                            R"(], "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1]}]})"));
  };
  const shadow::Scene z = scene("z.obj", ""), y = scene("y.obj", R"(, "up_axis": "y")");
  for (std::size_t f = 0; f < z.faces.size(); ++f) EXPECT_EQ(z.faces[f].vertices, y.faces[f].vertices);
  const shadow::ShadowResult a = compute(z), b = compute(y);
  ASSERT_EQ(a.lighting.size(), b.lighting.size());
  for (std::size_t i = 0; i < a.lighting.size(); ++i) EXPECT_EQ(a.lighting[i].lit_area, b.lighting[i].lit_area);
  // Without up_axis the Y-up box lies on its side: the ground gets a different shadow.
  const shadow::Scene wrong = scene("y.obj", "");
  EXPECT_NE(compute(wrong).lighting.back().lit_area, a.lighting.back().lit_area);
  EXPECT_NE(error_of([&] { parse(R"([{"name": "c", "polygons": [[[0,0,0],[1,0,0],[0,1,0]]], "up_axis": "x"}])"); })
                .find("placed.json: meshes[0].up_axis: expected \"z\""),
            std::string::npos);
  EXPECT_NE(error_of([&] { parse(R"([{"name": "c", "polygons": [[[0,0,0],[1,0,0],[0,1,0]]], "transform": {"scale": 0}}])"); })
                .find("meshes[0].transform: the transform is singular"),
            std::string::npos);
}

// ---- names -------------------------------------------------------------------------------------

TEST(Names, ObjGroupsAndInlinePolygonObjectsNameFaces) {
  TempDir dir("groups");
  dir.write("house.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
            "f 1 2 3\no roof\nf 1 3 4\ng south wall\nf 4 3 2\ng\nf 1 2 4\n");
  const shadow::Scene scene = shadow::load_scene(dir.write("s.json", R"({"meshes": [{"name": "h", "file": "house.obj"},
      {"name": "w", "polygons": [{"name": "facade", "kind": "Wall", "vertices": [[0,5,0],[4,5,0],[4,5,3],[0,5,3]],
                                   "holes": [[[1,5,1],[2,5,1],[2,5,2],[1,5,2]]]},
                                  [[9,9,0],[10,9,0],[10,10,0]]]}],
      "lights": [{"name": "sun", "type": "directional", "to_light": [0, -1, 1]}]})"));
  ASSERT_GE(scene.faces.size(), 7u);
  EXPECT_EQ(scene.faces[0].name, "");
  EXPECT_EQ(scene.faces[1].name, "roof");
  EXPECT_EQ(scene.faces[2].name, "south wall");
  EXPECT_EQ(scene.faces[3].name, "");
  std::size_t facade = 0;
  for (std::size_t f = 4; f + 1 < scene.faces.size(); ++f) {
    EXPECT_EQ(scene.faces[f].name, "facade");
    EXPECT_EQ(scene.faces[f].kind, "Wall");
    EXPECT_EQ(scene.faces[f].source.place, "meshes[1].polygons[0]");
    ++facade;
  }
  EXPECT_GE(facade, 2u);
  EXPECT_EQ(scene.faces.back().name, "");
  const auto surfaces = shadow::named_surfaces(scene);
  const auto it = std::find_if(surfaces.begin(), surfaces.end(), [](const auto& s) { return s.label == "facade"; });
  ASSERT_NE(it, surfaces.end());
  EXPECT_EQ(it->faces.size(), facade);
  double area = 0;
  for (const shadow::FaceLighting& fl : compute(scene).lighting)
    if (scene.faces[fl.face_id].name == "facade") area += fl.area;
  EXPECT_NEAR(area, 12.0 - 1.0, 1e-12);
  // A hole outside its polygon: the hole's path.
  EXPECT_NE(error_of([&] {
              parse(R"([{"name": "w", "polygons": [{"vertices": [[0,0,0],[4,0,0],[4,3,0],[0,3,0]],
                                                     "holes": [[[1,1,0],[2,1,0],[2,2,0]], [[5,1,0],[6,1,0],[6,2,0]]]}]}])");
            }).find("placed.json: meshes[0].polygons[0].holes[1]: hole 1 is outside the outer ring (vertex 0)"),
            std::string::npos);
}

// ---- orientation -------------------------------------------------------------------------------

TEST(Orient, AnInwardBoxIsTurnedOutwardAndLitLikeTheOutwardOne) {
  // The unit cube outward, reversed (inward), and with one face reversed (inconsistent), on a
  // ground; with "orient": "outward" the last two must shade exactly like the first.
  auto reversed = [](const std::string& polygons) {
    Json p = Json::parse(polygons);
    for (Json& face : p) std::reverse(face.begin(), face.end());
    return p.dump();
  };
  Json mixed = Json::parse(unit_cube_polygons());
  std::reverse(mixed[3].begin(), mixed[3].end());
  const std::string ground = R"({"name": "ground", "polygons": [[[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]]]})";
  auto scene = [&](const std::string& polygons, const std::string& orient) {
    return parse("[{\"name\": \"box\", \"polygons\": " + polygons + orient + "}, " + ground + "]");
  };
  const shadow::Scene outward = scene(unit_cube_polygons(), "");
  const shadow::Scene inward = scene(reversed(unit_cube_polygons()), "");
  ASSERT_EQ(inward.warnings.size(), 1u);
  EXPECT_NE(inward.warnings[0].message.find("mesh \"box\" is closed, and its faces point inward (faces 0, 1, 2, 3, 4 and 1 more"),
            std::string::npos)
      << inward.warnings[0].message;
  const shadow::Scene fixed = scene(reversed(unit_cube_polygons()), R"(, "orient": "outward")");
  ASSERT_EQ(fixed.warnings.size(), 1u);
  EXPECT_NE(fixed.warnings[0].message.find("were reversed (orient outward)"), std::string::npos);
  const shadow::Scene made_consistent = scene(mixed.dump(), R"(, "orient": "outward")");
  ASSERT_EQ(made_consistent.warnings.size(), 1u);
  EXPECT_NE(made_consistent.warnings[0].message.find("to agree with face 0, reversed face 3;"), std::string::npos)
      << made_consistent.warnings[0].message;
  const shadow::ShadowResult expected = compute(outward);
  for (const shadow::Scene* s : {&fixed, &made_consistent}) {
    const shadow::ShadowResult got = compute(*s);
    ASSERT_EQ(got.lighting.size(), expected.lighting.size());
    for (std::size_t i = 0; i < got.lighting.size(); ++i) {
      EXPECT_EQ(got.lighting[i].lit_area, expected.lighting[i].lit_area) << "face " << got.lighting[i].face_id;
      EXPECT_EQ(got.lighting[i].faces_light, expected.lighting[i].faces_light);
    }
  }
  // The inward box without orienting: its top is in attached shadow; outward, it is lit.
  EXPECT_FALSE(compute(inward).lighting[1].faces_light);
  EXPECT_TRUE(expected.lighting[1].faces_light);
  // The load option does the same for every mesh.
  shadow::LoadOptions options;
  options.orient_outward = true;
  shadow::Scene by_option = scene(reversed(unit_cube_polygons()), "");
  by_option.warnings.clear();
  shadow::validate_scene(by_option, options);
  EXPECT_EQ(compute(by_option).lighting[1].lit_area, expected.lighting[1].lit_area);
}

// ---- outputs -----------------------------------------------------------------------------------

TEST(Outputs, FacesCarryIdentityAndOrientationInReportAndVtp) {
  TempDir dir("outputs");
  dir.write("boxes.city.json", boxes_cityjson().dump());
  const shadow::Scene scene = shadow::load_scene(dir.write("city.json", scene_with("boxes.city.json")));
  const shadow::ShadowResult result = compute(scene);
  std::ostringstream report;
  shadow::write_report_json(report, scene, result);
  const Json r = Json::parse(report.str());
  EXPECT_EQ(r["origin"], Json::array({90000.0, 435000.0, 1.0}));
  const Json& roof = r["faces"][1];
  EXPECT_EQ(roof["name"], "A/1");
  EXPECT_EQ(roof["kind"], "RoofSurface");
  EXPECT_EQ(roof["tilt"], 0.0);
  EXPECT_EQ(roof["normal"], Json::array({0.0, 0.0, 1.0}));
  EXPECT_NE(roof["source"].get<std::string>().find("boundaries[0][1]"), std::string::npos);
  // Walls: south (y0) faces azimuth 180, east 90, north 0, west 270; vertical.
  const double expected_azimuth[4] = {180, 90, 0, 270};
  for (int w = 0; w < 4; ++w) {
    EXPECT_NEAR(r["faces"][2 + w]["azimuth"].get<double>(), expected_azimuth[w], 1e-9) << w;
    EXPECT_NEAR(r["faces"][2 + w]["tilt"].get<double>(), 90.0, 1e-9);
  }
  EXPECT_NEAR(r["faces"][0]["tilt"].get<double>(), 180.0, 1e-9);  // the ground surface faces down
  ASSERT_EQ(r["summary"]["per_mesh"].size(), 2u);
  EXPECT_EQ(r["summary"]["per_mesh"][0]["mesh"], "city/A");

  shadow::write_outputs(dir.path() / "out", scene, result);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((dir.path() / "out" / "faces.vtp").c_str());
  reader->Update();
  vtkPolyData* faces = reader->GetOutput();
  ASSERT_EQ(faces->GetNumberOfCells(), 12);
  auto* names = vtkStringArray::SafeDownCast(faces->GetCellData()->GetAbstractArray("name"));
  auto* kinds = vtkStringArray::SafeDownCast(faces->GetCellData()->GetAbstractArray("kind"));
  ASSERT_NE(names, nullptr);
  ASSERT_NE(kinds, nullptr);
  EXPECT_EQ(names->GetValue(7), "B/1");
  EXPECT_EQ(kinds->GetValue(7), "RoofSurface");
  vtkDataArray* normal = faces->GetCellData()->GetArray("normal");
  ASSERT_NE(normal, nullptr);
  EXPECT_EQ(normal->GetNumberOfComponents(), 3);
  EXPECT_EQ(normal->GetTuple3(3)[0], 1.0);  // A's east wall
  EXPECT_NEAR(faces->GetCellData()->GetArray("azimuth")->GetTuple1(3), 90.0, 1e-9);
  EXPECT_NEAR(faces->GetCellData()->GetArray("tilt")->GetTuple1(3), 90.0, 1e-9);
  // Points relative to the origin: small numbers that float32 rendering keeps.
  double p[3];
  faces->GetPoint(0, p);
  EXPECT_EQ(p[0], scene.faces[0].vertices[0].x - 90000.0);
  EXPECT_LT(std::fabs(p[0]) + std::fabs(p[1]) + std::fabs(p[2]), 100.0);
  vtkDataArray* origin = faces->GetFieldData()->GetArray("origin");
  ASSERT_NE(origin, nullptr);
  EXPECT_EQ(origin->GetTuple3(0)[1], 435000.0);
}

}  // namespace

namespace {

TEST(CityJson, MultiSolidAndNonPlanarSurfacesAndNullSemantics) {
  TempDir dir("multisolid");
  // Two unit cubes as one MultiSolid (no semantics), and a MultiSurface quad whose fourth corner
  // is 5 mm above the plane of the other three: split into 2 triangles of its own vertices.
  Json doc = boxes_cityjson();
  Json solids = Json::array();
  for (const char* id : {"A", "B"}) solids.push_back(doc["CityObjects"][id]["geometry"][0]["boundaries"]);
  doc["CityObjects"] = {{"M", {{"type", "GenericCityObject"},
                               {"geometry", {{{"type", "MultiSolid"}, {"lod", "2"}, {"boundaries", solids}}}}}},
                        {"Q", {{"type", "LandUse"},
                               {"geometry", {{{"type", "MultiSurface"}, {"lod", 1},
                                              {"boundaries", {{{16, 17, 18, 19}}}},
                                              {"semantics", {{"surfaces", Json::array()}, {"values", {nullptr}}}}}}}}}};
  for (const auto& v : std::vector<std::array<long long, 3>>{{0, 20000, 0}, {4000, 20000, 0}, {4000, 24000, 5}, {0, 24000, 0}})
    doc["vertices"].push_back({v[0], v[1], v[2]});
  const shadow::Scene scene = shadow::load_scene(dir.write("m.city.json", doc.dump()));
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[0].face_count, 12u);
  EXPECT_EQ(scene.faces[7].name, "M/7");  // surfaces counted across the solids
  EXPECT_EQ(scene.faces[7].kind, "");
  ASSERT_EQ(scene.meshes[1].face_count, 2u);
  EXPECT_EQ(scene.faces[12].name, "Q/0");
  EXPECT_EQ(scene.faces[12].vertices.size(), 3u);
  EXPECT_EQ(scene.faces[13].name, "Q/0");
  bool warned = false;
  for (const shadow::Warning& w : scene.warnings) warned |= w.message.find("1 surfaces are not planar") != std::string::npos;
  EXPECT_TRUE(warned);
  // The triangles cover the quad's chart exactly: 4 m x 4 m.
  double area = 0;
  for (std::size_t f = 12; f < 14; ++f) {
    const auto& v = scene.faces[f].vertices;
    area += std::fabs((v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y)) / 2;
  }
  EXPECT_DOUBLE_EQ(area, 16.0);
}

TEST(Outputs, AzimuthFollowsTheSunsNorthAxis) {
  // A wall facing +x is east (90) with +y north; with the model's +y 30 degrees clockwise from
  // north (EnergyPlus's Building North Axis), it faces 120.
  shadow::Scene scene = parse(R"([{"name": "w", "polygons": [{"name": "east", "vertices": [[0,0,0],[0,1,0],[0,1,1],[0,0,1]]}]}])");
  shadow::SunPeriod sun;
  sun.north_axis = 30;
  const shadow::ShadowResult result = compute(scene);
  std::ostringstream plain, turned;
  shadow::write_report_json(plain, scene, result);
  scene.sun = sun;
  shadow::write_report_json(turned, scene, result);
  EXPECT_NEAR(Json::parse(plain.str())["faces"][0]["azimuth"].get<double>(), 90.0, 1e-9);
  EXPECT_NEAR(Json::parse(turned.str())["faces"][0]["azimuth"].get<double>(), 120.0, 1e-9);
  EXPECT_EQ(Json::parse(turned.str())["faces"][0]["name"], "east");
  EXPECT_EQ(Json::parse(turned.str())["faces"][0]["source"], "placed.json: meshes[0].polygons[0]");
}

}  // namespace

// ---- invalid faces skipped, receivers and maps chosen by CityJSON object type (issue 31, 7 and 9)

namespace {

/// The boxes of boxes_cityjson() and a BuildingPart "C": a MultiSurface whose surface 0 is a
/// bow-tie (planar, its boundary crossing itself, as in Zürich's LoD2 sample) and whose surface 1
/// is a good 2 m x 2 m quad; and a TINRelief "T": one ground quad.
Json boxes_with_a_broken_part() {
  Json doc = boxes_cityjson();
  const std::size_t base = doc["vertices"].size();
  for (const auto& v : std::vector<std::array<long long, 3>>{
           {30000, 0, 0}, {32000, 2000, 0}, {32000, 0, 0}, {30000, 2000, 0},      // bow-tie: 0 1 2 3 crosses
           {40000, 0, 0}, {42000, 0, 0}, {42000, 2000, 0}, {40000, 2000, 0},      // the good quad
           {-5000, -5000, 0}, {60000, -5000, 0}, {60000, 20000, 0}, {-5000, 20000, 0}})  // the terrain
    doc["vertices"].push_back({v[0], v[1], v[2]});
  auto ring = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t d) {
    return Json::array({Json::array({base + a, base + b, base + c, base + d})});
  };
  doc["CityObjects"]["C"] = {{"type", "BuildingPart"},
                             {"geometry", {{{"type", "MultiSurface"}, {"lod", "2"},
                                            {"boundaries", Json::array({ring(0, 1, 2, 3), ring(4, 5, 6, 7)})}}}}};
  doc["CityObjects"]["T"] = {{"type", "TINRelief"},
                             {"geometry", {{{"type", "MultiSurface"}, {"lod", "1"},
                                            {"boundaries", Json::array({ring(8, 9, 10, 11)})}}}}};
  return doc;
}

shadow::LoadOptions skipping() {
  shadow::LoadOptions options;
  options.skip_invalid = true;
  return options;
}

TEST(SkipInvalid, ASelfIntersectingCityJsonSurfaceStopsTheCityWithoutTheFlagAndIsSkippedWithIt) {
  TempDir dir("skip_cityjson");
  dir.write("broken.city.json", boxes_with_a_broken_part().dump());
  const fs::path scene_file = dir.write("scene.json", scene_with("broken.city.json"));
  // Without the flag: the first bad face stops the load, and the message says how to go on.
  const std::string error = error_of([&] { shadow::load_scene(scene_file); });
  EXPECT_NE(error.find("broken.city.json: CityObjects[\"C\"].geometry[0].boundaries[0]: face boundary intersects itself "
                       "(--skip-invalid skips such faces"),
            std::string::npos)
      << error;
  // With it: the bow-tie is left out, everything else is read, and face ids count the faces kept.
  const shadow::Scene scene = shadow::load_scene(scene_file, skipping());
  ASSERT_EQ(scene.faces.size(), 14u);  // 12 of the boxes, C's good quad, the terrain
  ASSERT_EQ(scene.meshes.size(), 4u);
  EXPECT_EQ(scene.meshes[2].name, "city/C");
  EXPECT_EQ(scene.meshes[2].first_face, 12u);
  EXPECT_EQ(scene.meshes[2].face_count, 1u);
  EXPECT_EQ(scene.faces[12].name, "C/1");
  EXPECT_EQ(scene.meshes[3].first_face, 13u);
  EXPECT_EQ(scene.faces[13].name, "T/0");
  ASSERT_EQ(scene.skipped_faces.size(), 1u);
  const shadow::SkippedFace& skipped = scene.skipped_faces[0];
  EXPECT_EQ(skipped.name, "C/0");
  EXPECT_EQ(skipped.mesh, "city/C");
  EXPECT_EQ(skipped.reason, "face boundary intersects itself");
  EXPECT_EQ(skipped.source.to_string(), (dir.path() / "broken.city.json").lexically_normal().string() +
                                            ": CityObjects[\"C\"].geometry[0].boundaries[0]");
  std::size_t skip_warnings = 0;
  for (const shadow::Warning& w : scene.warnings)
    if (w.message.find("skipped (--skip-invalid)") != std::string::npos) {
      ++skip_warnings;
      EXPECT_NE(w.message.find("\"C/0\" (mesh \"city/C\") is invalid: face boundary intersects itself"), std::string::npos)
          << w.message;
    }
  EXPECT_EQ(skip_warnings, 1u);
  // The model read whole skips the same face; a second validation changes nothing.
  shadow::Scene whole = shadow::load_scene(dir.path() / "broken.city.json", skipping());
  EXPECT_EQ(whole.faces.size(), 14u);
  ASSERT_EQ(whole.skipped_faces.size(), 1u);
  EXPECT_EQ(whole.skipped_faces[0].mesh, "C");
  const std::size_t warnings = whole.warnings.size();
  shadow::validate_scene(whole);
  EXPECT_EQ(whole.faces.size(), 14u);
  EXPECT_EQ(whole.warnings.size(), warnings);
  // report.json: the count in the summary and the face with its reason.
  const shadow::ShadowResult result = compute(scene);
  std::ostringstream report;
  shadow::write_report_json(report, scene, result);
  const Json json = Json::parse(report.str());
  EXPECT_EQ(json["summary"]["skipped_faces"], 1);
  ASSERT_EQ(json["skipped_faces"].size(), 1u);
  EXPECT_EQ(json["skipped_faces"][0]["name"], "C/0");
  EXPECT_EQ(json["skipped_faces"][0]["mesh"], "city/C");
  EXPECT_EQ(json["skipped_faces"][0]["reason"], "face boundary intersects itself");
  EXPECT_EQ(json["faces"].size(), 14u);
  EXPECT_EQ(json["faces"][12]["name"], "C/1");
  EXPECT_NEAR(json["faces"][12]["area"].get<double>(), 4.0, 1e-9);
}

TEST(SkipInvalid, ASelfIntersectingObjFaceStopsWithoutTheFlagAndIsSkippedWithIt) {
  TempDir dir("skip_obj");
  dir.write("m.obj", "o good\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                     "o bowtie\nv 3 0 0\nv 4 1 0\nv 4 0 0\nv 3 1 0\nf 5 6 7 8\n"
                     "o after\nv 6 0 0\nv 7 0 0\nv 6 1 0\nf 9 10 11\n");
  const fs::path scene_file = dir.write(
      "scene.json", R"({"meshes": [{"name": "m", "file": "m.obj"}, {"name": "q", "polygons": [[[0,0,1],[1,0,1],[0,1,1]]]}],
                        "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})");
  const std::string error = error_of([&] { shadow::load_scene(scene_file); });
  EXPECT_NE(error.find("m.obj: line 12: face boundary intersects itself (--skip-invalid skips such faces"), std::string::npos)
      << error;
  const shadow::Scene scene = shadow::load_scene(scene_file, skipping());
  ASSERT_EQ(scene.faces.size(), 3u);
  EXPECT_EQ(scene.faces[1].name, "after");
  EXPECT_EQ(scene.meshes[0].face_count, 2u);
  EXPECT_EQ(scene.meshes[1].first_face, 2u);
  ASSERT_EQ(scene.skipped_faces.size(), 1u);
  EXPECT_EQ(scene.skipped_faces[0].name, "bowtie");
  EXPECT_EQ(scene.skipped_faces[0].mesh, "m");
  EXPECT_EQ(scene.skipped_faces[0].source.place, "line 12");
  // The faces kept compute as they would alone: the lit triangle above has area 1/2.
  const shadow::ShadowResult result = compute(scene);
  ASSERT_EQ(result.lighting.size(), 3u);
  EXPECT_EQ(result.lighting[2].face_id, 2u);
  EXPECT_DOUBLE_EQ(result.lighting[2].lit_area, 0.5);
}

TEST(SkipInvalid, WarningsAreCappedAndEveryKindOfBadFaceIsSkipped) {
  // 12 bow-ties, a non-planar quad and a face with 2 distinct vertices among good faces.
  std::string polygons = R"([[0,0,0],[1,0,0],[1,1,0],[0,1,0]])";
  for (int i = 0; i < 12; ++i) {
    const std::string x = std::to_string(2 * i + 2), x1 = std::to_string(2 * i + 3);
    polygons += ", [[" + x + ",0,0],[" + x1 + ",1,0],[" + x1 + ",0,0],[" + x + ",1,0]]";
  }
  polygons += R"(, [[0,5,0],[1,5,0],[1,6,0.5],[0,6,0]], [[0,8,0],[1,8,0],[1,8,0]], [[0,9,0],[1,9,0],[0,10,0]])";
  const std::string text = R"({"meshes": [{"name": "m", "polygons": [)" + polygons +
                           R"(]}], "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})";
  const shadow::Scene scene = shadow::parse_scene(text, "many.json", skipping());
  EXPECT_EQ(scene.faces.size(), 2u);
  ASSERT_EQ(scene.skipped_faces.size(), 14u);
  EXPECT_EQ(scene.skipped_faces[12].reason.rfind("face is not planar", 0), 0u) << scene.skipped_faces[12].reason;
  EXPECT_EQ(scene.skipped_faces[13].reason, "face has 2 distinct vertices; at least 3 are needed");
  EXPECT_EQ(scene.skipped_faces[13].source.place, "meshes[0].polygons[14]");
  std::size_t one_by_one = 0, summary = 0;
  for (const shadow::Warning& w : scene.warnings) {
    one_by_one += w.message.rfind("skipped (--skip-invalid)", 0) == 0;
    summary += w.message == "4 more invalid faces were skipped (14 in all; report.json lists each in skipped_faces)";
  }
  EXPECT_EQ(one_by_one, 10u);
  EXPECT_EQ(summary, 1u);
  // Not planar without the flag: the message names the flag too.
  EXPECT_NE(error_of([&] { shadow::parse_scene(R"({"meshes": [{"name": "m", "polygons": [[[0,5,0],[1,5,0],[1,6,0.5],[0,6,0]]]}],
                                                  "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})",
                                               "p.json"); })
                .find("face is not planar"),
            std::string::npos);
}

TEST(SkipInvalid, ASurfaceTheCityJsonReaderCannotCutIsSkippedToo) {
  // An inner ring outside its surface: the reader's error names the flag; with it the surface goes.
  TempDir dir("skip_ring");
  Json doc = boxes_cityjson();
  Json& roof = doc["CityObjects"]["A"]["geometry"][0]["boundaries"][0][1];
  const std::size_t base = doc["vertices"].size();
  for (const auto& v : std::vector<std::array<long long, 3>>{{50000, 0, 4000}, {50000, 1000, 4000}, {51000, 1000, 4000}})
    doc["vertices"].push_back({v[0], v[1], v[2]});
  roof.push_back(Json::array({base, base + 1, base + 2}));
  const fs::path file = dir.write("ring.city.json", doc.dump());
  const std::string error = error_of([&] { shadow::load_scene(file); });
  EXPECT_NE(error.find("boundaries[0][1][1]: inner ring 1"), std::string::npos) << error;
  EXPECT_NE(error.find("(--skip-invalid skips such faces"), std::string::npos) << error;
  const shadow::Scene scene = shadow::load_scene(file, skipping());
  EXPECT_EQ(scene.faces.size(), 11u);
  ASSERT_EQ(scene.skipped_faces.size(), 1u);
  EXPECT_EQ(scene.skipped_faces[0].name, "A/1");
  EXPECT_EQ(scene.skipped_faces[0].mesh, "A");
  EXPECT_EQ(scene.faces[1].name, "A/2");
  bool warned = false;
  for (const shadow::Warning& w : scene.warnings) warned |= w.message.find("\"A/1\" (mesh \"A\") is invalid: inner ring 1") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(SkipInvalid, ASceneWithNoValidFaceLeftIsAnError) {
  const std::string error = error_of([&] {
    shadow::parse_scene(R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,1,0],[1,0,0],[0,1,0]]]}],
                           "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})",
                        "all.json", skipping());
  });
  EXPECT_NE(error.find("all.json: meshes[0].polygons[0]: every face of the scene is invalid (1 skipped with --skip-invalid)"),
            std::string::npos)
      << error;
}

std::string typed_scene(const std::string& extra) {
  return R"({"meshes": [{"name": "city", "file": "typed.city.json"},
                        {"name": "ground", "polygons": [[[-100,-100,0],[100,-100,0],[100,100,0],[-100,100,0]]]}],
             "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 0.9]}])" +
         extra + "}";
}

TEST(MeshTypes, ReceiversAndSunHoursMapsByCityJsonObjectType) {
  TempDir dir("types");
  Json doc = boxes_with_a_broken_part();
  doc["CityObjects"].erase("C");  // only the boxes (Building) and the terrain (TINRelief)
  dir.write("typed.city.json", doc.dump());
  // The object types are the meshes' types.
  const shadow::Scene whole = shadow::load_scene(dir.path() / "typed.city.json");
  ASSERT_EQ(whole.meshes.size(), 3u);
  EXPECT_EQ(whole.meshes[0].object_type, "Building");
  EXPECT_EQ(whole.meshes[2].object_type, "TINRelief");
  // receivers by type: the terrain receives, the buildings and the scene's ground do not.
  const shadow::Scene terrain = shadow::load_scene(dir.write("r.json", typed_scene(R"(, "receivers": ["type:TINRelief"])")));
  ASSERT_EQ(terrain.meshes.size(), 4u);
  EXPECT_FALSE(terrain.meshes[0].receiver);
  EXPECT_FALSE(terrain.meshes[1].receiver);
  EXPECT_TRUE(terrain.meshes[2].receiver);
  EXPECT_EQ(terrain.meshes[2].name, "city/T");
  EXPECT_FALSE(terrain.meshes[3].receiver);
  // sun_hours_map: by type, by `mesh/<id>` (as --sun-hours-map and receivers take them) and by a
  // scene mesh's name, which is the scene mesh it became even after a model's many meshes.
  const shadow::Scene mapped = shadow::load_scene(
      dir.write("m.json", typed_scene(R"(, "sun_hours_map": ["type:Building", "city/T"])")));
  EXPECT_EQ(mapped.sun_hours_map, (std::vector<std::size_t>{0, 1, 2}));
  const shadow::Scene ground = shadow::load_scene(dir.write("g.json", typed_scene(R"(, "sun_hours_map": ["ground"])")));
  ASSERT_EQ(ground.sun_hours_map.size(), 1u);
  EXPECT_EQ(ground.meshes[ground.sun_hours_map[0]].name, "ground");
  const shadow::Scene city = shadow::load_scene(dir.write("c.json", typed_scene(R"(, "sun_hours_map": ["city"])")));
  EXPECT_EQ(city.sun_hours_map, (std::vector<std::size_t>{0, 1, 2}));
  // The library's choice for --sun-hours-map (and Python's sun_hours_map_faces).
  EXPECT_EQ(shadow::sun_hours_map_faces(mapped, {"type:TINRelief"}, "--sun-hours-map"), (std::vector<std::size_t>{12}));
  EXPECT_EQ(shadow::sun_hours_map_faces(mapped, {"city/B", "type:TINRelief"}, "--sun-hours-map"),
            (std::vector<std::size_t>{6, 7, 8, 9, 10, 11, 12}));
  // The scene mesh's own name on --sun-hours-map, as the scene key takes it: every mesh of its
  // model, and not the scene's other meshes.
  const std::size_t city_faces = mapped.meshes[3].first_face;
  std::vector<std::size_t> all_city(city_faces);
  for (std::size_t f = 0; f < city_faces; ++f) all_city[f] = f;
  EXPECT_EQ(shadow::sun_hours_map_faces(mapped, {"city"}, "--sun-hours-map"), all_city);
  EXPECT_EQ(shadow::select_meshes(mapped, "city", {"", "--sun-hours-map"}), (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_NE(error_of([&] { shadow::sun_hours_map_faces(mapped, {"cit"}, "--sun-hours-map"); })
                .find("--sun-hours-map: no mesh is named \"cit\""),
            std::string::npos);
  // Only the scene mesh's own name: not the start of a model id holding '/', nor a model read
  // as the scene itself (its meshes have no scene mesh).
  Json slashed = doc;
  slashed["CityObjects"]["T/1"] = slashed["CityObjects"]["T"];
  slashed["CityObjects"].erase("T");
  dir.write("slashed.city.json", slashed.dump());
  const shadow::Scene alone = shadow::load_scene(dir.path() / "slashed.city.json");
  EXPECT_NE(error_of([&] { shadow::sun_hours_map_faces(alone, {"T"}, "--sun-hours-map"); })
                .find("--sun-hours-map: no mesh is named \"T\""),
            std::string::npos);
  EXPECT_EQ(shadow::select_meshes(alone, "T/1", {"", "--sun-hours-map"}).size(), 1u);
  EXPECT_NE(error_of([&] { shadow::sun_hours_map_faces(whole, {"city"}, "--sun-hours-map"); })
                .find("no mesh is named \"city\""),
            std::string::npos);
  const shadow::Scene inside = shadow::load_scene(dir.write(
      "s.json", R"({"meshes": [{"name": "city", "file": "slashed.city.json"}],
                    "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 0.9]}]})"));
  EXPECT_EQ(shadow::select_meshes(inside, "city", {"", "--sun-hours-map"}).size(), inside.meshes.size());
  EXPECT_NE(error_of([&] { shadow::select_meshes(inside, "city/T", {"", "--sun-hours-map"}); })
                .find("no mesh is named \"city/T\""),
            std::string::npos);
  // An unknown type names the key or flag, the type and the types present.
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.write("u.json", typed_scene(R"(, "receivers": ["type:Bridge"])"))); })
                .find("u.json: receivers[0]: the type \"Bridge\" selects no mesh (the object types present: "
                      "Building, TINRelief)"),
            std::string::npos);
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.write("v.json", typed_scene(R"(, "sun_hours_map": ["type:building"])"))); })
                .find("v.json: sun_hours_map[0]: the type \"building\" selects no mesh (the object types "
                      "present: Building, TINRelief)"),
            std::string::npos);
  EXPECT_NE(error_of([&] { shadow::sun_hours_map_faces(mapped, {"type:Road"}, "--sun-hours-map"); })
                .find("--sun-hours-map: the type \"Road\" selects no mesh"),
            std::string::npos);
  // A scene without city objects says what type: selects.
  const shadow::Scene plain = shadow::parse_scene(
      R"({"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0],[0,1,0]]]}], "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]})",
      "plain.json");
  EXPECT_NE(error_of([&] { shadow::sun_hours_map_faces(plain, {"type:Building"}, "--sun-hours-map"); })
                .find("no mesh has an object type: type:<T> selects CityJSON city objects by their type"),
            std::string::npos);
  // A misspelt mesh name is still found before any model is read, with a suggestion.
  EXPECT_NE(error_of([&] { shadow::load_scene(dir.write("w.json", typed_scene(R"(, "sun_hours_map": ["grund"])"))); })
                .find("w.json: sun_hours_map[0]: no mesh is named \"grund\" (did you mean \"ground\"?)"),
            std::string::npos);
}

}  // namespace
