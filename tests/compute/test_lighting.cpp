// SPDX-License-Identifier: GPL-3.0-or-later
// The lighting models against values computed by hand (each comment shows the arithmetic).
#include <shadow/lighting.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using shadow::Attenuation;
using shadow::Light;
using shadow::LightingModel;
using shadow::LightingSettings;
using shadow::LightType;
using shadow::Material;
using shadow::ShadingPoint;

namespace {

constexpr double kTol = 1e-12;

Light sun(glm::dvec3 to_light, double intensity = 1.0, glm::dvec3 color = glm::dvec3(1.0)) {
  Light l;
  l.name = "sun";
  l.type = LightType::Directional;
  l.to_light = to_light;
  l.intensity = intensity;
  l.color = color;
  return l;
}

Light lamp(glm::dvec3 position, double intensity = 1.0) {
  Light l;
  l.name = "lamp";
  l.type = LightType::Point;
  l.position = position;
  l.intensity = intensity;
  return l;
}

/// A grey material with round numbers: k_a 0.1, k_d 0.5, k_s 0.4, p 2, white colours.
Material plain() {
  Material m;
  m.k_a = 0.1;
  m.k_d = 0.5;
  m.k_s = 0.4;
  m.shininess = 2.0;
  m.color = glm::dvec3(1.0);
  m.specular_color = glm::dvec3(1.0);
  return m;
}

LightingSettings settings(LightingModel model) {
  LightingSettings s;
  s.model = model;
  s.ambient_intensity = 1.0;
  s.ambient_color = glm::dvec3(1.0);
  s.attenuation = Attenuation::None;
  return s;
}

/// A point at the origin of the ground (normal +z) seen from straight above.
ShadingPoint ground_point(glm::dvec3 viewer = {0.0, 0.0, 5.0}) {
  return ShadingPoint{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, viewer};
}

void expect_grey(const glm::dvec3& c, double value) {
  EXPECT_NEAR(c.r, value, kTol);
  EXPECT_NEAR(c.g, value, kTol);
  EXPECT_NEAR(c.b, value, kTol);
}

// The sun 60 degrees from the zenith: N.L = cos 60 = 0.5.
const glm::dvec3 kSixtyDegrees{std::sin(M_PI / 3), 0.0, 0.5};

}  // namespace

// ---- irradiance --------------------------------------------------------------------------------

TEST(Irradiance, DirectionalIsIntensityTimesCosine) {
  // 2 * cos 60 = 1
  EXPECT_NEAR(shadow::irradiance(sun(kSixtyDegrees, 2.0), {3, 4, 0}, {0, 0, 1}), 1.0, kTol);
  // to_light need not be unit: (0, 3, 4) has N.L = 4/5
  EXPECT_NEAR(shadow::irradiance(sun({0, 3, 4}), {0, 0, 0}, {0, 0, 1}), 0.8, kTol);
}

TEST(Irradiance, DirectionalBehindTheSurfaceIsZero) {
  EXPECT_EQ(shadow::irradiance(sun({0, 0, -1}), {0, 0, 0}, {0, 0, 1}), 0.0);
}

TEST(Irradiance, PointLightFallsOffWithTheSquareOfTheDistance) {
  // lamp at (3, 0, 4), point at origin: r = 5, N.L = 4/5, 10 * 0.8 / 25 = 0.32
  EXPECT_NEAR(shadow::irradiance(lamp({3, 0, 4}, 10.0), {0, 0, 0}, {0, 0, 1}), 0.32, kTol);
  // straight above at height 2: 1 / 4
  EXPECT_NEAR(shadow::irradiance(lamp({1, 1, 2}), {1, 1, 0}, {0, 0, 1}), 0.25, kTol);
}

TEST(Irradiance, ANonUnitNormalIsNormalised) {
  EXPECT_NEAR(shadow::irradiance(sun({0, 0, 1}), {0, 0, 0}, {0, 0, 7}), 1.0, kTol);
}

