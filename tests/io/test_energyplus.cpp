// SPDX-License-Identifier: GPL-3.0-or-later
// EnergyPlus geometry in (IDF and epJSON): the example model both ways, coordinate systems,
// windows cut out of their walls, the sun, and one-line errors with line and field.
#include <shadow/energyplus.hpp>
#include <shadow/series_files.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/series.hpp>
#include <shadow/shadows.hpp>

#include "readers/energyplus_reader.hpp"
#include "readers/idf_tokenizer.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using glm::dvec3;
using shadow::Face;
using shadow::InputError;
using shadow::Scene;
using shadow::scene_readers::Model;
using shadow::scene_readers::parse_energyplus;
using shadow::scene_readers::read_energyplus;

const fs::path kExample = fs::path(LIBSHADOW_EXAMPLES_DIR) / "energyplus";

::testing::AssertionResult ThrowsInputError(const std::function<void()>& action,
                                            const std::vector<std::string>& parts) {
  try {
    action();
  } catch (const InputError& e) {
    const std::string message = e.what();
    if (message.find('\n') != std::string::npos) return ::testing::AssertionFailure() << "two lines: " << message;
    for (const std::string& part : parts)
      if (message.find(part) == std::string::npos)
        return ::testing::AssertionFailure() << "\"" << part << "\" not in: " << message;
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "no InputError";
}

Model idf(const std::string& text) { return parse_energyplus(text, "m.idf", false); }

/// Twice the area vector (Newell); exact here: the tests use small dyadic coordinates.
dvec3 newell(const std::vector<dvec3>& v) {
  dvec3 n(0.0);
  for (std::size_t a = 0; a < v.size(); ++a) {
    const dvec3& p = v[a];
    const dvec3& q = v[(a + 1) % v.size()];
    n += dvec3((p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x), (p.x - q.x) * (p.y + q.y));
  }
  return n;
}

double area(const std::vector<dvec3>& v) { return glm::length(newell(v)) / 2; }

std::map<std::string, double> area_by_name(const Model& m) {
  std::map<std::string, double> out;
  for (const Face& f : m.faces) out[f.name] += area(f.vertices);
  return out;
}

Scene scene_of(const Model& m, const dvec3& to_light) {
  Scene scene;
  scene.meshes = m.meshes;
  scene.faces = m.faces;
  scene.lights.push_back({"sun", shadow::LightType::Directional, to_light});
  shadow::validate_scene(scene);
  return scene;
}

const char* kHeader =
    "Version, 24.1;\n"
    "GlobalGeometryRules, UpperLeftCorner, Counterclockwise, Relative;\n"
    "Zone, Z1;\n";

// --- The example --------------------------------------------------------------------------

TEST(EnergyPlus, ExampleIdfAndEpJsonGiveTheSameFacesBitForBit) {
  const Model a = read_energyplus(kExample / "box-office.idf", "box-office.idf", {});
  const Model b = read_energyplus(kExample / "box-office.epJSON", "box-office.epJSON", {});
  ASSERT_EQ(a.faces.size(), b.faces.size());
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    EXPECT_EQ(a.meshes[m].name, b.meshes[m].name);
    EXPECT_EQ(a.meshes[m].first_face, b.meshes[m].first_face);
    EXPECT_EQ(a.meshes[m].face_count, b.meshes[m].face_count);
    EXPECT_EQ(a.meshes[m].receiver, b.meshes[m].receiver);
  }
  for (std::size_t f = 0; f < a.faces.size(); ++f) {
    EXPECT_EQ(a.faces[f].name, b.faces[f].name);
    EXPECT_EQ(a.faces[f].kind, b.faces[f].kind);
    EXPECT_EQ(a.faces[f].mesh, b.faces[f].mesh);
    ASSERT_EQ(a.faces[f].vertices.size(), b.faces[f].vertices.size()) << a.faces[f].name;
    for (std::size_t v = 0; v < a.faces[f].vertices.size(); ++v)
      for (int c = 0; c < 3; ++c)  // bit for bit: == on doubles, not a tolerance
        EXPECT_EQ(a.faces[f].vertices[v][c], b.faces[f].vertices[v][c]) << a.faces[f].name << " vertex " << v;
  }
  ASSERT_TRUE(a.sun && b.sun);
  EXPECT_EQ(a.sun->site.latitude, b.sun->site.latitude);
  EXPECT_EQ(a.sun->site.longitude, b.sun->site.longitude);
  EXPECT_EQ(a.sun->north_axis, b.sun->north_axis);
  EXPECT_EQ(a.sun->start, b.sun->start);
  EXPECT_EQ(a.sun->step_minutes, b.sun->step_minutes);
}

TEST(EnergyPlus, ExampleMeshesNamesKindsAndSources) {
  const Model m = read_energyplus(kExample / "box-office.idf", "box-office.idf", {});
  std::vector<std::string> meshes;
  for (const auto& mesh : m.meshes) meshes.push_back(mesh.name + (mesh.receiver ? "+" : "-"));
  EXPECT_EQ(meshes, (std::vector<std::string>{"Office+", "Shading:Building-", "Shading:Site-", "Not exposed-"}));
  std::map<std::string, std::string> kind;
  for (const Face& f : m.faces) kind[f.name] = f.kind;
  const std::map<std::string, std::string> expected{
      {"Wall-South", "Wall"}, {"Wall-East", "Wall"}, {"Wall-North", "Wall"}, {"Wall-West", "Wall"},
      {"Roof", "Roof"}, {"Floor", "Floor"}, {"Window-South", "Window"}, {"Window-East", "Window"},
      {"Door-South", "Door"}, {"Overhang-South", "Shading"}, {"Neighbour-North-Face", "Shading"},
      {"Neighbour-West-Face", "Shading"}, {"Neighbour-Roof", "Shading"},
      {"Neighbour-South-Face", "Shading"}, {"Neighbour-East-Face", "Shading"}};
  EXPECT_EQ(kind, expected);
  for (const Face& f : m.faces) {
    EXPECT_EQ(f.source.file, "box-office.idf");
    EXPECT_EQ(f.source.place.rfind("line ", 0), 0u) << f.source.place;
    EXPECT_NE(f.source.place.find("\"" + f.name + "\""), std::string::npos) << f.source.place;
  }
  EXPECT_EQ(m.faces[0].source.to_string(), "box-office.idf: line 86, BuildingSurface:Detailed \"Wall-South\"");
  // The floor is on the ground: it casts but is no receiver.
  for (const Face& f : m.faces)
    EXPECT_EQ(m.meshes[f.mesh].receiver, f.kind != "Shading" && f.name != "Floor") << f.name;
}

TEST(EnergyPlus, ExampleNamedSurfacesAreExactlyTheExteriorSurfaces) {
  // What `shadow series` writes as energyplus-shading.csv's columns: the named receiving
  // surfaces, the wall pieces added up under the wall's name; no shading, no ground floor.
  const Model m = read_energyplus(kExample / "box-office.idf", "box-office.idf", {});
  const Scene scene = scene_of(m, dvec3(0, -1, 1));
  std::vector<std::string> labels;
  for (const auto& surface : shadow::named_surfaces(scene)) labels.push_back(surface.label);
  EXPECT_EQ(labels, (std::vector<std::string>{"Wall-South", "Window-South", "Door-South", "Wall-East", "Window-East",
                                              "Wall-North", "Wall-West", "Roof"}));
}

TEST(EnergyPlus, AsAMeshFileTheModelKeepsItsReceivers) {
  // examples/energyplus/scene.json names the IDF as a mesh file: the scene's meshes are
  // office/<model mesh>, and shading and the ground floor still only cast.
  const Scene scene = shadow::load_scene(kExample / "scene.json");
  std::vector<std::string> receiving;
  for (const auto& surface : shadow::named_surfaces(scene)) receiving.push_back(surface.label);
  EXPECT_EQ(receiving, (std::vector<std::string>{"Wall-South", "Window-South", "Door-South", "Wall-East",
                                                 "Window-East", "Wall-North", "Wall-West", "Roof"}));
  EXPECT_EQ(scene.meshes.front().name, "office/Office");
}

