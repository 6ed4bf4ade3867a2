// SPDX-License-Identifier: GPL-3.0-or-later
// The exact sun-hours map (shadow/sun_hours.hpp, docs/sun-hours-map.md).
//
// Per receiving face, on one thread: the lit region of every instant, exactly as the exact
// engine computes it (exact/exact_receiver: casters, projection, one union, the chart minus
// it), is cut into directed boundary segments, the region on each segment's left. All of them,
// and the face's chart outline, go into one CGAL arrangement of the chart whose curves carry
// (instant, side) data, merged where boundaries of several instants overlap. A walk over the
// faces of the arrangement from the unbounded one then gives every face its hours: crossing an
// edge into instant i's region adds w_i, out of it subtracts w_i. Hours are summed as exact
// rationals (the weights are doubles), so equal sets of instants give equal hours, and the cost
// is the arrangement's size. Edges with equal hours on both sides are removed (touching cells
// of equal hours merge), and every remaining face is written like a fragment: simple cells
// (exact/regions.hpp), lifted to the face's plane, rounded once.
//
// Instants under which the face is wholly lit add their weight to the whole chart (no curves);
// wholly dark ones add nothing. So the arrangement holds only the instants whose shadow
// boundary crosses the face.
#include "core/culling.hpp"
#include "core/face_prep.hpp"
#include "core/lights.hpp"
#include "runtime/parallel.hpp"
#include "core/prepared_scene.hpp"
#include "engine/engine_access.hpp"
#include "exact/exact_faces.hpp"
#include "exact/exact_receiver.hpp"
#include "exact/lazy_geometry.hpp"
#include "exact/regions.hpp"

#include <shadow/series.hpp>

#include <shadow/error.hpp>
#include <shadow/sun_hours.hpp>

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>

#include <gmpxx.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <optional>
#include <string>
#include <utility>

namespace shadow {
namespace {

using namespace exact;

using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;
// A curve's data: +(i + 1) when instant i's lit region lies on the left of the segment run from
// its lexicographically smaller end to the larger, -(i + 1) when it lies on the right. Instant
// index `n` (the number of instants) stands for the face's chart outline.
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<SegmentTraits, long>;
using Dcel = CGAL::Arr_face_extended_dcel<Traits, long>;  // face data: index into the walk's values
using Arrangement = CGAL::Arrangement_2<Traits, Dcel>;


double round_mpq(const mpq_class& q) { return exact::round_mpq_to_double(q.get_mpq_t()); }

/// Adds the boundary of `polygon` (the region on its left) as curves tagged with `instant`.
void add_boundary(const Polygon2& polygon, long instant, std::vector<Traits::Curve_2>& curves) {
  const std::size_t n = polygon.size();
  for (std::size_t a = 0; a < n; ++a) {
    const Point2& p = polygon[a];
    const Point2& q = polygon[(a + 1) % n];
    if (p == q) continue;
    const long tag = CGAL::compare_xy(p, q) == CGAL::SMALLER ? instant + 1 : -(instant + 1);
    curves.emplace_back(Kernel::Segment_2(p, q), tag);
  }
}

template <class Circulator>
Polygon2 ccb_polygon(Circulator first) {
  Polygon2 polygon;
  auto h = first;
  do {
    polygon.push_back(h->source()->point());
  } while (++h != first);
  return polygon;
}

/// One face's part of the map (region ids local to the face, from 0).
struct FaceMap {
  std::vector<SunHoursCell> cells;
  SunHoursFace face;
  std::size_t regions = 0;
};

class FaceOverlay {
 public:
  FaceOverlay(const core::PreparedScene& ctx, const ExactFace& P, const core::FacePrep& fp, std::size_t face_id,
              const std::vector<double>& hours, bool merge)
      : ctx_(ctx), P_(P), fp_(fp), face_id_(face_id), hours_(hours), merge_(merge), n_(hours.size()) {
    exact_to_mpq(P.area_scale_squared, scale_.get_mpq_t());
  }

  /// An instant lights the whole face.
  void add_whole(std::size_t i) {
    base_ += mpq_class(hours_[i]);
    add_lit_area(i, P_.chart_area);
  }
  /// An instant lights part of the face: `lit` (in the chart), of exact area `lit_area`.
  void add_partial(std::size_t i, const PolygonSet2& lit, const FT& lit_area) {
    add_lit_area(i, lit_area);
    regions_.clear();
    lit.polygons_with_holes(std::back_inserter(regions_));
    for (const PolygonWithHoles2& r : regions_) {
      add_boundary(r.outer_boundary(), static_cast<long>(i), curves_);  // counter-clockwise
      for (auto h = r.holes_begin(); h != r.holes_end(); ++h) add_boundary(*h, static_cast<long>(i), curves_);  // clockwise
    }
  }