// An area light or a disk lights as a point light at its centre (centre_light): before, the
// shading functions read Light::position, (0, 0, 0) for an area light.
TEST(Irradiance, AnAreaLightOrADiskLightsFromItsCentre) {
  Light area;
  area.type = LightType::Area;
  area.intensity = 3.0;
  area.polygon = {{0.5, 1.5, 4}, {0.5, 2.5, 4}, {1.5, 2.5, 4}, {1.5, 1.5, 4}};  // centroid (1, 2, 4)
  Light disk;
  disk.type = LightType::Disk;
  disk.intensity = 3.0;
  disk.position = {1, 2, 4};
  disk.radius = 0.5;
  const Light centre = lamp({1, 2, 4}, 3.0);
  const glm::dvec3 p(0.25, -0.5, 0.0), n(0, 0, 1), viewer(3, -4, 5);
  LightingSettings settings;
  settings.model = LightingModel::BlinnPhong;
  settings.attenuation = Attenuation::InverseSquare;
  Material m;
  for (const Light& light : {area, disk}) {
    EXPECT_EQ(shadow::centre_light(light).position, centre.position);
    EXPECT_NEAR(shadow::irradiance(light, p, n), shadow::irradiance(centre, p, n), kTol);
    EXPECT_NEAR(shadow::irradiance(light, p, n), 3.0 * 4 / std::pow(glm::length(centre.position - p), 3), kTol);
    const glm::dvec3 d = shadow::direction_to_light(light, p) - shadow::direction_to_light(centre, p);
    EXPECT_LT(glm::length(d), kTol);
    EXPECT_NEAR(shadow::attenuation_factor(light, p, viewer, settings),
                shadow::attenuation_factor(centre, p, viewer, settings), kTol);
    const glm::dvec3 c = shadow::shade({p, n, viewer}, m, {light}, {true}, settings) -
                         shadow::shade({p, n, viewer}, m, {centre}, {true}, settings);
    EXPECT_LT(glm::length(c), kTol);
  }
}

TEST(Irradiance, ALampOnThePointGivesZeroNotInfinity) {
  EXPECT_EQ(shadow::irradiance(lamp({0, 0, 0}), {0, 0, 0}, {0, 0, 1}), 0.0);
}

// ---- the models ----------------------------------------------------------------------------------

TEST(LightingModels, AmbientIsKaTimesIa) {
  LightingSettings s = settings(LightingModel::Ambient);
  s.ambient_intensity = 0.5;
  // 0.1 * 0.5 = 0.05, whatever the lights
  expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, 1})}, {true}, s), 0.05);
}

TEST(LightingModels, AmbientUsesTheAmbientAndMaterialColours) {
  LightingSettings s = settings(LightingModel::Ambient);
  s.ambient_color = {1.0, 0.5, 0.0};
  Material m = plain();
  m.color = {0.5, 1.0, 1.0};
  const glm::dvec3 c = shadow::shade(ground_point(), m, {}, {}, s);
  EXPECT_NEAR(c.r, 0.1 * 0.5, kTol);
  EXPECT_NEAR(c.g, 0.1 * 0.5, kTol);
  EXPECT_NEAR(c.b, 0.0, kTol);
}

TEST(LightingModels, LambertIsKdTimesIlTimesCosine) {
  // 0.1 + 0.5 * 2 * 0.5 = 0.6
  expect_grey(shadow::shade(ground_point(), plain(), {sun(kSixtyDegrees, 2.0)}, {true},
                            settings(LightingModel::Lambert)),
              0.6);
}

