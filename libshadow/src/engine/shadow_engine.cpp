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
#include "geometry/box_sides.hpp"
#include "exact/convex_solids.hpp"
#include "core/culling.hpp"
#include "exact/exact_faces.hpp"
#include "exact/lazy_geometry.hpp"
#include "exact/leaf_projector.hpp"
#include "core/parallel.hpp"
#include "planes/plane_shadows.hpp"
#include "exact/regions.hpp"
#include "fast/fast_receiver.hpp"
#include "core/input_checks.hpp"
#include "core/lights.hpp"

#include <shadow/shadows.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>

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

struct ShadowEngine::Impl {
  const Scene* scene = nullptr;
  std::vector<exact::FacePrep> prep;
  std::vector<double> face_area;
  exact::CullScene cull;

  std::vector<exact::ConvexSolid> solids;
  std::vector<int> solid_of;  ///< per face: index into solids, or -1

  /// Per-thread exact state. Epeck objects are never shared between threads.
  struct Worker {
    std::vector<std::unique_ptr<exact::ExactFace>> faces;  // built on first use
    exact::CasterCandidates casters;
    ShadowStats stats;
    std::vector<exact::Point3> poly, scratch;
    std::vector<exact::Point2> poly2, scratch2;
    std::vector<CGAL::Sign> vertex_sign, piece_sign;
    fast::Worker fast;  // Arithmetic::Fast: the fast path's scratch state
  };

  const exact::ExactFace& exact_face(Worker& w, std::size_t f) const {
    if (!w.faces[f])
      w.faces[f] = std::make_unique<exact::ExactFace>(
          exact::make_exact_face(scene->faces[f].vertices, prep[f]));
    return *w.faces[f];
  }

  /// Result for one receiving face under one light.
  struct Item {
    FaceLighting lighting;
    std::vector<Fragment> fragments;  // fragment_id local to the item
  };

  void compute_light(const Light& light, std::size_t light_id, const ShadowOptions& options,
                     std::vector<Worker>& workers, const std::vector<std::size_t>& receivers,
                     std::vector<Item>& items, std::size_t progress_base, std::size_t progress_total) const;

  /// Computes `lights` (reported as `light_ids`) on every receiving face.
  ShadowResult run(const std::vector<const Light*>& lights, const std::vector<std::size_t>& light_ids,
                   const ShadowOptions& options) const;

  static ShadowResult assemble(std::vector<std::vector<Item>>& per_light,
                               const std::vector<Worker>& workers);

  Item compute_receiver(Worker& w, std::size_t face_id, std::size_t light_id,
                        const exact::ExactLight& light, int facing, const Light& light_in,
                        const exact::LightSpaceGrid* grid, bool polygons) const;
};


ShadowEngine::ShadowEngine(const Scene& scene, unsigned threads) : impl_(std::make_unique<Impl>()) {
  // Scenes built in code may not have been validated: NaN or huge coordinates would reach GMP
  // (SIGFPE) or the double culling. One pass over the vertices.
  shadow::detail::check_scene_numbers(scene);
  threads = exact::checked_threads(threads);
  impl_->scene = &scene;
  const std::size_t n = scene.faces.size();
  impl_->prep.resize(n);
  impl_->face_area.assign(n, 0.0);
  exact::parallel_for(n, exact::resolve_threads(threads), [&](unsigned, std::size_t f) {
    const Face& face = scene.faces[f];
    exact::FacePrep& prep = impl_->prep[f];
    if (face.degenerate || face.vertices.size() < 3) {
      prep.degenerate = true;
      return;
    }
    prep = exact::prepare_face(face.vertices);
    if (prep.degenerate) return;
    const exact::ExactFace ef = exact::make_exact_face(face.vertices, prep);
    impl_->face_area[f] = exact::area_3d(ef.chart_area, ef.area_scale_squared);
  });
  impl_->cull = exact::make_cull_scene(scene, impl_->prep);
  impl_->solids = exact::find_convex_solids(scene, impl_->prep, impl_->solid_of);
}

ShadowEngine::~ShadowEngine() = default;
ShadowEngine::ShadowEngine(ShadowEngine&&) noexcept = default;
ShadowEngine& ShadowEngine::operator=(ShadowEngine&&) noexcept = default;