TEST(EnergyPlus, RecognisedByContentUnderAnyNameAndMarkedAsEnergyPlus) {
  // An IDF whose first object comes after 64 KiB of comments, and the epJSON, under names that
  // do not say what they are: read as EnergyPlus models, their meshes marked so (which makes
  // `shadow series` write energyplus-shading.csv).
  std::ifstream idf_in(kExample / "box-office.idf"), json_in(kExample / "box-office.epJSON");
  const std::string idf_text((std::istreambuf_iterator<char>(idf_in)), std::istreambuf_iterator<char>());
  const std::string json_text((std::istreambuf_iterator<char>(json_in)), std::istreambuf_iterator<char>());
  std::string comments;
  while (comments.size() < 70000) comments += "! a long header, as model generators write them\n";
  const fs::path dir = fs::temp_directory_path() / ("libshadow-ep-content-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "model.txt") << comments << idf_text;
  std::ofstream(dir / "model.json") << json_text;
  for (const char* name : {"model.txt", "model.json"}) {
    const Scene scene = shadow::load_scene(dir / name);
    EXPECT_EQ(scene.faces.size(), shadow::load_scene(kExample / "box-office.idf").faces.size()) << name;
    for (const shadow::Mesh& mesh : scene.meshes) EXPECT_EQ(mesh.model, "energyplus") << name;
    EXPECT_TRUE(shadow::energyplus_shading_wanted(scene)) << name;
  }
  const Scene placed = shadow::load_scene(kExample / "scene.json");
  EXPECT_EQ(placed.meshes.front().model, "energyplus");
  EXPECT_TRUE(shadow::energyplus_shading_wanted(placed));
  fs::remove_all(dir);
}

TEST(EnergyPlus, ExampleSunFromSiteLocationRunPeriodTimestepAndNorthAxis) {
  const Model m = read_energyplus(kExample / "box-office.idf", "box-office.idf", {});
  ASSERT_TRUE(m.sun);
  EXPECT_EQ(m.sun->site.latitude, 41.98);
  EXPECT_EQ(m.sun->site.longitude, -87.92);
  EXPECT_EQ(m.sun->site.elevation, 201.0);
  EXPECT_EQ(m.sun->utc_offset_hours, -6.0);
  EXPECT_EQ(m.sun->start, "2023-01-01");
  EXPECT_EQ(m.sun->end, "2023-12-31");
  EXPECT_EQ(m.sun->step_minutes, 15);  // Timestep 4
  EXPECT_EQ(m.sun->north_axis, 20.0);
}

TEST(EnergyPlus, WindowsAndDoorAreCutOutOfTheirWallExactly) {
  const Model m = read_energyplus(kExample / "box-office.idf", "box-office.idf", {});
  const auto areas = area_by_name(m);
  // Gross south wall 10 x 3; window 2.5 x 1.5; door 1 x 2.25 (touching the floor line).
  EXPECT_EQ(areas.at("Window-South"), 3.75);
  EXPECT_EQ(areas.at("Door-South"), 2.25);
  EXPECT_EQ(areas.at("Wall-South"), 30.0 - 3.75 - 2.25);
  EXPECT_EQ(areas.at("Wall-South") + areas.at("Window-South") + areas.at("Door-South"), 30.0);
  EXPECT_EQ(areas.at("Window-East"), 3.75);  // the simple Window: 3 x 1.25
  EXPECT_EQ(areas.at("Wall-East"), 24.0 - 3.75);
  // The pieces of the wall face where the wall faces, and the engine's exact areas agree.
  const Scene scene = scene_of(m, dvec3(0.2, -1.0, 0.6));
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  std::map<std::string, double> engine_area;
  for (const auto& l : result.lighting) engine_area[scene.faces[l.face_id].name] += l.area;
  EXPECT_EQ(engine_area.at("Wall-South"), 24.0);
  for (const Face& f : m.faces)
    if (f.name == "Wall-South") {
      const dvec3 n = newell(f.vertices);
      EXPECT_EQ(n.x, 0.0);
      EXPECT_LT(n.y, 0.0);
      EXPECT_EQ(n.z, 0.0);
    }
}

TEST(EnergyPlus, SimpleWindowLiesWhereItsBaseSurfaceCoordinatesSay) {
  const Model m = read_energyplus(kExample / "box-office.idf", "box-office.idf", {});
  for (const Face& f : m.faces) {
    if (f.name == "Window-East")
      EXPECT_EQ(f.vertices, (std::vector<dvec3>{{10, 2.5, 1}, {10, 5.5, 1}, {10, 5.5, 2.25}, {10, 2.5, 2.25}}));
    if (f.name == "Door-South")
      EXPECT_EQ(f.vertices, (std::vector<dvec3>{{6, 0, 0}, {7, 0, 0}, {7, 0, 2.25}, {6, 0, 2.25}}));
  }
}

TEST(EnergyPlus, SiteShadingTurnsIntoBuildingCoordinatesBuildingShadingDoesNot) {
  const Model m = read_energyplus(kExample / "box-office.idf", "box-office.idf", {});
  // Building +y is 20 degrees clockwise from true north: a world point's building coordinates
  // are its components along the building's axes.
  const double a = 20.0 * M_PI / 180.0;
  const dvec3 x_axis(std::cos(a), -std::sin(a), 0.0), y_axis(std::sin(a), std::cos(a), 0.0);
  for (const Face& f : m.faces) {
    if (f.name == "Neighbour-North-Face") {
      const dvec3 world(24, -10, 9);
      EXPECT_NEAR(f.vertices[0].x, glm::dot(world, x_axis), 1e-12);
      EXPECT_NEAR(f.vertices[0].y, glm::dot(world, y_axis), 1e-12);
      EXPECT_EQ(f.vertices[0].z, 9.0);
    }
    if (f.name == "Overhang-South") EXPECT_EQ(f.vertices[1], dvec3(0.5, -0.75, 2.5));
  }
}

// --- Coordinate systems and vertex order ------------------------------------------------------

TEST(EnergyPlus, ClockwiseEntryAndRelativeCoordinatesWithZoneOriginAndNorth) {
  // The zone's +y points east (90 degrees clockwise from the building's +y); its origin is at
  // (5, 10, 0). The wall faces the zone's -y (south in the zone), so the building's -x (west).
  const Model m = idf(
      "GlobalGeometryRules, LowerLeftCorner, Clockwise, Relative;\n"
      "Zone, Z1, 90, 5, 10, 0;\n"
      "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
      "  0, 0, 0,  0, 0, 3,  4, 0, 3,  4, 0, 0;\n");
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0].vertices, (std::vector<dvec3>{{5, 6, 0}, {5, 6, 3}, {5, 10, 3}, {5, 10, 0}}));
  const dvec3 n = newell(m.faces[0].vertices);
  EXPECT_LT(n.x, 0.0);
  EXPECT_EQ(n.y, 0.0);
  EXPECT_EQ(n.z, 0.0);
  EXPECT_EQ(m.meshes[0].name, "Z1");
  EXPECT_FALSE(m.sun);  // no Site:Location
}

// Where the Rectangular Surface Coordinate System differs from the Coordinate System,
// EnergyPlus's MakeRectangularVertices places a simple surface's corner by the rectangular one:
// relative through the zone's origin (and the building's north axis) even with world
// coordinates, world as written even with relative ones; the azimuth turns with the building
// and zone only with relative coordinates. Both came out elsewhere, exit 0.
TEST(EnergyPlus, SimpleSurfacesFollowTheRectangularCoordinateSystem) {
  const Model world = idf("GlobalGeometryRules, UpperLeftCorner, Counterclockwise, World;\n"
                          "Zone, Z1, 0, 20, 10, 0;\n"
                          "Wall:Exterior, South, C, Z1, , 180, 90, 0, 0, 0, 10, 3;\n");
  ASSERT_EQ(world.faces.size(), 1u);
  EXPECT_EQ(world.faces[0].vertices[0], dvec3(20, 10, 0));
  EXPECT_EQ(world.faces[0].vertices[1], dvec3(30, 10, 0));
  const Model fence = idf("Building, B, 30;\n"
                          "GlobalGeometryRules, UpperLeftCorner, Counterclockwise, Relative, Relative, World;\n"
                          "Shading:Building, Fence, 180, 90, 0, -5, 0, 10, 2;\n");
  ASSERT_EQ(fence.faces.size(), 1u);
  // The world corner (0, -5) in the building frame (turned back by the north axis, 30 degrees);
  // the fence still runs along the building's x.
  const std::vector<dvec3>& v = fence.faces[0].vertices;
  EXPECT_NEAR(v[0].x, 2.5, 1e-12);
  EXPECT_NEAR(v[0].y, -5 * std::sqrt(0.75), 1e-12);
  EXPECT_NEAR(v[1].x, 12.5, 1e-12);
  EXPECT_NEAR(v[1].y, -5 * std::sqrt(0.75), 1e-12);
}

