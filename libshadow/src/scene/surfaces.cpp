// SPDX-License-Identifier: GPL-3.0-or-later
// Named surfaces: the unit of named results (faces sharing a name are added up); objects: the
// unit of results per building, zone or mesh.
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

std::vector<SceneObject> scene_objects(const Scene& scene, bool receivers_only, bool per_mesh) {
  std::vector<SceneObject> objects;
  std::unordered_map<std::string, std::size_t> by_id;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (receivers_only && !mesh.receiver) continue;
    const bool part = !per_mesh && !mesh.parent.empty();
    const std::string& id = part ? mesh.parent : mesh.name;
    const std::string& type = part ? mesh.parent_type : mesh.object_type;
    // Scene files keep mesh names unique; a model's object and a part's parent of the same name
    // are one object.
    const auto [it, inserted] = by_id.emplace(id, objects.size());
    if (inserted) objects.push_back({id, type.empty() ? "mesh" : type, {}});
    SceneObject& object = objects[it->second];
    // The parent's own mesh, read after a part of it, still says what it is.
    if (!part && !mesh.object_type.empty()) object.type = mesh.object_type;
    object.meshes.push_back(m);
  }
  return objects;
}

}  // namespace shadow
