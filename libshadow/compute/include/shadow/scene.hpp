// SPDX-License-Identifier: GPL-3.0-or-later
/// @file scene.hpp
/// @brief The scene: polygonal faces grouped in meshes, lights and receiving planes.
///
/// Plain structs with GLM types: no CGAL here. Coordinates are doubles as read;
/// everything derived from them inside the library is exact (see docs/numeric-contract.md).
#pragma once

#include <shadow/error.hpp>
#include <shadow/material.hpp>
#include <shadow/sun.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace shadow {

/// One planar polygon. Its front is the side from which the vertices run counter-clockwise.
struct Face {
  std::vector<glm::dvec3> vertices;  ///< at least 3, consecutive duplicates removed
  std::size_t mesh = 0;              ///< index into Scene::meshes
  SourceLocation source;             ///< where the face was defined (OBJ line or JSON path)
  /// The name of the surface this face belongs to (an inline polygon's `name`, an OBJ `o`/`g`
  /// group, an EnergyPlus surface, a CityJSON surface); empty when unnamed. Several faces may
  /// share a name: the pieces of one surface with holes, the faces of one OBJ group. Results
  /// per named surface add them up (named_surfaces()).
  std::string name;
  /// What the model says the surface is: a CityJSON semantic surface (`RoofSurface`,
  /// `WallSurface`, `GroundSurface`, ...) or an EnergyPlus surface type (`Wall`, `Roof`,
  /// `Window`, `Door`, `Shading`, ...); empty when the input says nothing.
  std::string kind;
  /// Set by validation: the face has zero area (collinear or coincident vertices).
  /// It keeps its face_id but casts no shadow and receives no light.
  bool degenerate = false;
};

/// A named group of consecutive faces, read from an OBJ file or given inline.
struct Mesh {
  std::string name;
  std::string file;             ///< OBJ path as written in the scene (empty for inline polygons)
  std::size_t first_face = 0;   ///< face_id of the mesh's first face
  std::size_t face_count = 0;
  bool receiver = true;         ///< faces of this mesh receive light (see `receivers`)
  /// Name of the mesh's entry in Scene::materials; empty: the default Material{}.
  std::string material;
  /// Validation turns the closed parts of this mesh outward (scene file `"orient": "outward"`,
  /// or LoadOptions::orient_outward for every mesh): a part whose faces disagree is made
  /// consistent, then a part with negative signed volume is reversed. Each change is a warning.
  bool orient_outward = false;
  /// The model the mesh was read from: "energyplus" (an IDF or epJSON file) or "cityjson";
  /// empty for OBJ files and inline polygons. A scene with an EnergyPlus mesh gets
  /// energyplus-shading.csv from `shadow series` (docs/series.md).
  std::string model;
  /// A model's mesh read through a scene file's mesh (`{"name": "city", "file": "x.city.json"}`):
  /// that scene mesh's name, which selects all of them (select_meshes()). Empty otherwise, also
  /// for a model read as the scene itself.
  std::string scene_mesh;
  /// What the mesh is in the model it was read from: a CityJSON city object's `type`
  /// (`Building`, `BuildingPart`, `TINRelief`, ...) or `zone` for an EnergyPlus zone; empty for
  /// meshes of a scene file or an OBJ file and for EnergyPlus's shading groups. `type:<T>` in
  /// `receivers`, `sun_hours_map` and `--sun-hours-map` selects by it (select_meshes()).
  std::string object_type;
  /// CityJSON: the top-level city object this one is part of (a BuildingPart's Building: the
  /// first of `parents`, followed up to an object without parents), named as meshes are
  /// (`<scene mesh>/<id>` inside a scene file). Empty for a top-level object and every other
  /// mesh. Results per object (scene_objects()) roll the mesh up into it.
  std::string parent;
  /// The CityJSON `type` of `parent` (`Building`); empty when `parent` is.
  std::string parent_type;
};

/// A face that failed validation and was left out of the scene (LoadOptions::skip_invalid):
/// it has no face_id; the faces after it are numbered as if it had never been there.
struct SkippedFace {
  std::string name;       ///< the face's name (Face::name), empty when unnamed
  std::string mesh;       ///< the name of the mesh it belonged to
  SourceLocation source;  ///< where it was defined (OBJ line or JSON path)
  std::string reason;     ///< the validation error it failed, without the place
};

/// Kinds of light. Directional and Point are points (at infinity or not) and cast hard shadows;
/// Area and Disk are extended sources whose shadows have an umbra and a penumbra, as has a
/// Directional light with an `angular_diameter` (the sun's disk). See docs/area-lights.md.
enum class LightType { Directional, Point, Area, Disk };

