// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz target: bytes -> shadow::parse_scene (a scene JSON text; inline meshes), then
// validate_scene. InputError is the expected answer to bad input; any other exception escapes
// so that libFuzzer (or the replay runner) reports it.
#include <shadow/scene_io.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

namespace {

/// True when the text names a mesh file: the target stays in memory (a fuzzed path could name
/// /dev/zero or a huge file). Checked on the parsed keys, so escapes such as "fil\u0065" count.
bool names_a_file(const std::string& text) {
  bool found = false;
  const auto callback = [&found](int /*depth*/, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    if (event == nlohmann::json::parse_event_t::key && parsed == "file") found = true;
    return true;
  };
  const nlohmann::json parsed = nlohmann::json::parse(text, callback, /*allow_exceptions=*/false);
  (void)parsed;
  return found;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (names_a_file(text)) return 0;
  try {
    // A directory that does not exist: any relative mesh path fails with an InputError.
    shadow::Scene scene = shadow::parse_scene(text, "/nonexistent-fuzz-dir/fuzz.json");
    shadow::validate_scene(scene);  // again: validating twice is harmless (scene_io.hpp)
  } catch (const shadow::InputError&) {
  }
  return 0;
}