// ASHRAE 90.1 Appendix G baselines are rotated by Compliance:Building: EnergyPlus turns every
// vertex by it, after the north axis, and in world coordinates by it alone. It was not read: a
// rotated baseline came out shaded as the unrotated one, without a word. A Timestep object with
// its field blank is the field's default, 6 steps an hour.
TEST(EnergyPlus, AppendixGRotationTurnsTheBuilding) {
  const std::string rest =
      "Zone, Z1;\n"
      "Site:Location, Somewhere, 45, 7, 1, 200;\n"
      "Timestep, ;\n"
      "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
      "  0, 0, 3,  0, 0, 0,  4, 0, 0,  4, 0, 3;\n";
  const Model relative = idf("Building, B, 30;\nCompliance:Building, 90;\n" + rest);
  ASSERT_TRUE(relative.sun);
  EXPECT_EQ(relative.sun->north_axis, 120.0);
  EXPECT_EQ(relative.sun->step_minutes, 10);
  // Daylight saving time: EnergyPlus reads every schedule an hour later while it is on, the
  // imported shading file too (ScheduleManager.cc, LookUpScheduleValue): said, not silent.
  const Model dst = idf(rest + "RunPeriodControl:DaylightSavingTime, 2nd Sunday in March, 1st Sunday in November;\n");
  bool warned = false;
  for (const auto& w : dst.warnings) warned = warned || w.message.find("one hour later") != std::string::npos;
  EXPECT_TRUE(warned);
  const Model world = idf("GlobalGeometryRules, UpperLeftCorner, Counterclockwise, World;\n"
                          "Building, B, 30;\nCompliance:Building, 90;\n" + rest);
  ASSERT_TRUE(world.sun);
  EXPECT_EQ(world.sun->north_axis, 90.0);
  EXPECT_EQ(world.faces[0].vertices[0], dvec3(0, 0, 3));  // drawn as written; the sun turns
  // Site shading is the one thing EnergyPlus does not turn in world coordinates: turned back here
  // (it stayed with the building, west of it instead of south).
  const Model site = idf("GlobalGeometryRules, UpperLeftCorner, Counterclockwise, World;\n"
                         "Compliance:Building, 90;\n" + rest +
                         "Shading:Site:Detailed, Fence, , 4,  0, -5, 2,  0, -5, 0,  4, -5, 0,  4, -5, 2;\n");
  for (const auto& f : site.faces)
    if (f.name == "Fence") {
      EXPECT_NEAR(f.vertices[0].x, 5.0, 1e-12);
      EXPECT_NEAR(f.vertices[0].y, 0.0, 1e-12);
    }
}

TEST(EnergyPlus, WorldCoordinatesIgnoreZoneOriginAndNorthAxisWithAWarning) {
  const Model m = idf(
      "GlobalGeometryRules, UpperLeftCorner, Counterclockwise, World;\n"
      "Building, B, 30;\n"
      "Zone, Z1, 90, 5, 10, 0;\n"
      "Site:Location, Somewhere, 45, 7, 1, 200;\n"
      "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
      "  0, 0, 3,  0, 0, 0,  4, 0, 0,  4, 0, 3;\n");
  EXPECT_EQ(m.faces[0].vertices[0], dvec3(0, 0, 3));
  ASSERT_TRUE(m.sun);
  EXPECT_EQ(m.sun->north_axis, 0.0);
  EXPECT_EQ(m.sun->step_minutes, 15);  // no Timestep: EnergyPlus takes 4 per hour
  EXPECT_EQ(m.sun->start, "2023-01-01");
  ASSERT_FALSE(m.warnings.empty());
  bool ignored = false;
  for (const auto& w : m.warnings) ignored = ignored || w.message.find("ignored") != std::string::npos;
  EXPECT_TRUE(ignored);
}

TEST(EnergyPlus, RunPeriodAcrossNewYearAndInterzoneSurfacesLeftOut) {
  const Model m = idf(std::string(kHeader) +
                      "Site:Location, S, 10, 20, 2, 0;\n"
                      "RunPeriod, Winter, 11, 1, , 2, 28, ;\n"
                      "Timestep, 2;\n"
                      "BuildingSurface:Detailed, Partition, Wall, C, Z1, , Surface, Partition, NoSun, NoWind, , 3,\n"
                      "  0, 0, 1,  0, 0, 0,  1, 0, 0;\n"
                      "BuildingSurface:Detailed, Out, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 3,\n"
                      "  0, 0, 1,  0, 0, 0,  1, 0, 0;\n"
                      "InternalMass, Mass, C, Z1, 20;\n"
                      "Shading:Site:Detailed, Tree, Leaves, 3, 5,5,0, 6,5,0, 6,5,4;\n");
  ASSERT_EQ(m.faces.size(), 2u);
  EXPECT_EQ(m.faces[0].name, "Out");
  EXPECT_EQ(m.faces[1].name, "Tree");
  EXPECT_EQ(m.sun->start, "2023-11-01");
  EXPECT_EQ(m.sun->end, "2024-02-28");
  EXPECT_EQ(m.sun->step_minutes, 30);
  EXPECT_EQ(m.sun->utc_offset_hours, 2.0);
  bool named = false;  // an unsupported geometry class is reported, not silently lost
  for (const auto& w : m.warnings) named = named || w.message.find("InternalMass") != std::string::npos;
  EXPECT_TRUE(named);
  bool opaque = false;  // shading is opaque: a transmittance schedule is not applied, and said so
  for (const auto& w : m.warnings)
    opaque = opaque || (w.message.find("\"Leaves\" not applied") != std::string::npos &&
                        w.where.place.find("field \"Transmittance Schedule Name\"") != std::string::npos);
  EXPECT_TRUE(opaque);
}

TEST(EnergyPlus, SimpleRectangularSurfacesMatchTheirDetailedTwins) {
  // Zone +y points east, origin (5, 10, 0): a Wall:Exterior facing the zone's south is the wall of
  // ClockwiseEntryAndRelativeCoordinatesWithZoneOriginAndNorth; a Roof and a Floor:GroundContact
  // of 4 x 2 face up and down; a Wall:Interzone is left out.
  const Model m = idf(
      "Zone, Z1, 90, 5, 10, 0;\n"
      "Wall:Exterior, W, C, Z1, , 180, 90, 0, 0, 0, 4, 3;\n"
      "Roof, R, C, Z1, , 180, 0, 0, 0, 3, 4, 2;\n"
      "Floor:GroundContact, F, C, Z1, , 180, 180, 0, 2, 0, 4, 2;\n"
      "Wall:Interzone, I, C, Z1, , Other, 0, 90, 0, 2, 0, 4, 3;\n");
  ASSERT_EQ(m.faces.size(), 3u);
  EXPECT_EQ(m.faces[0].name, "W");
  EXPECT_EQ(m.faces[0].kind, "Wall");
  EXPECT_EQ(m.faces[0].vertices, (std::vector<dvec3>{{5, 10, 0}, {5, 6, 0}, {5, 6, 3}, {5, 10, 3}}));
  EXPECT_EQ(m.faces[1].kind, "Roof");
  EXPECT_EQ(newell(m.faces[1].vertices), dvec3(0, 0, 16));  // 4 x 2, facing up
  EXPECT_EQ(m.faces[2].kind, "Floor");
  EXPECT_EQ(m.meshes[m.faces[2].mesh].name, "Not exposed");
  EXPECT_EQ(newell(m.faces[2].vertices), dvec3(0, 0, -16));  // facing down
  for (const Face& f : m.faces) EXPECT_NE(f.name, "I");
  // A Window on the simple wall, in the wall's own coordinates.
  const Model w = idf(
      "Zone, Z1;\n"
      "Wall:Exterior, W, C, Z1, , 180, 90, 0, 0, 0, 4, 3;\n"
      "Window, G, C, W, , 1, 1, 0.5, 2, 1.5;\n");
  EXPECT_EQ(area_by_name(w).at("W"), 12.0 - 3.0);
  EXPECT_EQ(w.faces.back().vertices, (std::vector<dvec3>{{1, 0, 0.5}, {3, 0, 0.5}, {3, 0, 2}, {1, 0, 2}}));
}

// --- The same building as OBJ and as IDF ------------------------------------------------------