double ShadowEngine::face_area(std::size_t face_id) const { return impl_->face_area.at(face_id); }

std::vector<PlaneShadow> ShadowEngine::compute_planes(const ShadowOptions& options) const {
  return exact::plane_shadows(*impl_->scene, impl_->prep, options);
}

namespace {

exact::ExactLight to_exact_light(const Light& light) {
  using exact::FT;
  if (light.type == LightType::Point)
    return {{FT(light.position.x), FT(light.position.y), FT(light.position.z), FT(1)}};
  return {{FT(light.to_light.x), FT(light.to_light.y), FT(light.to_light.z), FT(0)}};
}

/// The face's own outline as one fragment (wholly lit or wholly in shadow).
Fragment whole_face_fragment(const Face& face, std::size_t face_id, std::size_t light_id, bool lit,
                             double area, const exact::FacePrep& prep, const exact::ExactFace* ef) {
  Fragment fragment;
  fragment.face_id = face_id;
  fragment.light_id = light_id;
  fragment.lit = lit;
  fragment.area = area;
  if (prep.exactly_planar || ef == nullptr) {
    fragment.polygon = face.vertices;
  } else {
    for (const exact::Point3& p : ef->vertices)
      fragment.polygon.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()),
                                    CGAL::to_double(p.z()));
  }
  return fragment;
}

}  // namespace

