// SPDX-License-Identifier: GPL-3.0-or-later
#include "support/scene_builders.hpp"

#include <shadow/validation.hpp>

namespace shadow::test {

Scene furnace_room(double e, double rho) {
  Scene scene;
  Material m;
  m.name = "grey";
  m.emittance = e;
  m.reflectance = rho;
  scene.materials.push_back(m);
  add_mesh(scene, "room", room_faces({0, 0, 0}, {2, 1, 1.5}));
  scene.meshes[0].material = "grey";
  validate_scene(scene);
  return scene;
}

}  // namespace shadow::test
