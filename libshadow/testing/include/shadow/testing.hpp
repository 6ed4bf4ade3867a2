// SPDX-License-Identifier: GPL-3.0-or-later
/// @file testing.hpp
/// @brief libshadow::testing: exact oracles, invariant checkers and comparison helpers for
/// property tests of other people's geometry code (shadow maps, shadow rays, sunlit fractions).
///
/// Needs neither rapidcheck nor GoogleTest: the generators are in shadow/testing/generators.hpp
/// (rapidcheck) and the GoogleTest assertions in shadow/testing/gtest.hpp. Link
/// `libshadow::testing` (find_package(libshadow COMPONENTS testing)). See docs/testing-kit.md.
///
/// **Exactness contract.** `is_lit` and `is_lit_on_face` decide exactly, in rational arithmetic,
/// for the point as given in doubles, and do not use the engine: they test the open segment from
/// the point to the light (the open ray for a directional light) against every face's closed
/// polygon. A face is the polygon the engine computes on: its exact plane is the one through
/// the vertex average with the exact Newell normal (the plane itself for an exactly planar face,
/// the "lift" of docs/numeric-contract.md otherwise) and its outline keeps the input chart
/// coordinates. Every face counts, whether its mesh receives or not. `exact_lit_area` and
/// `exact_shadow_area` are the engine's exact results (they call compute_shadows and
/// compute_plane_shadows): they are the reference values, checked against closed forms and
/// against the oracles in libshadow's own tests (tests/testing-kit/test_testing_kit.cpp).
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace shadow::testing {

/// What a checker found: `ok`, or a readable explanation of the first (or worst) violation.
struct Verdict {
  bool ok = true;
  std::string message;  ///< empty when ok; otherwise one or more lines naming face, light, numbers
  explicit operator bool() const { return ok; }
};

// ---- exact oracles ---------------------------------------------------------------------------

/// Is `point` (as given in doubles) lit by scene light `light_id`? Decided exactly.
/// - The point is lit when every face that exactly contains it (closed polygon, on its exact
///   plane) has its front strictly toward the light, and no face blocks the open segment from
///   the point to the light (open ray for a directional light).
/// - A face blocks when the segment crosses its plane at one point that lies in its closed
///   polygon: a point on a shadow boundary (the segment grazes an occluder's edge or vertex) is
///   shadowed. A face seen edge-on (the segment in its plane) blocks nothing (its shadow has no
///   area), nor does a face touched only at the segment's ends (a lamp on a plane, the point's
///   own faces). Degenerate faces (zero Newell normal) neither block nor receive.
/// - A point on a receiver facing away from the light, or exactly parallel to it (grazing), is
///   not lit: the engine gives such faces no lit area. On an edge shared by a face toward the
///   light and one away from it the point is not lit (use is_lit_on_face to ask per face).
/// - A point on no face is lit when nothing blocks: visibility in free space.
/// - Each call prepares every face in rationals; for many queries use ExactOracle.
/// @throws InputError when `light_id` is not a scene light or the light is unusable.
bool is_lit(const Scene& scene, glm::dvec3 point, std::size_t light_id);

/// Is `point`, taken as a point of face `face_id`, lit by light `light_id`? The point is first
/// moved exactly onto the face's exact plane along the face's dominant axis (keeping its two
/// chart coordinates), so points rounded off the plane, e.g. sampled in doubles, still count as
/// on the face. Then: not lit when the face's front does not strictly face the light, otherwise
/// lit unless a face blocks (as in is_lit). Whether the point lies inside the face's outline is
/// not checked (see on_face).
/// @throws InputError for a bad face_id or light_id, or a degenerate face.
bool is_lit_on_face(const Scene& scene, std::size_t face_id, glm::dvec3 point, std::size_t light_id);

/// Does `point` lie exactly on face `face_id` (on its exact plane and in its closed polygon)?
/// @throws InputError for a bad face_id.
bool on_face(const Scene& scene, std::size_t face_id, glm::dvec3 point);

/// The exact point oracles over one scene whose faces are prepared once (exact planes, outlines
/// and outward-rounded bounding boxes that skip faces a segment cannot meet): for many queries.
/// Same answers as the free functions, which build one per call. The scene must outlive it and
/// stay unchanged.
class ExactOracle {
 public:
  explicit ExactOracle(const Scene& scene);
  ~ExactOracle();
  ExactOracle(ExactOracle&&) noexcept;
  ExactOracle& operator=(ExactOracle&&) noexcept;
  ExactOracle(const ExactOracle&) = delete;
  ExactOracle& operator=(const ExactOracle&) = delete;

  /// is_lit(scene, point, light_id).
  [[nodiscard]] bool is_lit(glm::dvec3 point, std::size_t light_id) const;
  /// is_lit_on_face(scene, face_id, point, light_id).
  [[nodiscard]] bool is_lit_on_face(std::size_t face_id, glm::dvec3 point, std::size_t light_id) const;
  /// on_face(scene, face_id, point).
  [[nodiscard]] bool on_face(std::size_t face_id, glm::dvec3 point) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The exact lit area of face `face_id` under light `light_id`, rounded once: the engine's
/// exact result (compute_shadows, Arithmetic::Exact, on this face's mesh and this light only),
/// the reference value. Any face is computed, whether its mesh receives or not.
/// @throws InputError for bad ids or an unusable scene.
double exact_lit_area(const Scene& scene, std::size_t face_id, std::size_t light_id);

/// The exact area of the shadow that the scene casts on its plane `plane_id` from light
/// `light_id`, inside the plane's window, rounded once: the engine's exact Blinn projection
/// (compute_plane_shadows), the reference value.
/// @throws InputError for bad ids or an unusable scene.
double exact_shadow_area(const Scene& scene, std::size_t plane_id, std::size_t light_id);

/// Up to `count` points spread uniformly over face `face_id` (rejection sampling in the face's
/// chart, lifted onto its plane in doubles), seeded: the same seed gives the same points. Thin
/// faces may yield fewer. For approximate methods that sample a face (shadow rays).
std::vector<glm::dvec3> sample_face(const Scene& scene, std::size_t face_id, std::size_t count,
                                    std::uint64_t seed);

// ---- invariant checkers ----------------------------------------------------------------------

/// Lit and shadowed parts partition each face: for every FaceLighting, lit_area + shadow_area
/// equals area (each rounded once from exact values: within 4e-16 of the area, relative), the
/// fraction is in [0, 1]; with fragments, each cell's double polygon has its stated area
/// (1e-12 (1 + area) plus what rounding its vertices can move: 2 eps perimeter max|x|) and its
/// face's orientation (unless rounding flattened it), and the cells of (face, light) plus
/// dropped_area add up to the area and the lit cells to lit_area (1e-12 (1 + area): cell areas
/// are rounded one by one; plus the error bound of a fast-path result). For an extended light
/// the lit cells add up to fully_lit_area + penumbra_area instead (lit_area is the centre's), and
/// fully_lit_area + penumbra_area + umbra_area to the area.
Verdict check_partition(const Scene& scene, const ShadowResult& result);

/// Lit claims agree with exact point queries: `points_per_fragment` points sampled inside each
/// fragment (at least 1e-7 of the fragment's size plus 16 ulps of its largest coordinate away
/// from its rounded boundary) must get the
/// fragment's lit/shadowed verdict from is_lit_on_face. Seeded. Needs result fragments; fails
/// when there are fragments but no point could be sampled in any of them (nothing checked).
Verdict check_lit_claims(const Scene& scene, const ShadowResult& result, std::uint64_t seed,
                         int points_per_fragment = 3);

/// A similarity that is exact in doubles as far as possible: quarter turns about the axes
/// (applied x, then y, then z), scaling by 2^scale_exponent (both exact), then a translation
/// (exact when the translated coordinates are representable, e.g. grid coordinates and a
/// power-of-two offset; otherwise rounded once).
struct Similarity {
  int quarter_turns_x = 0;
  int quarter_turns_y = 0;
  int quarter_turns_z = 0;
  int scale_exponent = 0;
  glm::dvec3 translation{0.0};
};

/// The scene moved by `s`: every face vertex, point light position and plane point; directional
/// lights and plane normals are rotated. Names, meshes and everything else are kept.
Scene transformed(const Scene& scene, const Similarity& s);

/// Results are invariant under `s`: each face's lit fraction under each light, computed by
/// `compute` (default: compute_shadows with polygons off), differs by at most `tolerance`
/// between the scene and its transform. Quarter turns and power-of-two scalings are exact, so
/// the exact engine must agree to the last bit there (tolerance 0 is fair); translations that
/// round need a tolerance of the order of the rounding.
Verdict check_invariance(const Scene& scene, const Similarity& s, double tolerance,
                         const std::function<ShadowResult(const Scene&)>& compute = {});

/// Monotone when an occluder is added: appending `occluder` (its faces, in a new non-receiving
/// mesh) must not increase any face's lit area under any light by more than `tolerance`, nor
/// drop any face-light entry.
Verdict check_monotone_occluder(const Scene& scene, const std::vector<std::vector<glm::dvec3>>& occluder,
                                double tolerance = 0.0);

// ---- comparing an approximate method -------------------------------------------------------

/// The outcome of comparing an approximate method's lit fractions with the exact ones.
struct Comparison {
  bool ok = true;               ///< every pair within tolerance
  std::size_t pairs = 0;        ///< face-light pairs compared
  std::size_t worst_face = 0;   ///< the pair with the largest error
  std::size_t worst_light = 0;
  std::string worst_label;      ///< the worst face's name, else its source (file: place), else face_<id>
  double approximate = 0.0;     ///< its approximate lit fraction
  double exact = 0.0;           ///< its exact lit fraction
  double error = 0.0;           ///< |approximate - exact|
  double tolerance = 0.0;
  std::uint64_t seed = 0;       ///< the seed the scene (and the method's sampling) came from
  /// Several lines: verdict, worst face and its numbers, and how to reproduce with the seed.
  [[nodiscard]] std::string report() const;
  explicit operator bool() const { return ok; }
};

/// An approximate lit fraction of face `face_id` under light `light_id` of `scene`.
using LitFractionMethod = std::function<double(const Scene& scene, std::size_t face_id, std::size_t light_id)>;

/// Compares `approximate` with the exact lit fraction on every receiving face (front-facing or
/// not) and every scene light; `seed` is only recorded, for the report. The scene must be valid.
Comparison compare_lit_fractions(const Scene& scene, const LitFractionMethod& approximate,
                                 double tolerance, std::uint64_t seed);

}  // namespace shadow::testing