TEST(LightingModels, LambertMultipliesLightAndMaterialColours) {
  Material m = plain();
  m.color = {1.0, 0.5, 0.25};
  const glm::dvec3 c = shadow::shade(ground_point(), m, {sun({0, 0, 1}, 1.0, {0.5, 1.0, 1.0})}, {true},
                                     settings(LightingModel::Lambert));
  // r: 0.1*1 + 0.5*0.5*1 = 0.35; g: 0.1*0.5 + 0.5*1*0.5 = 0.3; b: 0.025 + 0.125 = 0.15
  EXPECT_NEAR(c.r, 0.35, kTol);
  EXPECT_NEAR(c.g, 0.30, kTol);
  EXPECT_NEAR(c.b, 0.15, kTol);
}

TEST(LightingModels, LambertGivesNothingFromBehind) {
  expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, -1})}, {true},
                            settings(LightingModel::Lambert)),
              0.1);
}

TEST(LightingModels, HalfLambertMapsTheCosineToZeroOne) {
  // N.L = 0.5: 0.5 * 0.5 + 0.5 = 0.75; 0.1 + 0.5 * 0.75 = 0.475
  expect_grey(shadow::shade(ground_point(), plain(), {sun(kSixtyDegrees)}, {true},
                            settings(LightingModel::HalfLambert)),
              0.475);
  // N.L = -1 gives 0: ambient only; N.L = 0 gives 0.5: 0.1 + 0.25
  expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, -1})}, {true},
                            settings(LightingModel::HalfLambert)),
              0.1);
  expect_grey(shadow::shade(ground_point(), plain(), {sun({1, 0, 0})}, {true},
                            settings(LightingModel::HalfLambert)),
              0.35);
}

TEST(LightingModels, ModifiedHalfLambertAddsTheBackLightWithOneMinusH) {
  LightingSettings s = settings(LightingModel::ModifiedHalfLambert);
  s.back_intensity = 0.8;
  s.back_color = {1.0, 0.5, 0.0};
  // H = 0.75; front 1 * 1 * 0.5 * 0.75 = 0.375; back 0.8 * C_B * 0.5 * 0.25 = 0.1 * C_B
  const glm::dvec3 c = shadow::shade(ground_point(), plain(), {sun(kSixtyDegrees)}, {true}, s);
  EXPECT_NEAR(c.r, 0.1 + 0.375 + 0.1, kTol);
  EXPECT_NEAR(c.g, 0.1 + 0.375 + 0.05, kTol);
  EXPECT_NEAR(c.b, 0.1 + 0.375, kTol);
}

TEST(LightingModels, ModifiedHalfLambertBackLightStaysInShadow) {
  LightingSettings s = settings(LightingModel::ModifiedHalfLambert);
  s.back_intensity = 1.0;
  s.back_color = glm::dvec3(1.0);
  // Facing away: H = 0, front term 0 anyway; back 1 * 0.5 * 1 = 0.5.
  expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, -1})}, {false}, s), 0.6);
  // Shadowed while facing the sun 60 degrees off: the front term goes, the fill stays:
  // 0.1 + 1 * 0.5 * 0.25 = 0.225
  expect_grey(shadow::shade(ground_point(), plain(), {sun(kSixtyDegrees)}, {false}, s), 0.225);
}

TEST(LightingModels, PhongSpecularIsCosOfReflectionAndViewToThePowerP) {
  // Sun 60 degrees off towards +x; R = 2N(N.L) - L = (-sin60, 0, 0.5): the mirror direction.
  // A viewer along R sees cos = 1: 0.1 + 0.5*0.5 + 0.4*1 = 0.75
  const glm::dvec3 mirror{-std::sin(M_PI / 3), 0.0, 0.5};
  expect_grey(shadow::shade(ground_point(10.0 * mirror), plain(), {sun(kSixtyDegrees)}, {true},
                            settings(LightingModel::Phong)),
              0.75);
  // A viewer straight above: R.V = 0.5, squared 0.25; 0.1 + 0.25 + 0.4*0.25 = 0.45
  expect_grey(shadow::shade(ground_point(), plain(), {sun(kSixtyDegrees)}, {true},
                            settings(LightingModel::Phong)),
              0.45);
}

