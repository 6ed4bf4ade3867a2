// SPDX-License-Identifier: GPL-3.0-or-later
// The exact shadow engine (Atherton-Weiler-Greenberg, made exact).
//
// For a receiving face P that faces the light, a point X of P is in shadow exactly when the
// open segment from X to the light meets another face. That segment lies in the open slab
// between P's plane and the light, so
//
//   shadow(P) = P  intersected with  union over Q of  project_P(Q  clipped to that slab),
//
// where project_P is the projection from the light onto P's plane (Blinn's matrix for P's
// plane). No depth order is needed; cyclic overlap and interpenetration need no special case.
// Clipping Q also to the pyramid (point light) or prism (directional light) over P's chart
// bounding box keeps the projection finite and the union small. Everything is done with exact
// rationals (Epeck) in P's 2D chart; doubles appear only in culling (conservatively) and at
// the output.
//
// This file is the engine: ShadowEngine prepares the faces once (core/, exact/), dispatches each
// receiver to the fast path (fast/, Arithmetic::Fast) or the exact computation
// (exact/exact_receiver.cpp, also the fast path's fallback), and assembles the result;
// compute_shadows and find_lighting.
#include "engine/engine_impl.hpp"

#include "core/culling.hpp"
#include "core/input_checks.hpp"
#include "core/lights.hpp"
#include "core/parallel.hpp"
#include "engine/engine_access.hpp"
#include "exact/convex_solids.hpp"
#include "exact/exact_faces.hpp"
#include "exact/exact_receiver.hpp"
#include "exact/lazy_geometry.hpp"
#include "fast/fast_receiver.hpp"
#include "planes/plane_shadows.hpp"

#include <shadow/shadows.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace shadow {

const FaceLighting* find_lighting(const std::vector<FaceLighting>& lighting, std::size_t face_id,
                                  std::size_t light_id) {
  auto it = std::lower_bound(lighting.begin(), lighting.end(), std::make_pair(face_id, light_id),
                             [](const FaceLighting& l, const std::pair<std::size_t, std::size_t>& key) {
                               return std::make_pair(l.face_id, l.light_id) < key;
                             });
  if (it == lighting.end() || it->face_id != face_id || it->light_id != light_id) return nullptr;
  return &*it;
}

const FaceLighting* ShadowResult::find(std::size_t face_id, std::size_t light_id) const {
  return find_lighting(lighting, face_id, light_id);
}


// =============================================================================================

// ShadowEngine::Impl: engine/engine_impl.hpp (engine/series.cpp reads it too).


ShadowEngine::ShadowEngine(const Scene& scene, unsigned threads) : impl_(std::make_unique<Impl>()) {
  // Scenes built in code may not have been validated: NaN or huge coordinates would reach GMP
  // (SIGFPE) or the double culling. One pass over the vertices.
  shadow::detail::check_scene_numbers(scene);
  threads = core::checked_threads(threads);
  impl_->scene = &scene;
  const std::size_t n = scene.faces.size();
  impl_->prep.resize(n);
  impl_->face_area.assign(n, 0.0);
  core::parallel_for(n, core::resolve_threads(threads), [&](unsigned, std::size_t f) {
    const Face& face = scene.faces[f];
    core::FacePrep& prep = impl_->prep[f];
    if (face.degenerate || face.vertices.size() < 3) {
      prep.degenerate = true;
      return;
    }
    prep = exact::prepare_face(face.vertices);
    if (prep.degenerate) return;
    const exact::ExactFace ef = exact::make_exact_face(face.vertices, prep);
    impl_->face_area[f] = exact::area_3d(ef.chart_area, ef.area_scale_squared);
  });
  impl_->cull = core::make_cull_scene(scene, impl_->prep);
  impl_->solids = exact::find_convex_solids(scene, impl_->prep, impl_->solid_of);
}

ShadowEngine::~ShadowEngine() = default;
ShadowEngine::ShadowEngine(ShadowEngine&&) noexcept = default;
ShadowEngine& ShadowEngine::operator=(ShadowEngine&&) noexcept = default;

double ShadowEngine::face_area(std::size_t face_id) const { return impl_->face_area.at(face_id); }

std::vector<PlaneShadow> ShadowEngine::compute_planes(const ShadowOptions& options) const {
  return planes::plane_shadows(*impl_->scene, impl_->prep, impl_->solids, impl_->solid_of, options);
}


