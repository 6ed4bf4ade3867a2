// SPDX-License-Identifier: GPL-3.0-or-later
// Downstream check: a square lit by an overhead sun, computed through the installed package.
#include <shadow/shadow.hpp>

#include <cstdio>

int main() {
  shadow::Scene scene;
  scene.meshes.push_back({"ground", "", 0, 1, true});
  shadow::Face ground;
  ground.vertices = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  scene.faces.push_back(ground);
  shadow::Light sun;
  sun.name = "sun";
  sun.to_light = {0, 0, 1};
  scene.lights.push_back(sun);
  shadow::validate_scene(scene);
  const shadow::ShadowResult result = shadow::compute_shadows(scene);
  const shadow::FaceLighting* lighting = result.find(0, 0);
  std::printf("libshadow %s: lit area %.17g\n", shadow::version(), lighting ? lighting->lit_area : -1.0);
  return lighting && lighting->lit_area == 4.0 ? 0 : 1;
}