  FaceMap finish() {
    FaceMap out;
    out.face.face_id = face_id_;
    out.face.area = (*ctx_.face_area)[face_id_];
    out.face.instants_lit = lit_instants_;
    add_boundary(P_.chart, static_cast<long>(n_), curves_);
    Arrangement arr;
    CGAL::insert(arr, curves_.begin(), curves_.end());  // one sweep: not stopped inside
    curves_.clear();
    curves_.shrink_to_fit();
    runtime::check_stop();
    walk(arr);
    if (merge_) merge_equal(arr);
    runtime::check_stop();

    // The integral of hours over the face, sum over instants of w_i x lit area_i: the same exact
    // rational as the sum over the overlay's faces of hours x area (the tests check the cells
    // against it), and far cheaper: n terms whose areas the lit regions already evaluated,
    // instead of thousands of cell areas with unrelated denominators.
    out.face.hour_area = area_3d(balanced_sum(hour_area_terms_), P_.area_scale_squared);
    std::vector<Polygon2> cells;
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
      if (f->is_unbounded() || !inside_[f->data()]) continue;
      runtime::check_stop();
      PolygonWithHoles2 region(ccb_polygon(f->outer_ccb()));
      for (auto h = f->inner_ccbs_begin(); h != f->inner_ccbs_end(); ++h) region.add_hole(ccb_polygon(*h));
      const double sun_hours = round_mpq(hours_at_[f->data()]);
      cells.clear();
      append_simple_cells(region, cells);
      const std::size_t before = out.cells.size();
      for (Polygon2& cell : cells) emit(cell, sun_hours, out);
      if (out.cells.size() > before) {
        for (std::size_t c = before; c < out.cells.size(); ++c) out.cells[c].region_id = out.regions;
        ++out.regions;
      }
    }
    out.face.dropped_area = area_3d_mpq(dropped_);
    return out;
  }

 private:
  void add_lit_area(std::size_t i, const FT& lit_area) {
    ++lit_instants_;
    if (hours_[i] != 0 && !CGAL::is_zero(lit_area)) hour_area_terms_.push_back(FT(hours_[i]) * lit_area);
  }

  /// Gives every face of `arr` its hours, walking from the unbounded face: crossing halfedge h
  /// from h's face into its twin's leaves the regions on h's left and enters those on its right.
  void walk(Arrangement& arr) {
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) f->set_data(-1);
    const Arrangement::Face_handle unbounded = arr.unbounded_face();
    unbounded->set_data(0);
    hours_at_.assign(1, mpq_class(0));
    inside_.assign(1, 0);
    std::deque<Arrangement::Face_handle> queue{unbounded};
    auto visit_ccb = [&](Arrangement::Face_handle from, Arrangement::Ccb_halfedge_circulator first) {
      auto h = first;
      do {
        const Arrangement::Face_handle to = h->twin()->face();
        if (to->data() < 0) {
          mpq_class value = hours_at_[from->data()];
          int inside = inside_[from->data()];
          const bool left_to_right = h->direction() == CGAL::ARR_LEFT_TO_RIGHT;
          for (long tag : h->curve().data()) {
            const std::size_t i = static_cast<std::size_t>(std::labs(tag) - 1);
            // `from` lies on h's left; the region lies on the left of the left-to-right run
            // when tag > 0.
            const bool from_in_region = left_to_right == (tag > 0);
            const int step = from_in_region ? -1 : 1;
            if (i == n_) {
              inside += step;
              value += step > 0 ? base_ : mpq_class(-base_);
            } else {
              value += step > 0 ? mpq_class(hours_[i]) : mpq_class(-hours_[i]);
            }
          }
          to->set_data(static_cast<long>(hours_at_.size()));
          hours_at_.push_back(std::move(value));
          inside_.push_back(inside);
          queue.push_back(to);
        }
      } while (++h != first);
    };
    while (!queue.empty()) {
      const Arrangement::Face_handle f = queue.front();
      queue.pop_front();
      for (auto c = f->outer_ccbs_begin(); c != f->outer_ccbs_end(); ++c) visit_ccb(f, *c);
      for (auto c = f->inner_ccbs_begin(); c != f->inner_ccbs_end(); ++c) visit_ccb(f, *c);
    }
  }

