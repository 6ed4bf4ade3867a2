// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz target: bytes -> the EnergyPlus reader (IDF text, or epJSON when the text starts with `{`),
// then validate_scene on the faces it gives. InputError (with the line and field, or the JSON
// path) is the expected answer to bad input; any other exception escapes so that libFuzzer (or
// the replay runner) reports it.
#include <shadow/scene_io.hpp>

#include "readers/energyplus_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  const bool epjson = first != std::string::npos && text[first] == '{';
  try {
    const shadow::scene_readers::Model model = shadow::scene_readers::parse_energyplus(text, "fuzz.idf", epjson);
    // The hand-over's promises: meshes index the faces in order, every face has 3+ vertices.
    std::size_t next = 0;
    for (const shadow::Mesh& mesh : model.meshes) {
      if (mesh.first_face != next || mesh.face_count == 0) {
        std::fprintf(stderr, "fuzz_energyplus: mesh %s does not follow its predecessor\n", mesh.name.c_str());
        std::abort();
      }
      next += mesh.face_count;
    }
    if (next != model.faces.size()) std::abort();
    shadow::Scene scene;
    scene.meshes = model.meshes;
    scene.faces = model.faces;
    for (const shadow::Face& face : scene.faces)
      if (face.vertices.size() < 3 || face.mesh >= scene.meshes.size()) {
        std::fprintf(stderr, "fuzz_energyplus: a face with %zu vertices was accepted\n", face.vertices.size());
        std::abort();
      }
    shadow::validate_scene(scene);
  } catch (const shadow::InputError&) {
  }
  return 0;
}
