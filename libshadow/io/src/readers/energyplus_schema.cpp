// SPDX-License-Identifier: GPL-3.0-or-later
// The EnergyPlus reader's schemas (scene/energyplus_steps.hpp): for each geometry class read,
// its fields in the IDD's order (IDF positions) with their epJSON keys, by EnergyPlus version.
#include "readers/energyplus_steps.hpp"

#include <string>
#include <vector>

namespace shadow::scene_readers::energyplus {
namespace {

/// The fields of Shading:Fin (projection false) or Shading:Fin:Projection.
std::vector<FieldSpec> fin_fields(bool projection) {
  std::vector<FieldSpec> f{{"Name", nullptr}, {"Window or Door Name", "window_or_door_name"}};
  if (projection) {
    f.insert(f.end(), {{"Left Extension from Window/Door", "left_extension_from_window_door"},
                       {"Left Distance Above Top of Window", "left_distance_above_top_of_window"},
                       {"Left Distance Below Bottom of Window", "left_distance_below_bottom_of_window"},
                       {"Left Tilt Angle from Window/Door", "left_tilt_angle_from_window_door"},
                       {"Left Depth as Fraction of Window/Door Width", "left_depth_as_fraction_of_window_door_width"},
                       {"Right Extension from Window/Door", "right_extension_from_window_door"},
                       {"Right Distance Above Top of Window", "right_distance_above_top_of_window"},
                       {"Right Distance Below Bottom of Window", "right_distance_below_bottom_of_window"},
                       {"Right Tilt Angle from Window/Door", "right_tilt_angle_from_window_door"},
                       {"Right Depth as Fraction of Window/Door Width", "right_depth_as_fraction_of_window_door_width"}});
  } else {
    f.insert(f.end(), {{"Left Extension from Window/Door", "left_extension_from_window_door"},
                       {"Left Distance Above Top of Window", "left_distance_above_top_of_window"},
                       {"Left Distance Below Bottom of Window", "left_distance_below_bottom_of_window"},
                       {"Left Tilt Angle from Window/Door", "left_tilt_angle_from_window_door"},
                       {"Left Depth", "left_depth"},
                       {"Right Extension from Window/Door", "right_extension_from_window_door"},
                       {"Right Distance Above Top of Window", "right_distance_above_top_of_window"},
                       {"Right Distance Below Bottom of Window", "right_distance_below_bottom_of_window"},
                       {"Right Tilt Angle from Window/Door", "right_tilt_angle_from_window_door"},
                       {"Right Depth", "right_depth"}});
  }
  return f;
}

}  // namespace

std::vector<ClassSpec> class_specs(int version) {
  const bool has_space = version >= 906;       // Space Name in surfaces since 9.6
  const bool has_shading_control = version < 900;  // Shading Control Name in windows before 9.0
  auto surface_fields = [&](bool typed) {
    std::vector<FieldSpec> f{{"Name", nullptr}};
    if (typed) f.push_back({"Surface Type", "surface_type"});
    f.push_back({"Construction Name", "construction_name"});
    f.push_back({"Zone Name", "zone_name"});
    if (has_space) f.push_back({"Space Name", "space_name"});
    f.insert(f.end(), {{"Outside Boundary Condition", "outside_boundary_condition"},
                       {"Outside Boundary Condition Object", "outside_boundary_condition_object"},
                       {"Sun Exposure", "sun_exposure"},
                       {"Wind Exposure", "wind_exposure"},
                       {"View Factor to Ground", "view_factor_to_ground"},
                       {"Number of Vertices", "number_of_vertices"}});
    return f;
  };
  std::vector<FieldSpec> fenestration{{"Name", nullptr},
                                      {"Surface Type", "surface_type"},
                                      {"Construction Name", "construction_name"},
                                      {"Building Surface Name", "building_surface_name"},
                                      {"Outside Boundary Condition Object", "outside_boundary_condition_object"},
                                      {"View Factor to Ground", "view_factor_to_ground"}};
  if (has_shading_control) fenestration.push_back({"Shading Control Name", "shading_control_name"});
  fenestration.insert(fenestration.end(), {{"Frame and Divider Name", "frame_and_divider_name"},
                                           {"Multiplier", "multiplier"},
                                           {"Number of Vertices", "number_of_vertices"}});
  auto simple_opening = [&](bool framed) {
    std::vector<FieldSpec> f{{"Name", nullptr}, {"Construction Name", "construction_name"},
                             {"Building Surface Name", "building_surface_name"}};
    if (framed && has_shading_control) f.push_back({"Shading Control Name", "shading_control_name"});
    if (framed) f.push_back({"Frame and Divider Name", "frame_and_divider_name"});
    f.insert(f.end(), {{"Multiplier", "multiplier"},
                       {"Starting X Coordinate", "starting_x_coordinate"},
                       {"Starting Z Coordinate", "starting_z_coordinate"},
                       {"Length", "length"},
                       {"Height", "height"}});
    return f;
  };
  const std::vector<FieldSpec> simple_shading{{"Name", nullptr},
                                              {"Azimuth Angle", "azimuth_angle"},
                                              {"Tilt Angle", "tilt_angle"},
                                              {"Starting X Coordinate", "starting_x_coordinate"},
                                              {"Starting Y Coordinate", "starting_y_coordinate"},
                                              {"Starting Z Coordinate", "starting_z_coordinate"},
                                              {"Length", "length"},
                                              {"Height", "height"}};
  // Wall:Exterior, Roof, Floor:GroundContact, ...: a rectangle from its lower left corner.
  auto simple_surface = [&](bool interzone, const char* size_idd, const char* size_key) {
    std::vector<FieldSpec> f{{"Name", nullptr}, {"Construction Name", "construction_name"}, {"Zone Name", "zone_name"}};
    if (has_space) f.push_back({"Space Name", "space_name"});
    if (interzone) f.push_back({"Outside Boundary Condition Object", "outside_boundary_condition_object"});
    f.insert(f.end(), {{"Azimuth Angle", "azimuth_angle"},
                       {"Tilt Angle", "tilt_angle"},
                       {"Starting X Coordinate", "starting_x_coordinate"},
                       {"Starting Y Coordinate", "starting_y_coordinate"},
                       {"Starting Z Coordinate", "starting_z_coordinate"},
                       {"Length", "length"},
                       {size_idd, size_key}});
    return f;
  };
  const std::vector<FieldSpec> overhang{{"Name", nullptr},
                                        {"Window or Door Name", "window_or_door_name"},
                                        {"Height above Window or Door", "height_above_window_or_door"},
                                        {"Tilt Angle from Window/Door", "tilt_angle_from_window_door"},
                                        {"Left extension from Window/Door Width", "left_extension_from_window_door_width"},
                                        {"Right extension from Window/Door Width", "right_extension_from_window_door_width"},
                                        {"Depth", "depth"}};
  std::vector<FieldSpec> overhang_projection = overhang;
  overhang_projection.back() = {"Depth as Fraction of Window/Door Height", "depth_as_fraction_of_window_door_height"};
  std::vector<FieldSpec> run_period{{"Name", nullptr}, {"Begin Month", "begin_month"},
                                    {"Begin Day of Month", "begin_day_of_month"}};
  if (version >= 900) run_period.push_back({"Begin Year", "begin_year"});
  run_period.insert(run_period.end(), {{"End Month", "end_month"}, {"End Day of Month", "end_day_of_month"}});
  if (version >= 900) run_period.push_back({"End Year", "end_year"});
  return {
      {"BuildingSurface:Detailed", surface_fields(true), Vertices::List},
      {"Wall:Detailed", surface_fields(false), Vertices::List},
      {"RoofCeiling:Detailed", surface_fields(false), Vertices::List},
      {"Floor:Detailed", surface_fields(false), Vertices::List},
      {"FenestrationSurface:Detailed", fenestration, Vertices::Four},
      {"Window", simple_opening(true)},
      {"Door", simple_opening(false)},
      {"GlazedDoor", simple_opening(true)},
      {"Shading:Site:Detailed",
       {{"Name", nullptr}, {"Transmittance Schedule Name", "transmittance_schedule_name"},
        {"Number of Vertices", "number_of_vertices"}},
       Vertices::List},
      {"Shading:Building:Detailed",
       {{"Name", nullptr}, {"Transmittance Schedule Name", "transmittance_schedule_name"},
        {"Number of Vertices", "number_of_vertices"}},
       Vertices::List},
      {"Shading:Zone:Detailed",
       {{"Name", nullptr}, {"Base Surface Name", "base_surface_name"},
        {"Transmittance Schedule Name", "transmittance_schedule_name"},
        {"Number of Vertices", "number_of_vertices"}},
       Vertices::List},
      {"Wall:Exterior", simple_surface(false, "Height", "height")},
      {"Wall:Adiabatic", simple_surface(false, "Height", "height")},
      {"Wall:Underground", simple_surface(false, "Height", "height")},
      {"Wall:Interzone", simple_surface(true, "Height", "height")},
      {"Roof", simple_surface(false, "Width", "width")},
      {"Ceiling:Adiabatic", simple_surface(false, "Width", "width")},
      {"Ceiling:Interzone", simple_surface(true, "Width", "width")},
      {"Floor:GroundContact", simple_surface(false, "Width", "width")},
      {"Floor:Adiabatic", simple_surface(false, "Width", "width")},
      {"Floor:Interzone", simple_surface(true, "Width", "width")},
      {"Shading:Overhang", overhang},
      {"Shading:Overhang:Projection", overhang_projection},
      {"Shading:Fin", fin_fields(false)},
      {"Shading:Fin:Projection", fin_fields(true)},
      {"Shading:Site", simple_shading},
      {"Shading:Building", simple_shading},
      {"Zone",
       {{"Name", nullptr}, {"Direction of Relative North", "direction_of_relative_north"},
        {"X Origin", "x_origin"}, {"Y Origin", "y_origin"}, {"Z Origin", "z_origin"}}},
      {"Building", {{"Name", nullptr}, {"North Axis", "north_axis"}}},
      {"Compliance:Building", {{"Building Rotation for Appendix G", "building_rotation_for_appendix_g"}}},
      {"GlobalGeometryRules",
       {{"Starting Vertex Position", "starting_vertex_position"},
        {"Vertex Entry Direction", "vertex_entry_direction"},
        {"Coordinate System", "coordinate_system"},
        {"Daylighting Reference Point Coordinate System", "daylighting_reference_point_coordinate_system"},
        {"Rectangular Surface Coordinate System", "rectangular_surface_coordinate_system"}}},
      {"Site:Location",
       {{"Name", nullptr}, {"Latitude", "latitude"}, {"Longitude", "longitude"},
        {"Time Zone", "time_zone"}, {"Elevation", "elevation"}}},
      {"RunPeriod", run_period},
      {"Timestep", {{"Number of Timesteps per Hour", "number_of_timesteps_per_hour"}}},
  };
}

const std::vector<std::string>& unsupported_geometry_classes() {
  static const std::vector<std::string> classes{
      "InternalMass", "GeometryTransform"};
  return classes;
}

}  // namespace shadow::scene_readers::energyplus