TEST(EnergyPlus, RoundTripWithObjGivesTheSameAreasUnderALight) {
  // A 4 x 4 x 3 box with an overhang and a neighbouring wall; in the IDF the zone sits at
  // (2, 1, 0) and vertices run clockwise, so every coordinate goes through the reader's frames.
  const Model m = idf(
      "GlobalGeometryRules, UpperLeftCorner, Clockwise, Relative;\n"
      "Zone, Z, 0, 2, 1, 0;\n"
      "BuildingSurface:Detailed, S, Wall, C, Z, , Outdoors, , SunExposed, WindExposed, , 4,\n"
      "  0,0,3, 4,0,3, 4,0,0, 0,0,0;\n"
      "BuildingSurface:Detailed, E, Wall, C, Z, , Outdoors, , SunExposed, WindExposed, , 4,\n"
      "  4,0,3, 4,4,3, 4,4,0, 4,0,0;\n"
      "BuildingSurface:Detailed, R, Roof, C, Z, , Outdoors, , SunExposed, WindExposed, , 4,\n"
      "  0,4,3, 4,4,3, 4,0,3, 0,0,3;\n"
      "Shading:Zone:Detailed, O, S, , 4,  0,0,2.5, 4,0,2.5, 4,-1,2.5, 0,-1,2.5;\n"
      "Shading:Site:Detailed, N, , 4,  8,-3,5, 8,-3,0, 0,-3,0, 0,-3,5;\n");
  const std::string obj =
      "v 2 1 3\nv 2 1 0\nv 6 1 0\nv 6 1 3\nf 1 2 3 4\n"        // S, counter-clockwise from outside
      "v 6 1 3\nv 6 1 0\nv 6 5 0\nv 6 5 3\nf 5 6 7 8\n"        // E
      "v 2 1 3\nv 6 1 3\nv 6 5 3\nv 2 5 3\nf 9 10 11 12\n"     // R
      "v 2 0 2.5\nv 6 0 2.5\nv 6 1 2.5\nv 2 1 2.5\nf 13 14 15 16\n"  // O
      "v 0 -3 5\nv 0 -3 0\nv 8 -3 0\nv 8 -3 5\nf 17 18 19 20\n";      // N
  const auto polygons = shadow::parse_obj(obj, "same.obj");
  Model from_obj;
  from_obj.meshes = m.meshes;
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    Face face;
    face.vertices = polygons[f];
    face.mesh = m.faces[f].mesh;
    from_obj.faces.push_back(face);
  }
  const dvec3 to_light(0.35, -0.9, 1.6);
  const Scene a = scene_of(m, to_light), b = scene_of(from_obj, to_light);
  const auto ra = shadow::compute_shadows(a), rb = shadow::compute_shadows(b);
  ASSERT_EQ(ra.lighting.size(), 3u);  // the three zone surfaces receive
  ASSERT_EQ(ra.lighting.size(), rb.lighting.size());
  for (std::size_t i = 0; i < ra.lighting.size(); ++i) {
    EXPECT_EQ(ra.lighting[i].face_id, rb.lighting[i].face_id);
    EXPECT_EQ(ra.lighting[i].area, rb.lighting[i].area);
    EXPECT_EQ(ra.lighting[i].lit_area, rb.lighting[i].lit_area);
  }
  // The overhang shades the south wall: not all of it is lit, and the light reaches it.
  EXPECT_GT(ra.lighting[0].lit_area, 0.0);
  EXPECT_LT(ra.lighting[0].lit_area, 12.0);
}

// --- Errors -------------------------------------------------------------------------------------

TEST(EnergyPlus, NonNumberNamesLineObjectAndField) {
  EXPECT_TRUE(ThrowsInputError(
      [] {
        idf(std::string(kHeader) +
            "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
            "  0, 0, 3,\n"
            "  0, 0, zero,\n"
            "  4, 0, 0,  4, 0, 3;\n");
      },
      {"m.idf: line 6, BuildingSurface:Detailed \"W\" field \"Vertex 2 Z-coordinate\"", "not a number: \"zero\""}));
}

