// SPDX-License-Identifier: GPL-3.0-or-later
// The EnergyPlus reader's last step (scene/energyplus_steps.hpp): each base surface loses its
// openings exactly and is split into hole-free pieces; openings set back in a reveal or proud of
// their wall are checked, given their reveal's sides and reported.
#include "readers/energyplus_steps.hpp"
#include "readers/energyplus_reveals.hpp"

#include "core/input_checks.hpp"
#include "core/polygon_holes.hpp"
#include "exact/face_shape.hpp"
#include "geometry/newell_normal.hpp"
#include "readers/idf_tokenizer.hpp"
#include "readers/json_document.hpp"
#include "readers/obj_reader.hpp"

#include <shadow/input_file.hpp>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string_view>
#include <utility>


namespace shadow::scene_readers::energyplus {

// Each base surface loses its openings (exactly), and is split into hole-free pieces that share
// its name; meshes: the zones in Zone order, then building shading, site shading, not exposed.
void Reader::cut_and_emit(Model& model) {
  const int groups = 4;
  std::vector<std::vector<Face>> per_zone(zones_.size());
  std::vector<std::vector<Face>> per_group(groups);
  for (std::size_t i = 0; i < surfaces_.size(); ++i) {
    const Surface& s = surfaces_[i];
    if (s.opening || s.group == Surface::Dropped) continue;
    std::vector<Face>& out = s.group == Surface::ZoneGroup ? per_zone[zone_index_.at(lower(s.zone))] : per_group[s.group];
    auto face = [&](const Surface& surface, std::vector<glm::dvec3> vertices) {
      Face f;
      f.vertices = std::move(vertices);
      f.source = {file_, surface.object->place};
      f.name = surface.name;
      f.kind = surface.kind;
      out.push_back(std::move(f));
    };
    if (s.openings.empty()) {
      face(s, s.vertices);
      continue;
    }
    // Openings must lie in the base surface's plane (within the planarity tolerance) ...
    const glm::dvec3 origin = s.vertices.front();
    glm::dvec3 n = geometry::newell_normal(s.vertices, origin);
    const double n_length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (!(n_length > 0)) fail(s.object->place, "a surface with openings has zero area");
    n /= n_length;
    glm::dvec3 lo = s.vertices.front(), hi = lo;
    for (const glm::dvec3& p : s.vertices) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const double diameter = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const double allowed = options_.planarity_tolerance * diameter;
    std::vector<std::vector<glm::dvec3>> openings;
    std::vector<OpeningPlacement> placements;
    for (const std::size_t o : s.openings) {
      const Surface& opening = surfaces_[o];
      // In the plane, or parallel to it and set back (a reveal) or proud: energyplus_reveals.
      OpeningPlacement placement = place_opening(opening.vertices, origin, n, allowed);
      check_placement(opening, s, placement, allowed);
      const glm::dvec3 on = geometry::newell_normal(opening.vertices, opening.vertices.front());
      if (on.x * n.x + on.y * n.y + on.z * n.z < 0)
        fail(opening.object->place, "faces the other way from its base surface \"" + s.object->name +
                                        "\" (its vertices run the other way round)");
      openings.push_back(placement.outline);
      placements.push_back(std::move(placement));
    }
    // ... and inside it, without overlapping each other: exact predicates on the input doubles.
    const detail::OpeningsCut cut = detail::cut_openings(s.vertices, openings, allowed);
    if (cut.surface_not_simple) fail(s.object->place, "the surface has zero area or crosses itself");
    if (cut.not_simple >= 0)
      fail(surfaces_[s.openings[cut.not_simple]].object->place, "the opening has zero area or crosses itself");
    if (cut.outside >= 0)
      fail(surfaces_[s.openings[cut.outside]].object->place,
           "not inside its base surface \"" + s.name + "\"");
    if (cut.overlap_first >= 0)
      fail(surfaces_[s.openings[cut.overlap_second]].object->place,
           "overlaps \"" + surfaces_[s.openings[cut.overlap_first]].name + "\" in the same base surface");
    if (cut.within_tolerance)
      warnings_.push_back({{file_, s.object->place},
                           "an opening sticks out of the surface, or two openings overlap, by no more than the "
                           "planarity tolerance (" + detail::format_number(allowed) +
                               "): taken as rounding, the cut is exact up to those slivers"});
    for (const auto& region : cut.regions) {
      if (region.size() == 1) {
        face(s, region.front());
        continue;
      }
      const std::vector<std::vector<glm::dvec3>> holes(region.begin() + 1, region.end());
      const core::PolygonHolesSplit split =
          core::split_polygon_with_holes_checked(region.front(), holes, options_.planarity_tolerance);
      if (!split.error.empty()) fail(s.object->place, "cutting its openings out: " + split.error);
      for (const auto& piece : split.pieces) face(s, piece);
    }
    for (std::size_t k = 0; k < s.openings.size(); ++k) {
      const Surface& opening = surfaces_[s.openings[k]];
      const OpeningPlacement& placement = placements[k];
      // A window in a reveal stays at its depth, and the reveal's sides shade it; one proud of
      // its wall is put into the wall's plane (EnergyPlus gives it no projection either).
      face(opening, placement.kind == OpeningPlacement::Proud ? placement.outline : opening.vertices);
      if (placement.kind == OpeningPlacement::SetBack)
        add_reveal(opening, placement, per_group[Surface::BuildingShading]);
    }
  }
  report_reveals();
  auto emit = [&](const std::string& name, std::vector<Face>& faces, bool receiver, const char* type) {
    if (faces.empty()) return;
    Mesh mesh;
    mesh.name = name;
    mesh.object_type = type;  // a zone's results add up per zone (sun_hours_by_object.csv)
    mesh.first_face = model.faces.size();
    mesh.face_count = faces.size();
    mesh.receiver = receiver;
    const std::size_t index = model.meshes.size();
    for (Face& f : faces) {
      f.mesh = index;
      model.faces.push_back(std::move(f));
    }
    model.meshes.push_back(std::move(mesh));
  };
  for (std::size_t z = 0; z < zones_.size(); ++z) emit(zones_[z].name, per_zone[z], true, "zone");
  emit("Shading:Building", per_group[Surface::BuildingShading], false, "");
  emit("Shading:Site", per_group[Surface::SiteShading], false, "");
  emit("Not exposed", per_group[Surface::NotExposed], false, "");
}

// An opening off its wall's plane: in a reveal (set back) or proud of the wall, both parallel to
// it and at most kMaxRevealDepth away, is read (docs/energyplus.md); anything else is an error.
void Reader::check_placement(const Surface& opening, const Surface& base, const OpeningPlacement& placement,
                             double allowed) {
  const std::string plane = "not in the plane of its base surface \"" + base.object->name + "\": ";
  if (placement.kind == OpeningPlacement::Skew)
    fail(opening.object->place, plane + "vertex " + detail::format_vec(placement.vertex) + " is " +
                                    detail::format_number(placement.distance) +
                                    " off it, and the opening is not parallel to it (its vertices' distances "
                                    "differ by more than " + detail::format_number(allowed) +
                                    "), so it is no window in a reveal either");
  if (placement.kind == OpeningPlacement::TooDeep)
    fail(opening.object->place, plane + "it lies " + detail::format_number(std::abs(placement.offset)) +
                                    (placement.offset < 0 ? " behind" : " in front of") +
                                    " it, more than the deepest reveal read (" +
                                    detail::format_number(kMaxRevealDepth) + " m; docs/energyplus.md)");
  if (placement.kind != OpeningPlacement::SetBack && placement.kind != OpeningPlacement::Proud) return;
  RevealCount& count = placement.kind == OpeningPlacement::SetBack ? set_back_ : proud_;
  const double depth = std::abs(placement.offset);
  count.shallowest = count.openings == 0 ? depth : std::min(count.shallowest, depth);
  count.deepest = count.openings == 0 ? depth : std::max(count.deepest, depth);
  if (count.openings++ == 0) count.first = &opening;
}

// The reveal's sides of a set-back opening: building shading named after it, and counted.
void Reader::add_reveal(const Surface& opening, const OpeningPlacement& placement, std::vector<Face>& out) {
  const std::vector<std::vector<glm::dvec3>> sides = reveal_sides(opening.vertices, placement.outline);
  for (std::size_t k = 0; k < sides.size(); ++k) {
    Face f;
    f.vertices = sides[k];
    f.source = {file_, opening.object->place};
    f.name = opening.name + ":Reveal:" + std::to_string(k + 1);
    f.kind = "Shading";
    if (surface_index_.count(lower(f.name)) != 0)
      fail(opening.object->place, "its reveal's side would be named \"" + f.name +
                                      "\", which another surface already is (" +
                                      surfaces_[surface_index_.at(lower(f.name))].object->place + ")");
    out.push_back(std::move(f));
  }
}

// One warning for all set-back openings, one for all proud ones: a model has dozens of windows.
void Reader::report_reveals() {
  auto depths = [](const RevealCount& c) {
    return c.shallowest == c.deepest ? detail::format_number(c.deepest) + " m"
                                     : detail::format_number(c.shallowest) + " to " + detail::format_number(c.deepest) + " m";
  };
  auto openings = [](const RevealCount& c) {
    return std::to_string(c.openings) + (c.openings == 1 ? " window or door" : " windows and doors") + " (first \"" +
           c.first->name + "\")";
  };
  if (set_back_.openings > 0)
    warnings_.push_back({{file_, set_back_.first->object->place},
                         openings(set_back_) + " set back from the plane of their base surface by " + depths(set_back_) +
                             ": read as openings in reveals of that depth; each reveal's sides (jambs, head, sill) "
                             "are building shading named \"<opening>:Reveal:1\", \"<opening>:Reveal:2\", ... "
                             "(docs/energyplus.md)"});
  if (proud_.openings > 0)
    warnings_.push_back({{file_, proud_.first->object->place},
                         openings(proud_) + " in front of the plane of their base surface by " + depths(proud_) +
                             ": put into that plane, as EnergyPlus gives an opening proud of its wall no reveal "
                             "(docs/energyplus.md)"});
}

}  // namespace shadow::scene_readers::energyplus