TEST(LightingModels, BlinnPhongUsesTheHalfVector) {
  // Viewer straight above, sun 60 degrees off: H is 30 degrees off N; cos^2 30 = 0.75.
  // 0.1 + 0.25 + 0.4 * 0.75 = 0.65
  expect_grey(shadow::shade(ground_point(), plain(), {sun(kSixtyDegrees)}, {true},
                            settings(LightingModel::BlinnPhong)),
              0.65);
}

TEST(LightingModels, SpecularUsesTheSpecularColour) {
  Material m = plain();
  m.color = {0.0, 0.0, 1.0};
  m.specular_color = {1.0, 1.0, 0.0};
  // Sun and viewer straight above: N.L = 1, N.H = 1. r: 0.4; g: 0.4; b: 0.1 + 0.5 = 0.6
  const glm::dvec3 c =
      shadow::shade(ground_point(), m, {sun({0, 0, 1})}, {true}, settings(LightingModel::BlinnPhong));
  EXPECT_NEAR(c.r, 0.4, kTol);
  EXPECT_NEAR(c.g, 0.4, kTol);
  EXPECT_NEAR(c.b, 0.6, kTol);
}

TEST(LightingModels, NoHighlightOnTheBackSide) {
  // Viewer below the ground, sun below too: N.L < 0, so no Lambert and no highlight.
  expect_grey(shadow::shade(ground_point({0, 0, -5}), plain(), {sun({0, 0, -1})}, {true},
                            settings(LightingModel::Phong)),
              0.1);
}

TEST(LightingModels, TheBackOfAFaceIsNeverLitEvenWithTheLightInFront) {
  // Sun straight above the ground's front, viewer below it: the viewer sees the back side, which
  // only the front's light could reach through the face. Ambient only: 0.1.
  for (LightingModel model : {LightingModel::Lambert, LightingModel::HalfLambert, LightingModel::Phong,
                              LightingModel::BlinnPhong})
    expect_grey(shadow::shade(ground_point({0, 0, -5}), plain(), {sun({0, 0, 1})}, {true}, settings(model)), 0.1);
}

TEST(LightingModels, ModifiedHalfLambertFillLightsTheBackSideWithItsOwnNormal) {
  // Seen from below, the visible normal is -z: for the sun above, N.L = -1, H = 0, so the front
  // light adds nothing and the fill adds I_B C_LB M_D (1 - H) = 0.5 * (0.55, 0.6, 0.75) * 0.5.
  const glm::dvec3 c = shadow::shade(ground_point({0, 0, -5}), plain(), {sun({0, 0, 1})}, {true},
                                     settings(LightingModel::ModifiedHalfLambert));
  EXPECT_NEAR(c.r, 0.1 + 0.25 * 0.55, kTol);
  EXPECT_NEAR(c.g, 0.1 + 0.25 * 0.6, kTol);
  EXPECT_NEAR(c.b, 0.1 + 0.25 * 0.75, kTol);
}

TEST(LightingModels, SeveralLightsAddUp) {
  // Sun straight above (0.5) and sun 60 degrees off at intensity 2 (0.5 * 2 * 0.5 = 0.5): 0.1 + 1
  expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, 1}), sun(kSixtyDegrees, 2.0)},
                            {true, true}, settings(LightingModel::Lambert)),
              1.1);
}

TEST(LightingModels, AShadowedLightContributesNothingButAmbient) {
  for (LightingModel model : {LightingModel::Lambert, LightingModel::HalfLambert, LightingModel::Phong,
                              LightingModel::BlinnPhong}) {
    expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, 1})}, {false}, settings(model)), 0.1);
  }
  // Two lights, the first in shadow: only the second (0.5 * 0.5 = 0.25) adds to ambient.
  expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, 1}), sun(kSixtyDegrees)},
                            {false, true}, settings(LightingModel::Lambert)),
              0.35);
}