  /// Removes every edge with equal (inside, hours) on both sides: touching cells of equal
  /// hours become one face. No antenna is left, since every remaining edge separates faces
  /// of different hours.
  void merge_equal(Arrangement& arr) {
    std::vector<Arrangement::Halfedge_handle> removable;
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
      const long a = e->face()->data(), b = e->twin()->face()->data();
      if (a == b || (inside_[a] == inside_[b] && hours_at_[a] == hours_at_[b])) removable.push_back(e);
    }
    for (Arrangement::Halfedge_handle e : removable) arr.remove_edge(e);
  }

  /// One simple cell as a SunHoursCell when its rounded polygon is clean, else its triangles
  /// (those that collapse are counted in dropped_area), as the exact engine writes fragments.
  void emit(Polygon2& cell, double sun_hours, FaceMap& out) {
    const mpq_class cell_area = exact_area(cell);
    if (write(cell, cell_area, sun_hours, out)) return;
    if (sgn(cell_area) < 0) cell.reverse_orientation();
    std::vector<Polygon2> triangles;
    triangulate_region(PolygonWithHoles2(cell), triangles);
    for (const Polygon2& t : triangles) {
      const mpq_class t_area = exact_area(t);
      if (!write(t, t_area, sun_hours, out)) dropped_ += abs(t_area);
    }
  }

  /// The exact signed chart area of a cell: the shoelace on its vertices' exact rational
  /// coordinates. The same value as polygon_area, with half the rational operations and no lazy
  /// DAG per term: the cells' exact areas were half the map's run time.
  static mpq_class exact_area(const Polygon2& cell) {
    const std::size_t n = cell.size();
    mpq_class twice(0), term;
    for (std::size_t a = 0; a < n; ++a) {
      const auto& p = CGAL::exact(cell[a]);
      const auto& q = CGAL::exact(cell[(a + 1) % n]);
      term = p.x() * q.y();
      twice += term;
      term = q.x() * p.y();
      twice -= term;
    }
    return twice / 2;
  }

  /// area_3d for an exact rational chart area: sqrt(chart_area^2 x scale), the rational rounded
  /// to 256 bits before the root as sqrt_to_double does, so the result is area_3d's bit for bit.
  double area_3d_mpq(const mpq_class& chart_area) const {
    if (sgn(chart_area) == 0) return 0.0;
    const mpq_class squared = chart_area * chart_area * scale_;
    return exact::sqrt_mpq_to_double(squared.get_mpq_t());
  }

  bool write(const Polygon2& cell, const mpq_class& cell_area, double sun_hours, FaceMap& out) {
    SunHoursCell c;
    c.face_id = face_id_;
    c.sun_hours = sun_hours;
    c.area = area_3d_mpq(cell_area);
    for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
      c.polygon.push_back(nearest_doubles(lift(*v, P_, fp_.axis)));
    }
    // The chart sees the face clockwise when flipped: restore the face's orientation.
    if (fp_.flipped == (sgn(cell_area) > 0)) std::reverse(c.polygon.begin(), c.polygon.end());
    if (!core::clean_double_polygon(c.polygon, fp_.axis)) return false;
    out.cells.push_back(std::move(c));
    return true;
  }

  const core::PreparedScene& ctx_;
  const ExactFace& P_;
  const core::FacePrep& fp_;
  std::size_t face_id_;
  const std::vector<double>& hours_;
  bool merge_;
  std::size_t n_;
  mpq_class base_{0};  ///< the hours of the instants that light the whole face
  mpq_class scale_;    ///< (3D area / chart area)^2, exact
  std::size_t lit_instants_ = 0;
  std::vector<Traits::Curve_2> curves_;
  std::vector<PolygonWithHoles2> regions_;
  std::vector<mpq_class> hours_at_;  ///< per walked face (its data)
  std::vector<int> inside_;          ///< per walked face: 1 inside the chart, 0 outside
  mpq_class dropped_{0};  ///< exact chart area of the cells too thin to write
  std::vector<FT> hour_area_terms_;  ///< w_i x lit chart area_i
};

}  // namespace

