// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz target: bytes -> shadow::parse_obj. InputError (with the OBJ line) is the expected answer
// to bad input; any other exception escapes so that libFuzzer (or the replay runner) reports it.
#include <shadow/scene_io.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto faces = shadow::parse_obj(text, "fuzz.obj");
    for (const auto& face : faces) {
      // parse_obj promises faces (at least 3 vertex references each); the values are read
      // here so that a dangling or uninitialised vertex shows up under the sanitizers.
      if (face.size() < 3) {
        std::fprintf(stderr, "fuzz_obj: a face with %zu vertices was accepted\n", face.size());
        std::abort();
      }
      double sum = 0;
      for (const auto& v : face) sum += std::abs(v.x) + std::abs(v.y) + std::abs(v.z);
      if (sum == -1.0) std::abort();  // never true; keeps the reads
    }
  } catch (const shadow::InputError&) {
  }
  return 0;
}