TEST(EnergyPlus, VertexCountMismatch) {
  EXPECT_TRUE(ThrowsInputError(
      [] {
        idf(std::string(kHeader) +
            "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 5,\n"
            "  0, 0, 3,  0, 0, 0,  4, 0, 0,  4, 0, 3;\n");
      },
      {"line 4, BuildingSurface:Detailed \"W\" field \"Number of Vertices\"", "says 5 vertices, but 4 are given"}));
  EXPECT_TRUE(ThrowsInputError(
      [] {
        idf(std::string(kHeader) +
            "Shading:Site:Detailed, S, , ,\n  0, 0, 3,  0, 0, 0,  4, 0;\n");
      },
      {"line 5, Shading:Site:Detailed \"S\" field \"Vertex 3 Z-coordinate\"", "vertex 3 has only 2 of its 3 coordinates"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { idf(std::string(kHeader) + "Shading:Site:Detailed, S, , 1e150, 0,0,0, 1,0,0, 0,1,0;\n"); },
      {"line 4, Shading:Site:Detailed \"S\" field \"Number of Vertices\"", "says 1e+150 vertices, but 3 are given"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { idf(std::string(kHeader) + "Shading:Site:Detailed, S, , 2,\n  0, 0, 3,  0, 0, 0;\n"); },
      {"line 4, Shading:Site:Detailed \"S\"", "at least 3 vertices, 2 given"}));
}

const std::string kWall =
    std::string(kHeader) +
    "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
    "  0, 0, 3,  0, 0, 0,  4, 0, 0,  4, 0, 3;\n";

// A simple Window is measured from its base surface's Vertex(2) as EnergyPlus orders the
// vertices (MakeRelativeRectangularVertices), along the base's azimuth; a flat roof's azimuth
// comes from its edge Vertex(2) -> Vertex(3). The corner of the bounding rectangle and the
// model's +x put a window on a wall wider at the top, and a skylight, elsewhere (exit 0).
TEST(EnergyPlus, SimpleWindowsStartFromEnergyPlusVertexTwo) {
  const Model gable = idf(std::string(kHeader) +
                          "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
                          "  -1, 0, 3,  0, 0, 0,  10, 0, 0,  11, 0, 3;\n"
                          "Window, Win, C, W, , 1, 1, 1, 2, 1.5;\n");
  const Model roof = idf(std::string(kHeader) +
                         "BuildingSurface:Detailed, R, Roof, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
                         "  10, 0, 3,  10, 8, 3,  0, 8, 3,  0, 0, 3;\n"
                         "Window, Sky, C, R, , 1, 1, 1, 2, 1;\n");
  // Declared from the lower left corner: the first vertex is Vertex(2).
  const Model lower_left = idf(std::string("Version, 24.1;\nGlobalGeometryRules, LowerLeftCorner, Counterclockwise, "
                                           "Relative;\nZone, Z1;\n") +
                               "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
                               "  0, 0, 0,  10, 0, 0,  11, 0, 3,  -1, 0, 3;\n"
                               "Window, Win, C, W, , 1, 1, 1, 2, 1.5;\n");
  const auto window = [](const Model& m, const std::string& name) {
    for (const Face& f : m.faces)
      if (f.name == name) return f.vertices;
    return std::vector<dvec3>{};
  };
  EXPECT_EQ(window(gable, "Win"), (std::vector<dvec3>{{1, 0, 1}, {3, 0, 1}, {3, 0, 2.5}, {1, 0, 2.5}}));
  EXPECT_EQ(window(lower_left, "Win"), (std::vector<dvec3>{{1, 0, 1}, {3, 0, 1}, {3, 0, 2.5}, {1, 0, 2.5}}));
  EXPECT_EQ(window(roof, "Sky"), (std::vector<dvec3>{{9, 7, 3}, {7, 7, 3}, {7, 6, 3}, {9, 6, 3}}));
  // A roof 5e-9 radians off horizontal is horizontal to EnergyPlus (its unit normal's z rounds
  // to 1): the skylight's axes still come from the edge (they came from the normal's azimuth
  // above 1e-9, turning the skylight about the roof); at 1e-7 radians from the normal's.
  const auto tilted_roof = [](const std::string& dz) {
    return idf(std::string(kHeader) +
               "BuildingSurface:Detailed, R, Roof, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
               "  10, 0, 3,  10, 8, 3" + dz + ",  0, 8, 3" + dz + ",  0, 0, 3;\n"
               "Window, Sky, C, R, , 1, 1, 1, 2, 1;\n");
  };
  const std::vector<dvec3> nearly = window(tilted_roof(".00000004"), "Sky");
  const std::vector<dvec3> flat_sky = window(roof, "Sky");
  ASSERT_EQ(nearly.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_LT(glm::length(nearly[k] - flat_sky[k]), 1e-6) << k;
  // (Its x axis then runs east from Vertex(2), the north-east corner: the skylight leaves the roof.)
  EXPECT_TRUE(ThrowsInputError([&] { tilted_roof(".0000008"); }, {"Window \"Sky\"", "not inside its base surface"}));
  // An overhang on a window entered from another corner than the one declared: sized as
  // EnergyPlus sizes it (Width |V3 - V2|, Height |V2 - V1|), not refused as a zero-width shade.
  const Model odd = idf(kWall + "FenestrationSurface:Detailed, Win, Window, G, W, , , , 1, 4,\n"
                                "  1,0,1, 3,0,1, 3,0,2, 1,0,2;\n"
                                "Shading:Overhang, O, Win, 0.5, 90, 0, 0, 1;\n");
  const std::vector<dvec3> overhang = window(odd, "O");
  ASSERT_EQ(overhang.size(), 4u);
  EXPECT_EQ(overhang[0], dvec3(3, 0, 3.5));
  EXPECT_EQ(overhang[1], dvec3(4, 0, 3.5));
}

TEST(EnergyPlus, WindowOutsideItsWallOffItsPlaneOrOverlapping) {
  auto window = [](const std::string& name, const std::string& vertices) {
    return "FenestrationSurface:Detailed, " + name + ", Window, G, W, , , , 1, 4,\n  " + vertices + ";\n";
  };
  EXPECT_TRUE(ThrowsInputError([&] { idf(kWall + window("Win", "3,0,2, 3,0,1, 5,0,1, 5,0,2")); },
                               {"m.idf: line 6, FenestrationSurface:Detailed \"Win\"",
                                "not inside its base surface \"W\""}));
  // Off the plane and not parallel to it: no window in a reveal either (those are below).
  EXPECT_TRUE(ThrowsInputError([&] { idf(kWall + window("Win", "1,0.5,2, 1,0.5,1, 2,0.6,1, 2,0.6,2")); },
                               {"line 6, FenestrationSurface:Detailed \"Win\"", "not in the plane of its base surface",
                                "not parallel to it"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] { idf(kWall + window("A", "1,0,2, 1,0,1, 2,0,1, 2,0,2") + window("B", "1.5,0,2, 1.5,0,1, 3,0,1, 3,0,2")); },
      {"FenestrationSurface:Detailed \"B\"", "overlaps \"A\""}));
  EXPECT_TRUE(ThrowsInputError([&] { idf(kWall + window("Win", "1,0,2, 2,0,2, 2,0,1, 1,0,1")); },
                               {"FenestrationSurface:Detailed \"Win\"", "faces the other way"}));
  EXPECT_TRUE(ThrowsInputError(
      [&] {
        idf(kWall + "FenestrationSurface:Detailed, Win, Window, G, Nowhere, , , , 1, 3,\n  1,0,2, 1,0,1, 2,0,1;\n");
      },
      {"line 6, FenestrationSurface:Detailed \"Win\" field \"Building Surface Name\"",
       "no base surface named \"Nowhere\""}));
  // Sticking out by a rounding error (1e-9 of a 4 m wall, under the 1e-6 tolerance): taken as
  // rounding, with a warning; by 1 mm it is an error.
  const Model r = idf(kWall + window("Win", "3,0,2, 3,0,1, 4.000000001,0,1, 4.000000001,0,2"));
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].message.find("taken as rounding"), std::string::npos);
  EXPECT_NEAR(area_by_name(r).at("W"), 11.0, 1e-12);
  EXPECT_TRUE(ThrowsInputError([&] { idf(kWall + window("Win", "3,0,2, 3,0,1, 4.001,0,1, 4.001,0,2")); },
                               {"FenestrationSurface:Detailed \"Win\"", "not inside its base surface \"W\""}));
  // Side by side and on the wall's edge: allowed, and still exact.
  const Model m = idf(kWall + window("A", "1,0,2, 1,0,1, 2,0,1, 2,0,2") + window("B", "2,0,2, 2,0,0, 4,0,0, 4,0,2"));
  const auto areas = area_by_name(m);
  EXPECT_EQ(areas.at("W"), 12.0 - 1.0 - 4.0);
}

// --- Windows in reveals -------------------------------------------------------------------------

// A window w x h = 2 x 1 in the 4 x 3 south wall (outward normal -y), set back by d = 0.25
// behind the wall's plane, as EnergyPlus's SolarShadingTest.idf sets its windows back.
std::string set_back_window(double depth) {
  const std::string y = std::to_string(depth);
  return "FenestrationSurface:Detailed, Win, Window, G, W, , , , 1, 4,\n  1," + y + ",2, 1," + y + ",1, 3," + y +
         ",1, 3," + y + ",2;\n";
}

TEST(EnergyPlus, WindowSetBackFromItsWallSitsInAReveal) {
  const Model m = idf(kWall + set_back_window(0.25));
  // The wall loses the opening (cut in its own plane), the window keeps its depth, and the reveal's
  // four sides (perimeter 6 x depth 0.25) are building shading named after the window.
  const auto areas = area_by_name(m);
  EXPECT_EQ(areas.at("W"), 12.0 - 2.0);
  EXPECT_EQ(areas.at("Win"), 2.0);
  double reveal = 0.0;
  int sides = 0;
  for (const Face& f : m.faces) {
    if (f.name == "Win")
      for (const dvec3& p : f.vertices) EXPECT_EQ(p.y, 0.25);
    if (f.name == "W")
      for (const dvec3& p : f.vertices) EXPECT_EQ(p.y, 0.0);
    if (f.name.rfind("Win:Reveal:", 0) == 0) {
      ++sides;
      reveal += area(f.vertices);
      EXPECT_EQ(f.kind, "Shading");
      EXPECT_EQ(m.meshes[f.mesh].name, "Shading:Building");
      EXPECT_FALSE(m.meshes[f.mesh].receiver);
      EXPECT_NE(f.source.place.find("FenestrationSurface:Detailed \"Win\""), std::string::npos);
    }
  }
  EXPECT_EQ(sides, 4);
  EXPECT_EQ(areas.count("Win:Reveal:4"), 1u);
  EXPECT_EQ(reveal, 6.0 * 0.25);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].message.find("1 window or door (first \"Win\") set back from the plane of their base "
                                       "surface by 0.25 m"),
            std::string::npos)
      << m.warnings[0].message;

  // The reveal's shade, exactly: a sun with to_light (a, -1, c) reaches the window at depth d
  // through the opening shifted by (d a, d c), so the lit part is (w - d|a|) x (h - d|c|) =
  // (w - d |tan(azimuth difference)|) x (h - d tan(profile angle)).
  for (const dvec3& to_light : {dvec3(0.5, -1.0, 1.0), dvec3(-1.5, -1.0, 0.5), dvec3(0.0, -1.0, 2.0)}) {
    const Scene scene = scene_of(m, to_light);
    const shadow::ShadowResult result = shadow::compute_shadows(scene);
    std::map<std::string, double> lit;
    for (const auto& l : result.lighting) lit[scene.faces[l.face_id].name] += l.lit_area;
    const double expected = (2.0 - 0.25 * std::abs(to_light.x)) * (1.0 - 0.25 * std::abs(to_light.z));
    EXPECT_EQ(lit.at("Win"), expected) << to_light.x << " " << to_light.z;
    EXPECT_EQ(lit.at("W"), 10.0);  // nothing shades the wall; the reveal lies behind it
  }
}

TEST(EnergyPlus, WindowProudOfItsWallTooDeepOrSkew) {
  // In front of the wall (outside) by 0.1: put into the wall's plane, with a warning.
  const Model proud = idf(kWall + set_back_window(-0.1));
  for (const Face& f : proud.faces) {
    EXPECT_EQ(f.name.find(":Reveal:"), std::string::npos);
    if (f.name == "Win")
      for (const dvec3& p : f.vertices) EXPECT_EQ(p.y, 0.0);
  }
  EXPECT_EQ(area_by_name(proud).at("W"), 10.0);
  ASSERT_EQ(proud.warnings.size(), 1u);
  EXPECT_NE(proud.warnings[0].message.find("in front of the plane of their base surface by 0.1 m: put into that plane"),
            std::string::npos)
      << proud.warnings[0].message;
  // Deeper than any wall: an error that names the limit.
  EXPECT_TRUE(ThrowsInputError([&] { idf(kWall + set_back_window(1.5)); },
                               {"line 6, FenestrationSurface:Detailed \"Win\"",
                                "not in the plane of its base surface \"W\": it lies 1.5 behind it, more than the "
                                "deepest reveal read (1 m; docs/energyplus.md)"}));
  EXPECT_TRUE(ThrowsInputError([&] { idf(kWall + set_back_window(-2.0)); }, {"lies 2 in front of it"}));
}

// --- Results back into EnergyPlus ---------------------------------------------------------------

/// The test's own temporary directory, removed when the test program ends.
struct TempFiles {
  fs::path dir = fs::temp_directory_path() / ("libshadow_test_energyplus_" + std::to_string(::getpid()));
  ~TempFiles() {
    std::error_code ignored;
    fs::remove_all(dir, ignored);
  }
};

