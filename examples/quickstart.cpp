// SPDX-License-Identifier: GPL-3.0-or-later
// Quickstart: load a scene, compute exact shadows with one call, print each mesh's lit fraction.
//   example_quickstart examples/default/scene.json
#include <shadow/shadow.hpp>

#include <cstdio>
#include <map>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SCENE.json\n", argv[0]);
    return 1;
  }
  try {
    const shadow::Scene scene = shadow::load_scene(argv[1]);
    const shadow::ShadowResult result = shadow::compute_shadows(scene);
    // Sum exact per-face areas per mesh and light.
    std::map<std::pair<std::size_t, std::size_t>, std::pair<double, double>> per_mesh;
    for (const shadow::FaceLighting& fl : result.lighting) {
      auto& [area, lit] = per_mesh[{scene.faces[fl.face_id].mesh, fl.light_id}];
      area += fl.area;
      lit += fl.lit_area;
    }
    for (const auto& [key, value] : per_mesh)
      std::printf("%-12s %-8s lit fraction %.6f (%.3f of %.3f m2)\n", scene.meshes[key.first].name.c_str(),
                  scene.lights[key.second].name.c_str(), value.second / value.first, value.second,
                  value.first);
  } catch (const shadow::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