ShadowEngine::Impl::Item ShadowEngine::Impl::compute_receiver(
    Worker& w, std::size_t face_id, std::size_t light_id, const exact::ExactLight& light,
    int facing, const Light& light_in, const exact::LightSpaceGrid* grid, bool polygons) const {
  using namespace exact;
  Item item;
  FaceLighting& out = item.lighting;
  out.face_id = face_id;
  out.light_id = light_id;
  out.area = face_area[face_id];
  ++w.stats.receivers;
  const Face& face = scene->faces[face_id];
  const FacePrep& fp = prep[face_id];
  if (fp.degenerate) return item;  // zero area: nothing to light

  if (facing <= 0) {  // attached shadow: the front looks away from the light (or edge-on)
    ++w.stats.back_facing;
    out.shadow_area = out.area;
    if (polygons)
      item.fragments.push_back(whole_face_fragment(face, face_id, light_id, false, out.area, fp,
                                                   fp.exactly_planar ? nullptr : &exact_face(w, face_id)));
    return item;
  }
  out.faces_light = true;

  // ---- culling in doubles -------------------------------------------------------------------
  const ReceiverCuller culler(cull, fp, face_id, light_in);
  const std::vector<std::size_t>& candidates = w.casters.gather(culler, prep, face_id, grid);
  w.stats.candidate_pairs += candidates.size();

  // ---- exact clipping and projection ---------------------------------------------------------
  // The receiver's exact frame is built on first use: most receivers are decided by the
  // predicates below alone (nothing strictly in front of them).
  std::optional<ReceiverFrame> frame_storage;
  auto exact_frame = [&]() -> const ReceiverFrame& {
    if (!frame_storage) {
      const ExactFace& receiver = exact_face(w, face_id);
      frame_storage = make_frame(receiver, fp, light, plane_at_light(receiver, light));
    }
    return *frame_storage;
  };
  // Signs of s (the receiver's plane) at input vertices are decided by Epick's orientation
  // predicate on the doubles: exact, and cheap even when the answer is zero, which is common
  // (faces that share an edge with the receiver). Lazy Epeck arithmetic would have to
  // evaluate every zero exactly.
  using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto epick = [](const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); };
  const EK::Point_3 corner0 = epick(face.vertices[fp.corner[1]]);
  const EK::Point_3 corner1 = epick(face.vertices[fp.corner[2]]);
  const EK::Point_3 corner2 = epick(face.vertices[fp.corner[0]]);
  const bool point_light = light.is_point();
  std::optional<LeafProjector> projector_storage;
  auto leaf_projector = [&]() -> LeafProjector& {
    if (!projector_storage) projector_storage.emplace(face.vertices, fp, light_in);
    return *projector_storage;
  };
  std::vector<Polygon2> shadows;
  const int own_solid = solid_of[face_id];
  for (std::size_t q : candidates) {
    const int solid = solid_of[q];
    if (solid >= 0 && (solid == own_solid || w.casters.solid_done(solid))) continue;
    if (solid >= 0 && !point_light && fp.exactly_planar) {
      // A convex solid casts the hull of its projection (see ConvexSolid).
      w.casters.mark_solid_done(solid);
      const exact::ConvexSolid& cs = solids[solid];
      w.vertex_sign.resize(cs.vertices.size());
      bool any_front = false;
      for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
        CGAL::Sign sv = CGAL::orientation(corner0, corner1, corner2, epick(cs.vertices[v]));
        if (fp.flipped) sv = CGAL::opposite(sv);
        w.vertex_sign[v] = sv;
        any_front |= sv == CGAL::POSITIVE;
      }
      if (!any_front) continue;
      LeafProjector& projector = leaf_projector();
      w.poly2.clear();
      for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
        if (w.vertex_sign[v] == CGAL::POSITIVE) w.poly2.push_back(projector.project(cs.vertices[v]));
        if (w.vertex_sign[v] == CGAL::ZERO) w.poly2.push_back(projector.chart(cs.vertices[v]));
      }
      for (const auto& [a, b] : cs.edges) {
        const CGAL::Sign sa = w.vertex_sign[a], sb = w.vertex_sign[b];
        if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE))
          w.poly2.push_back(projector.crossing(cs.vertices[a], cs.vertices[b]));
      }
      w.scratch2.clear();
      CGAL::convex_hull_2(w.poly2.begin(), w.poly2.end(), std::back_inserter(w.scratch2), Kernel());
      w.poly2.swap(w.scratch2);
      for (int c = 0; c < 2; ++c) {
        clip_convex_2d(w.poly2, c, fp.chart_min[c], true, w.scratch2);
        clip_convex_2d(w.poly2, c, fp.chart_max[c], false, w.scratch2);
      }
      if (w.poly2.size() < 3) continue;
      Polygon2 projected(w.poly2.begin(), w.poly2.end());
      if (CGAL::sign(polygon_area(projected)) != CGAL::POSITIVE) continue;  // flat: edge-on solid
      shadows.push_back(std::move(projected));
      ++w.stats.casting_pairs;
      continue;
    }
    const FacePrep& qp = prep[q];
    const Face& qface = scene->faces[q];
    w.vertex_sign.resize(qface.vertices.size());
    bool any_front = false;
    if (point_light) {
      // A caster whose plane contains the light is edge-on to it and casts nothing; projecting
      // it would divide by zero where it touches the light.
      const bool edge_on =
          qp.exactly_planar
              ? CGAL::orientation(epick(qface.vertices[qp.corner[1]]), epick(qface.vertices[qp.corner[2]]),
                                  epick(qface.vertices[qp.corner[0]]), epick(light_in.position)) == CGAL::COPLANAR
              : CGAL::is_zero(plane_at_light(exact_face(w, q), light));
      if (edge_on) continue;
    }
    // Two routes to the same exact polygons: exact leaves straight from the input doubles when
    // both faces are exactly planar (the common case), lazy Epeck values for lifted faces.
    const bool leaves = fp.exactly_planar && qp.exactly_planar;
    const ExactFace* Q = nullptr;
    const ReceiverFrame* frame = nullptr;
    if (leaves) {
      for (std::size_t v = 0; v < qface.vertices.size(); ++v) {
        CGAL::Sign sv = CGAL::orientation(corner0, corner1, corner2, epick(qface.vertices[v]));
        if (fp.flipped) sv = CGAL::opposite(sv);
        w.vertex_sign[v] = sv;
        any_front |= sv == CGAL::POSITIVE;
      }
    } else {
      Q = &exact_face(w, q);
      frame = &exact_frame();
      for (std::size_t v = 0; v < Q->vertices.size(); ++v) {
        w.vertex_sign[v] = CGAL::sign(frame->front(Q->vertices[v]));
        any_front |= w.vertex_sign[v] == CGAL::POSITIVE;
      }
    }
    if (!any_front) continue;  // nothing strictly in front of the receiver
    bool cast = false;
    for (const std::vector<int>& piece : qp.convex_pieces) {
      w.piece_sign.clear();
      bool piece_front = false;
      for (int v : piece) {
        w.piece_sign.push_back(w.vertex_sign[v]);
        piece_front |= w.vertex_sign[v] == CGAL::POSITIVE;
      }
      if (!piece_front) continue;
      if (leaves) {
        leaf_projector().project_piece(qface.vertices, piece, w.piece_sign, w.poly2);
      } else {
        w.poly.clear();
        for (int v : piece) w.poly.push_back(Q->vertices[v]);
        if (point_light) {
          // The pyramid over the chart box keeps the central projection finite.
          clip_front(w.poly, w.piece_sign, frame->front, w.scratch);
          for (const Affine3& side : frame->sides) clip_convex(w.poly, side, w.scratch);
          w.poly2.clear();
          for (const Point3& y : w.poly) w.poly2.push_back(project_to_chart(y, *frame, light));
        } else {
          project_front_part(w.poly, w.piece_sign, *frame, light, w.poly2);
        }
      }
      if (!point_light) {  // parallel projection is affine: clip to the chart box in 2D
        for (int c = 0; c < 2; ++c) {
          clip_convex_2d(w.poly2, c, fp.chart_min[c], true, w.scratch2);
          clip_convex_2d(w.poly2, c, fp.chart_max[c], false, w.scratch2);
        }
      }
      if (w.poly2.size() < 3) continue;
      Polygon2 projected(w.poly2.begin(), w.poly2.end());
      const CGAL::Sign orientation = CGAL::sign(polygon_area(projected));
      if (orientation == CGAL::ZERO) continue;  // the caster is edge-on to the light
      if (orientation == CGAL::NEGATIVE) projected.reverse_orientation();
      shadows.push_back(std::move(projected));
      cast = true;
    }
    if (cast) ++w.stats.casting_pairs;
  }

  const ExactFace& P = exact_face(w, face_id);
  if (shadows.empty()) {  // nothing in front: wholly lit, no Boolean operation needed
    ++w.stats.unshadowed;
    out.lit_area = out.area;
    out.lit_fraction = 1.0;
    if (polygons) item.fragments.push_back(whole_face_fragment(face, face_id, light_id, true, out.area, fp, &P));
    return item;
  }

  std::vector<PolygonWithHoles2> shadow_regions, lit_regions;
  PolygonSet2 shadow_set;
  if (shadows.size() == 1 && fp.chart_is_box) {
    // One convex caster already clipped to a rectangular receiver: it is the shadow.
    shadow_regions.emplace_back(shadows.front());
    if (polygons) shadow_set.insert(shadows.front());
  } else {
    shadow_set.join(shadows.begin(), shadows.end());  // one aggregated union
    if (!fp.chart_is_box) shadow_set.intersection(P.chart);
    shadow_set.polygons_with_holes(std::back_inserter(shadow_regions));
  }
  std::vector<FT> region_areas;
  for (const PolygonWithHoles2& r : shadow_regions) region_areas.push_back(region_area(r));
  const FT shadow_chart_area = balanced_sum(region_areas);
  const FT lit_chart_area = P.chart_area - shadow_chart_area;
  out.lit_area = area_3d(lit_chart_area, P.area_scale_squared);
  out.shadow_area = area_3d(shadow_chart_area, P.area_scale_squared);
  out.lit_fraction = round_to_double(lit_chart_area / P.chart_area);
  if (!polygons) return item;

  PolygonSet2 lit_set(P.chart);
  lit_set.difference(shadow_set);
  lit_set.polygons_with_holes(std::back_inserter(lit_regions));

  std::size_t fragment_id = 0;
  std::vector<Polygon2> cells, triangles;
  std::vector<FT> dropped;  // exact chart areas of cells too thin to write (see below)
  // One cell as a fragment, if its vertices rounded to doubles still make one simple polygon of
  // non-zero area (the output contract); false, writing nothing, otherwise.
  auto write = [&](const Polygon2& cell, const FT& cell_area, bool lit) {
    Fragment fragment;
    fragment.face_id = face_id;
    fragment.light_id = light_id;
    fragment.fragment_id = fragment_id;
    fragment.lit = lit;
    fragment.area = area_3d(CGAL::abs(cell_area), P.area_scale_squared);
    for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
      const Point3 p = lift(*v, P, fp.axis);
      fragment.polygon.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    }
    // The chart sees the face clockwise when flipped: restore the face's orientation.
    if (fp.flipped == CGAL::is_positive(cell_area)) std::reverse(fragment.polygon.begin(), fragment.polygon.end());
    if (!clean_double_polygon(fragment.polygon, fp.axis)) return false;
    item.fragments.push_back(std::move(fragment));
    return true;
  };
  auto emit = [&](const std::vector<PolygonWithHoles2>& regions, bool lit) {
    for (const PolygonWithHoles2& region : regions) {
      cells.clear();
      append_simple_cells(region, cells);
      const std::size_t written = item.fragments.size();
      for (Polygon2& cell : cells) {
        const FT cell_area = polygon_area(cell);
        if (write(cell, cell_area, lit)) continue;
        // Rounding broke the cell (a sliver a few ulps wide, or a spike that now crosses an
        // edge): write its triangles instead, and leave out those that collapse, accounting
        // for their exact area in dropped_area.
        if (CGAL::is_negative(cell_area)) cell.reverse_orientation();
        triangles.clear();
        triangulate_region(PolygonWithHoles2(cell), triangles);
        for (const Polygon2& t : triangles) {
          const FT t_area = polygon_area(t);
          if (!write(t, t_area, lit)) dropped.push_back(CGAL::abs(t_area));
        }
      }
      if (item.fragments.size() > written) ++fragment_id;  // ids stay consecutive
    }
  };
  emit(lit_regions, true);
  emit(shadow_regions, false);
  if (!dropped.empty()) out.dropped_area = area_3d(balanced_sum(dropped), P.area_scale_squared);
  return item;
}

