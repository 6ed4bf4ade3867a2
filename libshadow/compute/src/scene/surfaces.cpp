// SPDX-License-Identifier: GPL-3.0-or-later
// Named surfaces: the unit of named results (faces sharing a name are added up); objects: the
// unit of results per building, zone or mesh.
#include <shadow/scene.hpp>

#include <algorithm>
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

std::vector<std::size_t> select_meshes(const Scene& scene, const std::string& name, const SourceLocation& where) {
  std::vector<std::size_t> chosen;
  // A mesh's own name first: a mesh whose name happens to begin with "type:" is still found.
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    if (scene.meshes[m].name == name) return {m};
  // A scene file's mesh whose `file` is a model became that model's meshes: its name selects
  // them all, as the scene's keys take it.
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    if (!name.empty() && scene.meshes[m].scene_mesh == name) chosen.push_back(m);
  if (!chosen.empty()) return chosen;
  const std::string prefix = "type:";
  if (name.rfind(prefix, 0) != 0) throw InputError(where, "no mesh is named \"" + name + "\"");
  const std::string type = name.substr(prefix.size());
  std::vector<std::string> present;  // the types of the scene's meshes, in order of appearance
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const std::string& t = scene.meshes[m].object_type;
    if (t == type && !type.empty()) chosen.push_back(m);
    if (!t.empty() && std::find(present.begin(), present.end(), t) == present.end()) present.push_back(t);
  }
  if (!chosen.empty()) return chosen;
  std::string known;
  for (const std::string& t : present) known += (known.empty() ? "" : ", ") + t;
  const std::string asked = type.empty() ? "an empty type" : "the type \"" + type + "\"";
  throw InputError(where, asked + " selects no mesh (" +
                              (present.empty() ? std::string("no mesh has an object type: type:<T> selects CityJSON "
                                                             "city objects by their type, EnergyPlus zones as type:zone")
                                               : "the object types present: " + known) +
                              ")");
}

}  // namespace shadow
