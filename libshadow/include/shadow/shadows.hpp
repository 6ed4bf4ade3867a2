// SPDX-License-Identifier: GPL-3.0-or-later
/// @file shadows.hpp
/// @brief Exact lit and shadowed polygons on every face for every light.
///
/// For each receiving face P and light L, the face is split into lit and shadowed "detail
/// polygons" (Atherton, Weiler and Greenberg, 1978), computed with exact rational arithmetic:
/// every other face Q is clipped to the part of space strictly between P's plane and the light,
/// projected from the light onto P's plane, and the projections are united in one aggregated
/// exact Boolean operation. Areas are exact rationals until they are rounded once to double.
/// See docs/algorithm.md and docs/numeric-contract.md.
#pragma once

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace shadow {

/// Progress of a long computation: `done` of `total` work items (face-light pairs).
struct Progress {
  std::size_t done = 0;
  std::size_t total = 0;
};

/// Options for computing shadows on faces.
struct ShadowOptions {
  /// Worker threads; 0 means every hardware thread. Results do not depend on it.
  unsigned threads = 0;
  /// Produce the 3D lit/shadow polygons. When false only areas are computed (cheaper).
  bool polygons = true;
  /// Indices of the scene lights to compute; empty means every light.
  std::vector<std::size_t> lights;
  /// Called now and then from one thread at a time (never concurrently). May be empty.
  std::function<void(const Progress&)> progress;
};

/// One simple polygon of a face that is wholly lit or wholly shadowed by one light.
/// A lit or shadowed region with holes is split into several simple cells that share
/// `fragment_id`. The polygon has the orientation of its face.
struct Fragment {
  std::size_t face_id = 0;
  std::size_t light_id = 0;
  std::size_t fragment_id = 0;  ///< numbers connected regions; pieces of one region share it
  bool lit = false;
  std::vector<glm::dvec3> polygon;
  double area = 0.0;            ///< exact area of this cell, rounded once
};

/// Lit and shadowed areas of one receiving face under one light.
struct FaceLighting {
  std::size_t face_id = 0;
  std::size_t light_id = 0;
  double area = 0.0;          ///< area of the face
  double lit_area = 0.0;      ///< exact lit area, rounded once
  double shadow_area = 0.0;   ///< exact shadowed area (area - lit_area exactly), rounded once
  double lit_fraction = 0.0;  ///< exact lit_area / area, rounded once (0 for zero-area faces)
  bool faces_light = false;   ///< the face's front looks toward the light
};

/// Counters that show how much work culling saved.
struct ShadowStats {
  std::uint64_t receivers = 0;          ///< face-light pairs considered
  std::uint64_t back_facing = 0;        ///< pairs in attached shadow (no clipping needed)
  std::uint64_t candidate_pairs = 0;    ///< occluder-receiver pairs after bounding-box culling
  std::uint64_t casting_pairs = 0;      ///< pairs whose exact projection was non-empty
  std::uint64_t unshadowed = 0;         ///< front-facing receivers with nothing in front (no clipping)
};

/// Everything computed for a scene's faces.
struct ShadowResult {
  /// One entry per receiving face and computed light, ordered by face_id then light_id.
  std::vector<FaceLighting> lighting;
  /// Lit and shadowed polygons, ordered by face_id, then light_id, then fragment_id.
  std::vector<Fragment> fragments;
  ShadowStats stats;

  /// The entry for (face, light), or nullptr when that pair was not computed.
  [[nodiscard]] const FaceLighting* find(std::size_t face_id, std::size_t light_id) const;
};

/// One call: validate-free computation of every selected light on every receiving face.
/// The scene must have been validated (load_scene does it; see validate_scene).
/// @throws InputError if a light or face is unusable (zero direction, NaN, ...).
ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options = {});

/// Reusable engine over one scene: exact face data (planes, charts, convex pieces, bounding
/// boxes) is prepared once and reused for every light, e.g. many sun positions over a day.
class ShadowEngine {
 public:
  /// Prepares the scene. The scene must outlive the engine and stay unchanged.
  explicit ShadowEngine(const Scene& scene);
  ~ShadowEngine();
  ShadowEngine(ShadowEngine&&) noexcept;
  ShadowEngine& operator=(ShadowEngine&&) noexcept;
  ShadowEngine(const ShadowEngine&) = delete;
  ShadowEngine& operator=(const ShadowEngine&) = delete;

  /// The scene's own lights (options.lights selects among them).
  [[nodiscard]] ShadowResult compute(const ShadowOptions& options = {}) const;

  /// Any light, not necessarily in the scene; results carry `light_id`.
  [[nodiscard]] ShadowResult compute(const Light& light, std::size_t light_id,
                                     const ShadowOptions& options = {}) const;

  /// Exact area of a face, rounded once (0 for degenerate faces).
  [[nodiscard]] double face_area(std::size_t face_id) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace shadow