void ShadowEngine::Impl::compute_light(const Light& light_in, std::size_t light_id,
                                       const ShadowOptions& options, std::vector<Worker>& workers,
                                       const std::vector<std::size_t>& receivers,
                                       std::vector<Item>& items, std::size_t progress_base,
                                       std::size_t progress_total) const {
  using namespace exact;
  const unsigned threads = static_cast<unsigned>(workers.size());
  std::optional<core::LightSpaceGrid> grid;
  if (light_in.type == LightType::Directional) grid.emplace(cull, prep, light_in.to_light);

  std::function<void(std::size_t)> report;
  if (options.progress)
    report = [&](std::size_t done) { options.progress(Progress{progress_base + done, progress_total}); };

  std::vector<std::optional<ExactLight>> lights(threads);
  const bool fast = options.arithmetic == Arithmetic::Fast;
  const fast::Context fast_context{scene, &prep, &face_area, &cull, &solids, &solid_of};
  const exact::ExactContext exact_context{scene, &prep, &face_area, &cull, &solids, &solid_of};
  core::parallel_for(
      receivers.size(), threads,
      [&](unsigned wi, std::size_t r) {
        Worker& w = workers[wi];
        w.exact.trim(exact::kExactFaceCache);
        if (fast) {
          Item item;
          if (fast::compute_receiver(fast_context, w.fast, receivers[r], light_id, light_in,
                                     grid ? &*grid : nullptr, options.polygons, item.lighting,
                                     item.fragments, w.stats)) {
            items[r] = std::move(item);
            return;
          }
          ++w.stats.fast_exact_fallbacks;  // ill-conditioned in doubles: decided exactly below
        }
        if (!lights[wi]) lights[wi] = engine_detail::to_exact_light(light_in);
        const ExactLight& light = *lights[wi];
        const std::size_t f = receivers[r];
        int side = 0;
        if (!prep[f].degenerate) side = CGAL::sign(plane_at_light(w.exact.face(exact_context, f), light));
        items[r] = compute_exact_receiver(exact_context, w.exact, f, light_id, light, side, light_in,
                                          grid ? &*grid : nullptr, options.polygons, w.stats);
      },
      report);
}

ShadowResult ShadowEngine::Impl::assemble(std::vector<std::vector<Item>>& per_light,
                                          const std::vector<Worker>& workers) {
  ShadowResult result;
  const std::size_t lights = per_light.size();
  const std::size_t receivers = lights ? per_light[0].size() : 0;
  result.lighting.reserve(lights * receivers);
  std::size_t next_fragment_id = 0;
  for (std::size_t r = 0; r < receivers; ++r) {
    for (std::size_t li = 0; li < lights; ++li) {
      Item& item = per_light[li][r];
      result.lighting.push_back(item.lighting);
      std::size_t used = 0;
      for (Fragment& fragment : item.fragments) {
        used = std::max(used, fragment.fragment_id + 1);
        fragment.fragment_id += next_fragment_id;
        result.fragments.push_back(std::move(fragment));
      }
      next_fragment_id += used;
      item.fragments.clear();
      item.fragments.shrink_to_fit();
    }
  }
  for (const Worker& w : workers) {
    result.stats += w.stats;
  }
  return result;
}

ShadowResult ShadowEngine::Impl::run(const std::vector<const Light*>& lights,
                                     const std::vector<std::size_t>& light_ids,
                                     const ShadowOptions& options) const {
  std::vector<std::size_t> receivers;
  for (std::size_t f = 0; f < scene->faces.size(); ++f)
    if (scene->is_receiver(f)) receivers.push_back(f);
  std::vector<Worker> workers(core::resolve_threads(core::checked_threads(options.threads)));
  for (Worker& w : workers) {
    w.exact.reset(scene->faces.size(), solids.size());
    if (options.arithmetic == Arithmetic::Fast) w.fast.casters.reset(scene->faces.size(), solids.size());
  }
  std::vector<std::vector<Item>> per_light(lights.size(), std::vector<Item>(receivers.size()));
  const std::size_t total = lights.size() * receivers.size();
  for (std::size_t li = 0; li < lights.size(); ++li)
    compute_light(*lights[li], light_ids[li], options, workers, receivers, per_light[li],
                  li * receivers.size(), total);
  ShadowResult result = assemble(per_light, workers);
  result.arithmetic = options.arithmetic;
  return result;
}

ShadowResult ShadowEngine::compute(const ShadowOptions& options) const {
  const Scene& scene = *impl_->scene;
  const std::vector<std::size_t> light_ids = shadow::detail::resolve_lights(scene, options.lights);
  std::vector<const Light*> lights;
  for (std::size_t l : light_ids) lights.push_back(&scene.lights[l]);
  return impl_->run(lights, light_ids, options);
}

ShadowResult ShadowEngine::compute(const Light& light, std::size_t light_id,
                                   const ShadowOptions& options) const {
  // A light that need not be one of the scene's: checked here (resolve_lights checks the scene's).
  shadow::detail::check_light(light, "", "lights[" + std::to_string(light_id) + "]");
  return impl_->run({&light}, {light_id}, options);
}

namespace detail {

core::PreparedScene EngineAccess::prepared(const ShadowEngine& engine) {
  const ShadowEngine::Impl& impl = *engine.impl_;
  return {impl.scene, &impl.prep, &impl.face_area, &impl.cull, &impl.solids, &impl.solid_of};
}

}  // namespace detail

ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options) {
  const ShadowEngine engine(scene, options.threads);
  ShadowResult result = engine.compute(options);
  if (options.planes) result.plane_shadows = engine.compute_planes(options);
  return result;
}

}  // namespace shadow
