// SPDX-License-Identifier: GPL-3.0-or-later
/// @file validation.hpp
/// @brief Scene validation (compute component): the checks a scene gets before any shadow is
/// computed, whether it was read from files (shadow/scene_io.hpp calls this) or built in code.
#pragma once

#include <shadow/scene.hpp>

#include <cstdint>
#include <string>

namespace shadow {

/// The largest accepted magnitude of any coordinate (vertices, point-light positions, plane
/// points and windows): 2^500, about 3.27e150. Directions (`to_light`, plane normals) are
/// scale-free and only need to be finite and non-zero. Differences of two such values
/// and products of two differences stay finite in doubles (2^1002 < DBL_MAX), which the
/// library's floating-point culling and the fast path rely on; beyond it input is an
/// InputError. Scenes scaled by 2^450 (tests/compute/test_fast_path.cpp) are inside the range.
inline constexpr double max_coordinate = 0x1p500;

/// How strictly face geometry is checked, and how much is read.
struct LoadOptions {
  /// A face is planar when every vertex lies within `planarity_tolerance * diameter` of the
  /// plane through its centroid with its Newell normal (diameter: the largest extent of its
  /// bounding box). The allowed distance is never below 8 ulps of the face's largest coordinate
  /// (rounding alone moves coordinates that much), and faces whose normal is numerically zero
  /// skip this test and go to the exact zero-area check. Must be > 0. Faces beyond it are an
  /// InputError. Within it, the library works on the face lifted exactly onto that plane
  /// (docs/numeric-contract.md).
  double planarity_tolerance = 1e-6;
  /// The largest scene or mesh file read, in bytes (default 2 GiB). A bigger file, and anything
  /// that is not a regular file after following symlinks (a FIFO, /dev/zero, a directory), is
  /// an InputError naming the file.
  std::uintmax_t max_file_bytes = std::uintmax_t{2} << 30;
  /// Turn the closed parts of every mesh outward during validation (Mesh::orient_outward for all
  /// meshes; `shadow compute --orient-outward`).
  bool orient_outward = false;
  /// The CityJSON level of detail to read (`"1"`, `"2"`, `"2.2"`, compared with the geometry's
  /// `lod` as written); empty: the highest level of each city object. A city object without
  /// geometry at the chosen level is left out with a warning.
  std::string cityjson_lod;
  /// Threads for validation's per-face checks, and for reading a large OBJ file in parts and
  /// making its faces (0: every hardware thread; at most 1024, else an InputError). The outcome
  /// does not depend on it: faces come in file order, warnings in face order, and the error
  /// reported is that of the first face (in face order, or the first line of a file) that has one.
  unsigned threads = 0;
  /// Leave out the faces that fail validation instead of stopping (`--skip-invalid`): a face
  /// with fewer than 3 distinct vertices, one beyond the planarity tolerance, one whose boundary
  /// intersects itself, one with a coordinate that is not finite or beyond max_coordinate, and a
  /// model surface the reader cannot make faces of (a CityJSON inner ring outside its surface, a
  /// non-planar surface that cannot be split into triangles). Each is recorded in
  /// Scene::skipped_faces with the reason, and warned about (the first 10 one by one, then one
  /// line for the rest). Skipped faces are removed before faces are numbered: face ids count the
  /// faces kept, so ids stay dense and every output agrees on them (a skipped face has none).
  /// Zero-area faces are not invalid: they are kept, marked `degenerate`, as without the flag.
  /// Without it the first invalid face is an InputError whose message names this option.
  bool skip_invalid = false;
  /// A scene file must have `lights` (at least one) unless it has a `sun` block. False: `lights`
  /// may be absent or empty (`shadow irradiance`, whose suns come from a weather file).
  bool require_lights = true;
};

/// Checks every face's geometry: finite coordinates within max_coordinate, planarity within tolerance, a simple
/// (non-self-intersecting) boundary; and the lights and planes. It changes the scene: removes
/// consecutive duplicate vertices, marks zero-area faces `degenerate` and adds a warning for
/// each. It also warns (Scene::warnings) about a closed mesh whose faces point inward (negative
/// signed volume) or whose faces are oriented inconsistently (an edge run the same way by both
/// of its faces); open meshes are never warned about. With LoadOptions::skip_invalid, invalid
/// faces are removed (Scene::skipped_faces, the faces after them renumbered, Mesh::first_face and
/// face_count updated) instead of thrown. Scenes built in code must call this before computing
/// shadows; calling it twice is harmless.
/// @throws InputError naming the face's source.
void validate_scene(Scene& scene, const LoadOptions& options = {});

}  // namespace shadow
