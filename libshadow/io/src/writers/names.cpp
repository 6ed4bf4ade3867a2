// SPDX-License-Identifier: GPL-3.0-or-later
#include "writers/names.hpp"

#include <set>
#include <unordered_map>

namespace shadow::detail {

std::string sanitize_array_name(const std::string& name) {
  std::string out = name;
  for (char& c : out) {
    const bool keep = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
    if (!keep) c = '_';
  }
  return out;
}

std::string light_display_name(const Scene& scene, std::size_t light_id) {
  if (light_id < scene.lights.size()) return scene.lights[light_id].name;
  return "light" + std::to_string(light_id);
}

std::vector<std::string> light_array_names(const Scene& scene,
                                           const std::vector<std::size_t>& light_ids) {
  std::vector<std::string> names;
  names.reserve(light_ids.size());
  std::unordered_map<std::string, int> uses;
  for (std::size_t id : light_ids) {
    std::string name = sanitize_array_name(light_display_name(scene, id));
    if (name.empty()) name = "light" + std::to_string(id);
    names.push_back(name);
    ++uses[name];
  }
  // Names that clash ("sun 1" and "sun_1") get their light id so no array overwrites another.
  std::set<std::string> taken;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (uses[names[i]] > 1) names[i] += "_" + std::to_string(light_ids[i]);
    while (!taken.insert(names[i]).second) names[i] += "_";
  }
  return names;
}

std::vector<std::size_t> lights_with_results(const ShadowResult& result) {
  std::set<std::size_t> ids;
  for (const FaceLighting& entry : result.lighting) ids.insert(entry.light_id);
  return {ids.begin(), ids.end()};
}

}  // namespace shadow::detail