/// A light source. Directional lights are at infinity in direction `to_light`.
struct Light {
  std::string name;
  LightType type = LightType::Directional;
  glm::dvec3 to_light{0.0, 0.0, 1.0};  ///< directional: from the scene toward the light (any length)
  glm::dvec3 position{0.0};            ///< point: the light's position; disk: its centre
  double intensity = 1.0;              ///< radiometric scale (used by lighting models)
  glm::dvec3 color{1.0, 1.0, 1.0};     ///< linear RGB in [0, 1]
  /// Area: the luminous planar polygon (at least 3 vertices). Light leaves its front, the side
  /// from which the vertices run counter-clockwise, as for faces.
  std::vector<glm::dvec3> polygon;
  /// Disk: the side the light leaves (any length); the disk lies in the plane through
  /// `position` with this normal.
  glm::dvec3 normal{0.0, 0.0, -1.0};
  double radius = 0.0;                 ///< disk: its radius (> 0)
  /// Directional only: the angular diameter of the source in degrees (the sun's is about
  /// 0.53); 0, the default, keeps it a point at infinity with hard shadows.
  double angular_diameter = 0.0;

  /// True for a source with extent (Area, Disk, or Directional with angular_diameter > 0).
  [[nodiscard]] bool is_extended() const {
    return type == LightType::Area || type == LightType::Disk ||
           (type == LightType::Directional && angular_diameter > 0.0);
  }
};

/// The point light (or directional light) that stands for `light` where one point is needed:
/// an area light's area centroid, a disk's centre, a sun disk's central direction (its
/// `angular_diameter` set to 0), with the same name, intensity and colour. Point and directional
/// lights come back as they are. FaceLighting::lit_area of an extended light is this light's;
/// the shading functions (lighting.hpp), the shadow-map and ray baselines and `shadow render`
/// use it for extended lights (docs/area-lights.md).
[[nodiscard]] Light centre_light(const Light& light);

/// An infinite receiving plane for Blinn projection shadows: n . (x - point) = 0.
struct Plane {
  std::string name;
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  /// Half side of the square window, centred under the scene, in which this plane's shadows are
  /// computed; 0 means ShadowOptions::plane_window.
  double window = 0.0;
};

/// The scene file's `camera`: the view `shadow render` pictures the scene from. Every key is
/// optional; one that is absent is left to the renderer (its default frames the scene, up
/// [0, 0, 1], 30 degrees). The shadows do not depend on it.
struct Camera {
  std::optional<glm::dvec3> eye;     ///< where the camera stands
  std::optional<glm::dvec3> target;  ///< the point it looks at
  std::optional<glm::dvec3> up;      ///< its up direction (any length)
  std::optional<double> fov_degrees; ///< vertical view angle in degrees, in [1, 170]
};

/// A whole scene. Face ids are indices into `faces`: meshes in order, faces in file order.
struct Scene {
  std::vector<Mesh> meshes;
  std::vector<Face> faces;
  std::vector<Light> lights;
  std::vector<Plane> planes;
  std::vector<Material> materials;  ///< named materials for lighting (scene file `materials`)
  std::filesystem::path source;    ///< the scene file (empty when built in code)
  std::vector<Warning> warnings;   ///< non-fatal findings of loading and validation
  /// The scene file's `camera` (absent when the file has none, or the scene is built in code).
  std::optional<Camera> camera;
  /// The scene's `sun` block (sun.hpp): the site and period whose suns were appended to
  /// `lights` as directional lights. Absent when the scene has none.
  std::optional<SunPeriod> sun;
  /// Every instant of the sun period in time order, above the horizon or not; an instant above
  /// it names its directional light in `lights` (SunInstant::light_id). Empty without `sun`.
  std::vector<SunInstant> sun_instants;
  /// The scene file's `sun_hours_map`: indices into `meshes` of the meshes whose faces get the
  /// exact sun-hours map (sun_hours.hpp, `sun_hours.vtp`), in the order given; empty: no map.
  std::vector<std::size_t> sun_hours_map;
  /// The scene file's `energyplus_shading`: whether `shadow series` writes
  /// energyplus-shading.csv. Absent: it does when a mesh comes from an EnergyPlus model
  /// (energyplus_shading_wanted(), series.hpp).
  std::optional<bool> energyplus_shading;
  /// The scene file's `ground`: indices into `meshes` of the meshes that are the ground, for
  /// `shadow irradiance` (what a face sees of them below the horizon reflects the ground
  /// reflectance; ground_faces() in irradiance.hpp). Absent: the default rule of ground_faces()
  /// (meshes named `ground`, CityJSON terrain and land); an empty list: no mesh is the ground.
  std::optional<std::vector<std::size_t>> ground;
  /// A point subtracted from every point written to the VTK files (faces, fragments, plane
  /// shadows, lights) and stated in report.json as `origin`: a city model at projected
  /// coordinates (1e5 to 1e7 m) then renders in ParaView without the jitter of float32
  /// rendering. The scene's coordinates, and everything computed from them, stay as read.
  /// Absent: points are written as they are. Set by the CityJSON reader (docs/cityjson.md).
  std::optional<glm::dvec3> origin;
  /// The faces left out because they failed validation (LoadOptions::skip_invalid), in the
  /// order they were found (model readers first, then validation in face order). Empty unless
  /// the scene was loaded or validated with skip_invalid.
  std::vector<SkippedFace> skipped_faces;

