// SPDX-License-Identifier: GPL-3.0-or-later
// Named surfaces: the unit of named results (faces sharing a name are added up).
#include <shadow/scene.hpp>

#include <unordered_map>

namespace shadow {

std::string face_label(const Scene& scene, std::size_t face_id) {
  const std::string& name = scene.faces.at(face_id).name;
  return name.empty() ? "face_" + std::to_string(face_id) : name;
}

std::vector<NamedSurface> named_surfaces(const Scene& scene, bool receivers_only) {
  std::vector<NamedSurface> surfaces;
  std::unordered_map<std::string, std::size_t> by_name;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (receivers_only && !scene.is_receiver(f)) continue;
    const std::string& name = scene.faces[f].name;
    if (name.empty()) {
      surfaces.push_back({face_label(scene, f), {f}});
      continue;
    }
    const auto [it, inserted] = by_name.emplace(name, surfaces.size());
    if (inserted)
      surfaces.push_back({name, {f}});
    else
      surfaces[it->second].faces.push_back(f);
  }
  return surfaces;
}

}  // namespace shadow