TEST(LightingModels, LightsWithoutAVisibilityEntryCountAsLit) {
  expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, 1})}, {}, settings(LightingModel::Lambert)),
              0.6);
}

// ---- attenuation ---------------------------------------------------------------------------------

TEST(Attenuation, InverseSquareForPointLightsOnly) {
  LightingSettings s = settings(LightingModel::Lambert);
  s.attenuation = Attenuation::InverseSquare;
  // Lamp 2 above: N.L = 1, 1/r^2 = 1/4: 0.1 + 0.5 / 4 = 0.225
  expect_grey(shadow::shade(ground_point(), plain(), {lamp({0, 0, 2})}, {true}, s), 0.225);
  EXPECT_NEAR(shadow::attenuation_factor(sun({0, 0, 1}), {0, 0, 0}, {0, 0, 5}, s), 1.0, kTol);
}

TEST(Attenuation, ViewerLinearIsOneOverViewerDistancePlusK) {
  LightingSettings s = settings(LightingModel::Lambert);
  s.attenuation = Attenuation::ViewerLinear;
  s.attenuation_k = 3.0;
  // Seeds 000/001: d = 5 from the viewer: 1 / (5 + 3); ambient is not attenuated.
  // 0.1 + 0.5 / 8 = 0.1625
  expect_grey(shadow::shade(ground_point(), plain(), {sun({0, 0, 1})}, {true}, s), 0.1625);
  EXPECT_NEAR(shadow::attenuation_factor(lamp({0, 0, 2}), {0, 0, 0}, {0, 0, 5}, s), 0.125, kTol);
}

TEST(Attenuation, LightLinearIsOneOverLightDistancePlusK) {
  LightingSettings s = settings(LightingModel::Lambert);
  s.attenuation = Attenuation::LightLinear;
  s.attenuation_k = 2.0;
  // Lamp at (3, 0, 4): d = 5, 1/(5 + 2) = 1/7
  EXPECT_NEAR(shadow::attenuation_factor(lamp({3, 0, 4}), {0, 0, 0}, {0, 0, 9}, s), 1.0 / 7.0, kTol);
  EXPECT_NEAR(shadow::attenuation_factor(sun({0, 0, 1}), {0, 0, 0}, {0, 0, 9}, s), 1.0, kTol);
  // N.L = 0.8: 0.1 + 0.5 * 0.8 / 7
  expect_grey(shadow::shade(ground_point(), plain(), {lamp({3, 0, 4})}, {true}, s), 0.1 + 0.4 / 7.0);
}

TEST(Attenuation, ANonPositiveDenominatorGivesZeroNotInfinity) {
  LightingSettings s = settings(LightingModel::Lambert);
  s.attenuation = Attenuation::ViewerLinear;
  s.attenuation_k = -5.0;
  EXPECT_EQ(shadow::attenuation_factor(sun({0, 0, 1}), {0, 0, 0}, {0, 0, 5}, s), 0.0);
}

// ---- names ---------------------------------------------------------------------------------------

TEST(LightingNames, RoundTrip) {
  for (LightingModel m : {LightingModel::Ambient, LightingModel::Lambert, LightingModel::HalfLambert,
                          LightingModel::ModifiedHalfLambert, LightingModel::Phong,
                          LightingModel::BlinnPhong}) {
    LightingModel parsed = LightingModel::Ambient;
    ASSERT_TRUE(shadow::parse_lighting_model(shadow::to_string(m), parsed));
    EXPECT_EQ(parsed, m);
  }
  for (Attenuation a : {Attenuation::None, Attenuation::InverseSquare, Attenuation::ViewerLinear,
                        Attenuation::LightLinear}) {
    Attenuation parsed = Attenuation::None;
    ASSERT_TRUE(shadow::parse_attenuation(shadow::to_string(a), parsed));
    EXPECT_EQ(parsed, a);
  }
  LightingModel unused;
  EXPECT_FALSE(shadow::parse_lighting_model("gouraud", unused));
}