  /// True when face `face_id` belongs to a receiving mesh.
  [[nodiscard]] bool is_receiver(std::size_t face_id) const {
    return meshes[faces[face_id].mesh].receiver;
  }

  /// The material of face `face_id`: its mesh's named material, or the default Material{}
  /// when the mesh names none (or a name that is not in `materials`).
  [[nodiscard]] const Material& material_of(std::size_t face_id) const {
    static const Material default_material{};
    const std::string& name = meshes[faces[face_id].mesh].material;
    if (name.empty()) return default_material;
    for (const Material& m : materials)
      if (m.name == name) return m;
    return default_material;
  }
};

/// The faces that share one name, or one unnamed face: the unit in which named results (CSV
/// columns, EnergyPlus surfaces) are reported. Its lit fraction is the area-weighted mean of its
/// faces' (sum of lit areas over sum of areas).
struct NamedSurface {
  std::string label;              ///< the faces' name, or `face_<id>` for an unnamed face
  std::vector<std::size_t> faces; ///< face ids, ascending
};

/// The scene's named surfaces in the order of their first face: faces with the same non-empty
/// name form one surface (whatever their meshes), every unnamed face is a surface of its own
/// labelled `face_<id>`. With `receivers_only`, faces of non-receiving meshes are left out (and
/// a surface with none left is dropped).
std::vector<NamedSurface> named_surfaces(const Scene& scene, bool receivers_only = true);

/// A face's label: its name, or `face_<id>` when it has none.
std::string face_label(const Scene& scene, std::size_t face_id);

/// An object of the model, the unit of results per object (sun_hours_by_object.csv): a
/// CityJSON top-level city object with its parts (BuildingParts rolled up into their Building),
/// an EnergyPlus zone, or any other mesh.
struct SceneObject {
  /// The object's name: its mesh's name (a CityJSON object's id, `<scene mesh>/<id>` inside a
  /// scene file; a zone's name), or for a parent without geometry of its own, its name as a mesh
  /// would have it (Mesh::parent).
  std::string id;
  /// The CityJSON type (`Building`, `TINRelief`, ...), `zone` for an EnergyPlus zone, `mesh`
  /// for any other mesh.
  std::string type;
  std::vector<std::size_t> meshes;  ///< indices into Scene::meshes, ascending
};

/// The scene's objects in the order of their first mesh: each mesh belongs to its Mesh::parent
/// when it has one (a parent without a mesh of its own is an object too), else it is an object
/// of its own. With `per_mesh`, every mesh is an object of its own (type: its object_type, or
/// `mesh`), parts not rolled up. With `receivers_only`, meshes that do not receive are left out
/// (and an object with none left is dropped).
std::vector<SceneObject> scene_objects(const Scene& scene, bool receivers_only = true, bool per_mesh = false);

/// The meshes (indices into Scene::meshes, ascending) that one name selects, as `receivers`,
/// `sun_hours_map` and `--sun-hours-map` spell it: a mesh's name selects that mesh (a model's
/// meshes are named `<scene mesh>/<id>` inside a scene file, `<id>` when the model is the
/// scene); the name of a scene file's mesh whose `file` is a model selects all of that model's
/// meshes (Mesh::scene_mesh); otherwise `type:<T>` selects every mesh whose Mesh::object_type
/// is `T` (a CityJSON object type such as `type:Building` or `type:TINRelief`, or `type:zone`
/// for EnergyPlus zones; compared as written).
/// @throws InputError at `where` (the key or flag that gave the name: `receivers[2]`,
/// `--sun-hours-map`) for a name no mesh has, or a type no mesh has (listing the types present).
std::vector<std::size_t> select_meshes(const Scene& scene, const std::string& name, const SourceLocation& where);

}  // namespace shadow