/// A file in the test's own temporary directory.
fs::path temp_file(const std::string& name, const std::string& text) {
  static const TempFiles files;
  const fs::path& dir = files.dir;
  fs::create_directories(dir);
  const fs::path file = dir / name;
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

std::vector<shadow::scene_readers::IdfObject> objects_of_class(const std::string& text, const std::string& cls) {
  std::vector<shadow::scene_readers::IdfObject> out;
  for (auto& o : shadow::scene_readers::tokenize_idf(text, "copy.idf"))
    if (o.fields[0].text == cls) out.push_back(o);
  return out;
}

TEST(EnergyPlus, ImportObjectsNameTheCsvAndImportedShading) {
  const std::string objects = shadow::energyplus_import_objects("/runs/out/energyplus-shading.csv");
  const auto calc = objects_of_class(objects, "ShadowCalculation");
  ASSERT_EQ(calc.size(), 1u);
  // EnergyPlus 9.6's field order: method, update frequency method, frequency, figures,
  // clipping, pixels, sky diffuse, output external results.
  std::vector<std::string> fields;
  for (std::size_t i = 1; i < calc[0].fields.size(); ++i) fields.push_back(calc[0].fields[i].text);
  EXPECT_EQ(fields, (std::vector<std::string>{"Imported", "Timestep", "1", "15000", "SutherlandHodgman", "512",
                                              "SimpleSkyDiffuseModeling", "No"}));
  const auto schedule = objects_of_class(objects, "Schedule:File:Shading");
  ASSERT_EQ(schedule.size(), 1u);
  ASSERT_EQ(schedule[0].fields.size(), 2u);
  EXPECT_EQ(schedule[0].fields[1].text, "/runs/out/energyplus-shading.csv");
  EXPECT_NE(objects.find("!- Shading Calculation Method"), std::string::npos);
  // A path an IDF field cannot hold is refused, not written broken.
  EXPECT_TRUE(ThrowsInputError([] { shadow::energyplus_import_objects("/runs/a,b/energyplus-shading.csv"); },
                               {"cannot hold ','"}));
}

TEST(EnergyPlus, ModelCopyImportsTheCsvAndReReadsToTheSameFaces) {
  const std::string model = std::string("Version, 9.6;\n") +
                            "GlobalGeometryRules, UpperLeftCorner, Counterclockwise, Relative;\nZone, Z1;\n"
                            "BuildingSurface:Detailed, W, Wall, C, Z1, , Outdoors, , SunExposed, WindExposed, , 4,\n"
                            "  0, 0, 3,  0, 0, 0,  4, 0, 0,  4, 0, 3;\n"
                            "ShadowCalculation,\n  PolygonClipping,  !- Shading Calculation Method\n"
                            "  Periodic,         !- Shading Calculation Update Frequency Method\n"
                            "  20;               !- Shading Calculation Update Frequency\n" +
                            set_back_window(0.152) + "Output:Variable, *, Surface Outside Face Sunlit Fraction, Hourly;\n";
  const fs::path file = temp_file("model.idf", model);
  const shadow::EnergyPlusImportCopy copy = shadow::energyplus_model_importing_shading(file, "/runs/out/energyplus-shading.csv");
  EXPECT_FALSE(copy.epjson);
  EXPECT_EQ(copy.version, "9.6");
  EXPECT_EQ(copy.version_code, 906);  // as the reader picks its field lists
  EXPECT_EQ(copy.replaced, 1);
  // The model's own ShadowCalculation is gone, with its comments; the new pair took its place.
  const auto calc = objects_of_class(copy.text, "ShadowCalculation");
  ASSERT_EQ(calc.size(), 1u);
  EXPECT_EQ(calc[0].fields[1].text, "Imported");
  EXPECT_EQ(copy.text.find("PolygonClipping"), std::string::npos);
  EXPECT_LT(copy.text.find("Schedule:File:Shading"), copy.text.find("FenestrationSurface:Detailed"));
  EXPECT_NE(copy.text.find("Output:Variable, *, Surface Outside Face Sunlit Fraction, Hourly;"), std::string::npos);
  // Everything else is the model, byte for byte: the same faces when read again.
  const Model a = idf(model), b = idf(copy.text);
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t f = 0; f < a.faces.size(); ++f) {
    EXPECT_EQ(a.faces[f].name, b.faces[f].name);
    EXPECT_EQ(a.faces[f].vertices, b.faces[f].vertices);
  }
  // Without one, the objects are added at the end; the copy of the copy replaces both.
  const shadow::EnergyPlusImportCopy plain =
      shadow::energyplus_model_importing_shading(temp_file("plain.idf", kWall), "/x/energyplus-shading.csv");
  EXPECT_EQ(plain.replaced, 0);
  EXPECT_EQ(plain.text.rfind(kWall, 0), 0u);
  EXPECT_EQ(idf(plain.text).faces.size(), idf(kWall).faces.size());
  const shadow::EnergyPlusImportCopy again =
      shadow::energyplus_model_importing_shading(temp_file("again.idf", plain.text), "/y/energyplus-shading.csv");
  EXPECT_EQ(again.replaced, 2);
  EXPECT_EQ(objects_of_class(again.text, "ShadowCalculation").size(), 1u);
  const auto schedule = objects_of_class(again.text, "Schedule:File:Shading");
  ASSERT_EQ(schedule.size(), 1u);
  EXPECT_EQ(schedule[0].fields[1].text, "/y/energyplus-shading.csv");
}

// One reading of a version identifier for the reader's field lists and the copy's version_code.
TEST(EnergyPlus, VersionCodeIsMajorTimesHundredPlusMinor) {
  using shadow::scene_readers::energyplus_version_code;
  EXPECT_EQ(energyplus_version_code("9.6"), 906);
  EXPECT_EQ(energyplus_version_code("24.1.0"), 2401);
  EXPECT_EQ(energyplus_version_code("9"), 900);
  EXPECT_EQ(energyplus_version_code("8.150"), 800);  // a minor beyond 99 is no minor
  EXPECT_EQ(energyplus_version_code(""), 0);
  EXPECT_EQ(energyplus_version_code("v9.6"), 0);
  EXPECT_EQ(energyplus_version_code("1000.1"), 0);
  EXPECT_EQ(energyplus_version_code("9.6.0.1"), 0);
}

TEST(EnergyPlus, EpJsonModelCopyGetsEpJsonObjects) {
  const fs::path source = kExample / "box-office.epJSON";
  const shadow::EnergyPlusImportCopy copy = shadow::energyplus_model_importing_shading(source, "/o/energyplus-shading.csv");
  EXPECT_TRUE(copy.epjson);
  const Model a = read_energyplus(source, "a.epJSON", {});
  const Model b = parse_energyplus(copy.text, "b.epJSON", true);
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t f = 0; f < a.faces.size(); ++f) EXPECT_EQ(a.faces[f].vertices, b.faces[f].vertices);
  EXPECT_NE(copy.text.find("\"shading_calculation_method\": \"Imported\""), std::string::npos);
  EXPECT_NE(copy.text.find("\"file_name\": \"/o/energyplus-shading.csv\""), std::string::npos);
  // Not a model: refused.
  EXPECT_TRUE(ThrowsInputError(
      [] { shadow::energyplus_model_importing_shading(kExample / "scene.json", "/o/energyplus-shading.csv"); },
      {"not an EnergyPlus model"}));
  EXPECT_TRUE(shadow::is_energyplus_model(source));
  EXPECT_FALSE(shadow::is_energyplus_model(kExample / "scene.json"));
}

TEST(EnergyPlus, OverhangsAndFinsAreDrawnFromTheirWindow) {
  // Window 2 x 1 at x 1..3, z 1..2 in a south wall; shades square to it (the default 90).
  const Model m = idf(kWall + "FenestrationSurface:Detailed, Win, Window, G, W, , , , 1, 4,\n"
                              "  1,0,2, 1,0,1, 3,0,1, 3,0,2;\n"
                              "Shading:Overhang, O, Win, 0.5, 90, 0.25, 0.5, 1;\n"
                              "Shading:Overhang:Projection, P, Win, 0.25, , 0, 0, 0.5;\n"
                              "Shading:Fin, F, Win, 0.25, 0.25, 0.5, 90, 0.5, 0.25, 0, 0, 90, 1;\n");
  std::map<std::string, std::vector<dvec3>> shade;
  for (const Face& f : m.faces)
    if (f.kind == "Shading") {
      EXPECT_EQ(m.meshes[f.mesh].name, "Shading:Building");
      shade[f.name] = f.vertices;
    }
  ASSERT_EQ(shade.size(), 4u);
  EXPECT_EQ(shade.at("O"), (std::vector<dvec3>{{0.75, 0, 2.5}, {3.5, 0, 2.5}, {3.5, -1, 2.5}, {0.75, -1, 2.5}}));
  // Depth as a fraction of the window's height (1 m).
  EXPECT_EQ(shade.at("P"), (std::vector<dvec3>{{1, 0, 2.25}, {3, 0, 2.25}, {3, -0.5, 2.25}, {1, -0.5, 2.25}}));
  EXPECT_EQ(shade.at("F Left"), (std::vector<dvec3>{{0.75, 0, 0.5}, {0.75, 0, 2.25}, {0.75, -0.5, 2.25}, {0.75, -0.5, 0.5}}));
  EXPECT_EQ(shade.at("F Right"), (std::vector<dvec3>{{3.25, 0, 1}, {3.25, 0, 2}, {3.25, -1, 2}, {3.25, -1, 1}}));
  // Tilted 45 degrees: EnergyPlus gives both fins the azimuth window - (180 - tilt), so both
  // turn toward the window's right: the left fin leans over the window (it leaned away).
  const Model tilted = idf(kWall + "FenestrationSurface:Detailed, Win, Window, G, W, , , , 1, 4,\n"
                                   "  1,0,2, 1,0,1, 3,0,1, 3,0,2;\n"
                                   "Shading:Fin, T, Win, 0, 0, 0, 45, 1, 0, 0, 0, 45, 1;\n");
  std::map<std::string, std::vector<dvec3>> fin;
  for (const Face& f : tilted.faces)
    if (f.kind == "Shading") fin[f.name] = f.vertices;
  ASSERT_EQ(fin.size(), 2u);
  const double h = std::sqrt(0.5);
  for (const auto& [name, x] : std::map<std::string, double>{{"T Left", 1.0}, {"T Right", 3.0}}) {
    const std::vector<dvec3>& v = fin.at(name);
    ASSERT_EQ(v.size(), 4u) << name;
    EXPECT_EQ(v[0], dvec3(x, 0, 1)) << name;
    EXPECT_NEAR(v[2].x, x + h, 1e-12) << name;
    EXPECT_NEAR(v[2].y, -h, 1e-12) << name;
  }
  EXPECT_TRUE(ThrowsInputError([&] { idf(kWall + "Shading:Overhang, O, Nowhere, 0.5, 90, 0, 0, 1;\n"); },
                               {"line 6, Shading:Overhang \"O\" field \"Window or Door Name\"",
                                "no window or door named \"Nowhere\""}));
}