SunHoursMap compute_sun_hours_map(const ShadowEngine& engine, const std::vector<std::size_t>& faces_in,
                                  const std::vector<SunHoursInstant>& instants, const SunHoursOptions& options) {
  const core::PreparedScene ctx = shadow::engine::prepared_scene(engine);
  const Scene& scene = *ctx.scene;
  const unsigned threads = runtime::resolve_threads(runtime::checked_threads(options.threads));
  std::vector<double> hours(instants.size());
  for (std::size_t i = 0; i < instants.size(); ++i) {
    const std::string path = "instants[" + std::to_string(i) + "]";
    shadow::detail::check_light(instants[i].light, "", path + ".light");
    const double w = instants[i].hours;
    if (!std::isfinite(w) || w < 0)
      throw InputError({"", path + ".hours"}, "hours must be finite and >= 0, got " + std::to_string(w));
    hours[i] = w;
  }
  std::vector<std::size_t> faces;
  for (std::size_t k = 0; k < faces_in.size(); ++k) {
    if (faces_in[k] >= scene.faces.size())
      throw InputError({"", "sun-hours map faces[" + std::to_string(k) + "]"},
                       "face id " + std::to_string(faces_in[k]) + " is out of range (the scene has " +
                           std::to_string(scene.faces.size()) + " faces)");
    faces.push_back(faces_in[k]);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());

  SunHoursMap map;
  for (double w : hours) map.total_hours += w;  // informative; cells are summed exactly
  // The culling grid of each directional light, built once and shared read-only by the threads.
  std::vector<std::optional<core::LightSpaceGrid>> grids(instants.size());
  for (std::size_t i = 0; i < instants.size(); ++i)
    if (instants[i].light.type == LightType::Directional) grids[i].emplace(*ctx.cull, *ctx.prep, instants[i].light.to_light);

  struct Worker {
    ExactWorker exact;
    ShadowStats stats;
  };
  std::vector<Worker> workers(threads);
  for (Worker& w : workers) w.exact.reset(scene.faces.size(), ctx.solids->size());
  std::vector<FaceMap> per_face(faces.size());
  std::atomic<std::size_t> done{0};
  const std::size_t total = faces.size() * (instants.size() + 1);
  std::function<void(std::size_t)> report;
  if (options.progress) report = [&](std::size_t) { options.progress(Progress{done.load(), total}); };

  runtime::parallel_for(
      faces.size(), threads,
      [&](unsigned wi, std::size_t k) {
        Worker& w = workers[wi];
        const std::size_t f = faces[k];
        const core::FacePrep& fp = (*ctx.prep)[f];
        if (fp.degenerate) {
          per_face[k].face.face_id = f;
          done += instants.size() + 1;
          return;
        }
        const ExactFace& P = w.exact.face(ctx, f);
        FaceOverlay overlay(ctx, P, fp, f, hours, options.merge_equal);
        for (std::size_t i = 0; i < instants.size(); ++i) {
          runtime::check_stop();  // a face's instants take long: Ctrl-C must not wait for all of them
          const ExactLight light = to_exact_light(instants[i].light);
          const int side = CGAL::sign(plane_at_light(P, light));
          const LitRegion region = exact_lit_region(ctx, w.exact, f, i, light, side, instants[i].light,
                                                    grids[i] ? &*grids[i] : nullptr, w.stats);
          if (region.kind == LitRegion::Kind::Whole) overlay.add_whole(i);
          if (region.kind == LitRegion::Kind::Partial) overlay.add_partial(i, region.lit, region.lit_chart_area);
          ++done;
        }
        per_face[k] = overlay.finish();
        ++done;
      },
      report);

  std::size_t next_region = 0;
  for (FaceMap& fm : per_face) {
    for (SunHoursCell& c : fm.cells) {
      c.region_id += next_region;
      map.cells.push_back(std::move(c));
    }
    next_region += fm.regions;
    map.faces.push_back(fm.face);
  }
  map.regions = next_region;
  return map;
}

std::vector<std::size_t> sun_hours_map_faces(const Scene& scene) {
  std::vector<std::size_t> faces;
  for (std::size_t k = 0; k < scene.sun_hours_map.size(); ++k) {
    const std::size_t m = scene.sun_hours_map[k];
    if (m >= scene.meshes.size())  // a scene built in code: load_scene only stores valid indices
      throw InputError({scene.source.string(), "sun_hours_map[" + std::to_string(k) + "]"},
                       "mesh index " + std::to_string(m) + " is out of range (the scene has " +
                           std::to_string(scene.meshes.size()) + " meshes)");
    const Mesh& mesh = scene.meshes[m];
    for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count; ++f) faces.push_back(f);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

std::vector<std::size_t> sun_hours_map_faces(const Scene& scene, const std::vector<std::string>& mesh_names,
                                             const std::string& what) {
  Scene chosen;
  chosen.meshes = scene.meshes;
  // A mesh's name, or type:<T> for every mesh of a CityJSON object type (select_meshes).
  for (std::size_t k = 0; k < mesh_names.size(); ++k)
    for (std::size_t m : select_meshes(scene, mesh_names[k], {"", what})) chosen.sun_hours_map.push_back(m);
  return sun_hours_map_faces(chosen);
}

std::vector<SunHoursInstant> sun_hours_instants(const Scene& scene) {
  std::vector<SunHoursInstant> out;
  if (!scene.sun) return out;
  const double step_hours = hours_per_instant(*scene.sun);  // the series' rule (shadow/series.hpp)
  for (const SunInstant& instant : scene.sun_instants) {
    if (instant.light_id == SunInstant::none || instant.light_id >= scene.lights.size()) continue;
    out.push_back({scene.lights[instant.light_id], step_hours});
  }
  return out;
}

}  // namespace shadow