void ShadowEngine::Impl::compute_light(const Light& light_in, std::size_t light_id,
                                       const ShadowOptions& options, std::vector<Worker>& workers,
                                       const std::vector<std::size_t>& receivers,
                                       std::vector<Item>& items, std::size_t progress_base,
                                       std::size_t progress_total) const {
  using namespace exact;
  shadow::detail::check_light(light_in, "", "lights[" + std::to_string(light_id) + "]");
  const unsigned threads = static_cast<unsigned>(workers.size());
  std::optional<LightSpaceGrid> grid;
  if (light_in.type == LightType::Directional) grid.emplace(cull, prep, light_in.to_light);

  std::function<void(std::size_t)> report;
  if (options.progress)
    report = [&](std::size_t done) { options.progress(Progress{progress_base + done, progress_total}); };

  std::vector<std::optional<ExactLight>> lights(threads);
  const bool fast = options.arithmetic == Arithmetic::Fast;
  const fast::Context fast_context{scene, &prep, &face_area, &cull, &solids, &solid_of};
  parallel_for(
      receivers.size(), threads,
      [&](unsigned wi, std::size_t r) {
        Worker& w = workers[wi];
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
        if (!lights[wi]) lights[wi] = to_exact_light(light_in);
        const ExactLight& light = *lights[wi];
        const std::size_t f = receivers[r];
        int side = 0;
        if (!prep[f].degenerate) side = CGAL::sign(plane_at_light(exact_face(w, f), light));
        items[r] = compute_receiver(w, f, light_id, light, side, light_in,
                                    grid ? &*grid : nullptr, options.polygons);
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
  std::vector<Worker> workers(exact::resolve_threads(exact::checked_threads(options.threads)));
  for (Worker& w : workers) {
    w.faces.resize(scene->faces.size());
    w.casters.reset(scene->faces.size(), solids.size());
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
  return impl_->run({&light}, {light_id}, options);
}

ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options) {
  const ShadowEngine engine(scene, options.threads);
  ShadowResult result = engine.compute(options);
  if (options.planes) result.plane_shadows = engine.compute_planes(options);
  return result;
}

}  // namespace shadow