TEST(EnergyPlus, UnterminatedObjectDuplicateNamesAndUnknownZone) {
  EXPECT_TRUE(ThrowsInputError(
      [] { idf(std::string(kHeader) + "Shading:Site:Detailed, S, , 3,\n  0,0,0, 1,0,0, 1,0,1\n"); },
      {"m.idf: line 4", "Shading:Site:Detailed is not terminated by ';'"}));
  EXPECT_TRUE(ThrowsInputError(
      [] {
        idf(std::string(kHeader) + "Shading:Site:Detailed, Fence, , 3, 0,0,0, 1,0,0, 1,0,1;\n" +
            "Shading:Building:Detailed, FENCE, , 3, 0,0,0, 1,0,0, 1,0,1;\n");
      },
      {"line 5, Shading:Building:Detailed \"FENCE\"", "a second surface named \"FENCE\"", "differs from \"Fence\"",
       "line 4", "only by case", "EnergyPlus upper-cases names"}));
  // The same in epJSON, where the two are different keys of one class.
  EXPECT_TRUE(ThrowsInputError(
      [] {
        parse_energyplus(R"({"Shading:Site:Detailed": {
            "wall1": {"number_of_vertices": 3, "vertices": [
              {"vertex_x_coordinate": 0, "vertex_y_coordinate": 0, "vertex_z_coordinate": 0},
              {"vertex_x_coordinate": 1, "vertex_y_coordinate": 0, "vertex_z_coordinate": 0},
              {"vertex_x_coordinate": 1, "vertex_y_coordinate": 0, "vertex_z_coordinate": 1}]},
            "Wall1": {"number_of_vertices": 3, "vertices": [
              {"vertex_x_coordinate": 0, "vertex_y_coordinate": 1, "vertex_z_coordinate": 0},
              {"vertex_x_coordinate": 1, "vertex_y_coordinate": 1, "vertex_z_coordinate": 0},
              {"vertex_x_coordinate": 1, "vertex_y_coordinate": 1, "vertex_z_coordinate": 1}]}}})",
                         "m.epJSON", true);
      },
      {"m.epJSON", "\"Wall1\"", "\"wall1\"", "only by case"}));
  EXPECT_TRUE(ThrowsInputError(
      [] {
        idf("BuildingSurface:Detailed, W, Wall, C, Attic, , Outdoors, , SunExposed, WindExposed, , 3,\n"
            "  0,0,1, 0,0,0, 1,0,0;\n");
      },
      {"line 1, BuildingSurface:Detailed \"W\" field \"Zone Name\"", "no Zone named \"Attic\""}));
}

TEST(EnergyPlus, EpJsonErrorsNameTheJsonPath) {
  const std::string json = R"({
    "Zone": {"Z1": {}},
    "BuildingSurface:Detailed": {"W": {"surface_type": "Wall", "zone_name": "Z1",
      "outside_boundary_condition": "Outdoors", "number_of_vertices": 3, "vertices": [
        {"vertex_x_coordinate": 0, "vertex_y_coordinate": 0, "vertex_z_coordinate": 1},
        {"vertex_x_coordinate": 0, "vertex_y_coordinate": 0, "vertex_z_coordinate": "low"},
        {"vertex_x_coordinate": 1, "vertex_y_coordinate": 0, "vertex_z_coordinate": 0}]}}})";
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse_energyplus(json, "m.epJSON", true); },
      {"m.epJSON: [\"BuildingSurface:Detailed\"][\"W\"].vertices[1].vertex_z_coordinate", "not a number: \"low\""}));
  EXPECT_TRUE(ThrowsInputError([&] { parse_energyplus("{\"Zone\": ", "m.epJSON", true); },
                               {"m.epJSON", "malformed JSON"}));
  // A number beyond a double (nlohmann's out_of_range 406, not a parse_error): named at its path.
  EXPECT_TRUE(ThrowsInputError(
      [&] { parse_energyplus(R"({"Zone": {"Z": {"x_origin": 1e400}}})", "m.epJSON", true); },
      {"m.epJSON: [\"Zone\"][\"Z\"].x_origin: number 1e400 is not finite"}));
}

/// The message of the InputError `action` throws ("" if none).
std::string message_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(EnergyPlus, EpJsonObjectNamedTwiceIsAnErrorNotALostObject) {
  // JSON keeps one value per key: the first "Fence" would vanish (a neighbour's shading gone,
  // exit 0). The IDF reader refuses the same model; so does the epJSON one, at the class's path.
  const std::string shading = R"({"vertices": [{"vertex_x_coordinate": 0, "vertex_y_coordinate": 0, "vertex_z_coordinate": 0},
      {"vertex_x_coordinate": 1, "vertex_y_coordinate": 0, "vertex_z_coordinate": 0},
      {"vertex_x_coordinate": 1, "vertex_y_coordinate": 0, "vertex_z_coordinate": 1}]})";
  const std::string twice = "{\"Shading:Site:Detailed\": {\"Fence\": " + shading + ",\n \"Fence\": " + shading + "}}";
  const std::string message = message_of([&] { parse_energyplus(twice, "m.epJSON", true); });
  EXPECT_NE(message.find("m.epJSON: [\"Shading:Site:Detailed\"]: duplicate key \"Fence\""), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
  // The IDF twin: the same rule (a second surface of the same name), whatever the case.
  EXPECT_TRUE(ThrowsInputError(
      [] {
        idf(std::string(kHeader) + "Shading:Site:Detailed, Fence, , 3, 0,0,0, 1,0,0, 1,0,1;\n" +
            "Shading:Site:Detailed, Fence, , 3, 0,0,0, 1,0,0, 1,0,1;\n");
      },
      {"line 5, Shading:Site:Detailed \"Fence\"", "a second surface named \"Fence\""}));
  // Across classes and letter case, as in IDF: surface names are unique among all surfaces.
  const std::string across = "{\"Shading:Site:Detailed\": {\"Fence\": " + shading +
                             "}, \"Shading:Building:Detailed\": {\"FENCE\": " + shading + "}}";
  EXPECT_TRUE(ThrowsInputError([&] { parse_energyplus(across, "m.epJSON", true); },
                               {"m.epJSON: [\"Shading:Building:Detailed\"][\"FENCE\"]",
                                "a second surface named \"FENCE\"", "[\"Shading:Site:Detailed\"][\"Fence\"]"}));
  // A class written twice would lose all the objects of its first block.
  const std::string two_blocks = "{\"Shading:Site:Detailed\": {\"A\": " + shading +
                                 "}, \"Shading:Site:Detailed\": {\"B\": " + shading + "}}";
  EXPECT_TRUE(ThrowsInputError([&] { parse_energyplus(two_blocks, "m.epJSON", true); },
                               {"m.epJSON: top level: duplicate key \"Shading:Site:Detailed\""}));
  // Two zones of one name in different case: the IDF reader's rule again.
  EXPECT_TRUE(ThrowsInputError([&] { parse_energyplus(R"({"Zone": {"Z1": {}, "z1": {}}})", "m.epJSON", true); },
                               {"m.epJSON: [\"Zone\"][\"z1\"]", "a second Zone named \"z1\""}));
}

