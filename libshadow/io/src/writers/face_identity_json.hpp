// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the identity keys of a face entry in report.json (name, source, kind, normal,
// azimuth, tilt), one writer for `shadow compute`'s and `shadow series`'s reports.
#pragma once

#include "writers/face_orientation.hpp"

#include <shadow/scene.hpp>

#include <nlohmann/json.hpp>

#include <cmath>

namespace shadow::detail {

/// Adds face `face_id`'s identity and orientation to `entry` (docs/scene-format.md, "Named
/// faces"): `name` (empty when unnamed), `source`, `kind` (when set), unit `normal`, `azimuth`
/// and `tilt` in degrees (null for a face without area).
inline void add_face_identity(nlohmann::ordered_json& entry, const Scene& scene, std::size_t face_id) {
  using Json = nlohmann::ordered_json;
  if (face_id >= scene.faces.size()) return;
  const Face& face = scene.faces[face_id];
  const FaceOrientation o = face_orientation(face, north_axis_of(scene));
  auto number = [](double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); };
  entry["name"] = face.name;
  entry["source"] = face.source.to_string();
  if (!face.kind.empty()) entry["kind"] = face.kind;
  entry["normal"] = Json::array({o.normal.x, o.normal.y, o.normal.z});
  entry["azimuth"] = number(o.azimuth);
  entry["tilt"] = number(o.tilt);
}

/// report.json's `skipped_faces` (written when there are any): the faces left out by
/// LoadOptions::skip_invalid, each with its name, mesh, source and the reason (the validation
/// error it failed). They have no id.
inline nlohmann::ordered_json skipped_faces_json(const Scene& scene) {
  using Json = nlohmann::ordered_json;
  Json list = Json::array();
  for (const SkippedFace& s : scene.skipped_faces)
    list.push_back({{"name", s.name}, {"mesh", s.mesh}, {"source", s.source.to_string()}, {"reason", s.reason}});
  return list;
}

}  // namespace shadow::detail