TEST(EnergyPlus, MessagesNamePlaceAndProblemInWords) {
  // A syntax error: line and column, no JSON library's tag or byte offset.
  std::string message = message_of([] { parse_energyplus("{\"Zone\": {\"Z\": {}},\n  \"Building\" 3}", "m.epJSON", true); });
  EXPECT_NE(message.find("m.epJSON: line 2, column 14: malformed JSON: "), std::string::npos) << message;
  EXPECT_EQ(message.find("json.exception"), std::string::npos) << message;
  EXPECT_EQ(message.find("byte"), std::string::npos) << message;
  // Bytes that are not UTF-8 are shown as \xHH, never echoed raw.
  message = message_of([] { parse_energyplus("{\"Zone\": {\"Z\xff\xfe\": {}}}", "m.epJSON", true); });
  EXPECT_NE(message.find("m.epJSON: line 1, column 13: malformed JSON: "), std::string::npos) << message;
  EXPECT_NE(message.find("\\xff"), std::string::npos) << message;
  EXPECT_TRUE(std::all_of(message.begin(), message.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; })) << message;
  message = message_of([] {
    idf(std::string(kHeader) +
        "BuildingSurface:Detailed, W, Wall, C, Z\xe9, , Outdoors, , SunExposed, WindExposed, , 3, 0,0,1, 0,0,0, 1,0,0;\n");
  });
  EXPECT_NE(message.find("no Zone named \"Z\\xe9\""), std::string::npos) << message;
  // A zone name given as a number is a mistake in epJSON (names are strings), not a missing name.
  const std::string json = R"({"Zone": {"17": {}},
    "BuildingSurface:Detailed": {"W": {"surface_type": "Wall", "zone_name": 17,
      "outside_boundary_condition": "Outdoors", "vertices": [
        {"vertex_x_coordinate": 0, "vertex_y_coordinate": 0, "vertex_z_coordinate": 1},
        {"vertex_x_coordinate": 0, "vertex_y_coordinate": 0, "vertex_z_coordinate": 0},
        {"vertex_x_coordinate": 1, "vertex_y_coordinate": 0, "vertex_z_coordinate": 0}]}}})";
  EXPECT_TRUE(ThrowsInputError([&] { parse_energyplus(json, "m.epJSON", true); },
                               {"m.epJSON: [\"BuildingSurface:Detailed\"][\"W\"].zone_name",
                                "expected a name (a JSON string), got number 17"}));
  // In an IDF every field is text: a zone may be called 17.
  EXPECT_EQ(idf("Version, 24.1;\nZone, 17;\nBuildingSurface:Detailed, W, Wall, C, 17, , Outdoors, , SunExposed, "
                "WindExposed, , 3, 0,0,1, 0,0,0, 1,0,0;\n")
                .faces.size(),
            1u);
  // A version that is no version.
  EXPECT_TRUE(ThrowsInputError([] { idf("Version, abc;\nZone, Z1;\n"); },
                               {"m.idf: line 1, Version field \"Version Identifier\"",
                                "expected an EnergyPlus version like 24.1 or 9.6, not \"abc\""}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse_energyplus(R"({"Version": {"Version 1": {"version_identifier": "24.x"}}})", "m.epJSON", true); },
      {"m.epJSON: [\"Version\"][\"Version 1\"].version_identifier", "expected an EnergyPlus version"}));
  EXPECT_TRUE(ThrowsInputError(
      [] { parse_energyplus(R"({"Version": {"Version 1": {"version_identifier": 24.1}}})", "m.epJSON", true); },
      {"m.epJSON: [\"Version\"][\"Version 1\"].version_identifier", "got number 24.1"}));
  // Versions as EnergyPlus writes them are read.
  for (const char* version : {"9.4", "24.1.0", "23.2"})
    EXPECT_NO_THROW(idf(std::string("Version, ") + version + ";\nZone, Z1;\nShading:Site:Detailed, S, , 3, 0,0,0, 1,0,0, 1,0,1;\n"))
        << version;
}

TEST(EnergyPlus, ReadsOlderIdfVersionsWithoutSpaceName) {
  // Before EnergyPlus 9.6 the surfaces had no Space Name field.
  const Model m = idf(
      "Version, 9.4;\nZone, Z1;\n"
      "BuildingSurface:Detailed, W, Wall, C, Z1, Outdoors, , SunExposed, WindExposed, , 3,\n"
      "  0,0,1, 0,0,0, 1,0,0;\n");
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0].vertices[2], dvec3(1, 0, 0));
}

}  // namespace

namespace {

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Damaged models give a model or an InputError, never another exception or a crash: every
// mutation of the example (a byte changed, a span deleted or doubled), seeded, both syntaxes.
TEST(EnergyPlus, DamagedModelsGiveAModelOrAnInputErrorOnly) {
  for (const char* name : {"box-office.idf", "box-office.epJSON"}) {
    const std::string original = read_all(kExample / name);
    const bool epjson = std::string(name).find("epJSON") != std::string::npos;
    std::mt19937_64 random(20261123);
    const std::string alphabet = "0123456789-.,;!{}[]\":eE \n+xX";
    int models = 0, errors = 0;
    for (int trial = 0; trial < 400; ++trial) {
      std::string text = original;
      const std::size_t at = random() % text.size();
      const std::size_t span = 1 + random() % 12;
      switch (trial % 3) {
        case 0: text[at] = alphabet[random() % alphabet.size()]; break;
        case 1: text.erase(at, span); break;
        default: text.insert(at, text.substr(at, span)); break;
      }
      try {
        parse_energyplus(text, name, epjson);
        ++models;
      } catch (const InputError& e) {
        ++errors;
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      } catch (const std::exception& e) {
        ADD_FAILURE() << name << " trial " << trial << ": not an InputError: " << e.what();
      }
    }
    EXPECT_GT(models, 0) << name;
    EXPECT_GT(errors, 0) << name;
  }
}

}  // namespace

namespace {

// Seeded random windows and doors in one wall (some touching the wall's edges or each other),
// with the zone turned by a multiple of 90 degrees and moved: wall pieces + openings = gross wall,
// exactly, and the pieces are hole-free polygons of positive area that the validator accepts.
TEST(EnergyPlus, RandomOpeningsAlwaysLeaveTheExactNetWall) {
  std::mt19937 random(20261123);
  for (int trial = 0; trial < 60; ++trial) {
    const int north = 90 * static_cast<int>(random() % 4);
    const double ox = static_cast<double>(random() % 64) / 8.0, oy = static_cast<double>(random() % 64) / 8.0;
    std::string text = "Zone, Z, " + std::to_string(north) + ", " + std::to_string(ox) + ", " + std::to_string(oy) +
                       ", 0;\nBuildingSurface:Detailed, W, Wall, C, Z, , Outdoors, , SunExposed, WindExposed, , 4,\n"
                       "  0,0,4, 0,0,0, 8,0,0, 8,0,4;\n";
    double openings = 0.0;
    int count = 0;
    for (int cx = 0; cx < 4; ++cx)
      for (int cy = 0; cy < 2; ++cy) {
        if (random() % 2 == 0) continue;
        // Inside the 2 x 2 cell, edges on eighths: 0 insets touch the neighbours or the wall's edge.
        const double x0 = 2.0 * cx + static_cast<double>(random() % 4) / 8.0;
        const double x1 = 2.0 * cx + 2.0 - static_cast<double>(random() % 4) / 8.0;
        const double z0 = 2.0 * cy + static_cast<double>(random() % 4) / 8.0;
        const double z1 = 2.0 * cy + 2.0 - static_cast<double>(random() % 4) / 8.0;
        openings += (x1 - x0) * (z1 - z0);
        char window[256];
        std::snprintf(window, sizeof window,
                      "FenestrationSurface:Detailed, O%d, Window, G, W, , , , 1, 4,\n"
                      "  %.17g,0,%.17g, %.17g,0,%.17g, %.17g,0,%.17g, %.17g,0,%.17g;\n",
                      count++, x0, z1, x0, z0, x1, z0, x1, z1);
        text += window;
      }
    SCOPED_TRACE(text);
    const Model m = idf(text);
    const auto areas = area_by_name(m);
    EXPECT_EQ(areas.at("W"), 32.0 - openings);
    double wall_and_openings = 0.0;
    for (const auto& [name, a] : areas) wall_and_openings += a;
    EXPECT_EQ(wall_and_openings, 32.0);
    for (const Face& f : m.faces) {
      EXPECT_GT(area(f.vertices), 0.0) << f.name;
      const dvec3 n = newell(f.vertices);
      EXPECT_EQ(n.z, 0.0) << f.name;  // every piece stays in the (vertical) wall, facing its way:
      // the zone's -y, turned `north` degrees clockwise
      const double a = north * M_PI / 180.0;
      EXPECT_GT(n.x * -std::sin(a) + n.y * -std::cos(a), 0.0) << f.name;
    }
    Scene scene = scene_of(m, dvec3(1, 1, 1));  // validation: planar, simple, no zero area
    EXPECT_EQ(scene.faces.size(), m.faces.size());
  }
}

}  // namespace
