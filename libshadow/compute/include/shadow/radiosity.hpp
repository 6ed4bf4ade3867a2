// SPDX-License-Identifier: GPL-3.0-or-later
/// @file radiosity.hpp
/// @brief Global illumination by radiosity with exact visibility (docs/radiosity.md).
///
/// Every face is a Lambertian surface with the reflectance and emittance of its mesh's material
/// (Material::reflectance, Material::emittance). Light leaves and arrives on a face's front only.
/// Form factors are Lambert's contour integral over the part of the source polygon that the
/// receiving point sees exactly (the extended-light machinery of area_lights.hpp), integrated
/// over the receiver by quadrature. The solver is progressive refinement (shooting) radiosity on
/// elements cut from each face's exact lit and shadowed fragments of the scene's lights.
#pragma once

#include <shadow/area_lights.hpp>
#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <functional>
#include <vector>

namespace shadow {

/// The form factor from each of `points` (a differential area on its face, facing the face's
/// normal) to face `to_face`: the fraction of the diffuse power leaving the differential area
/// that reaches `to_face`'s front directly, through the part of the face the point sees
/// exactly (hidden parts removed by the scene's other faces). 0 for a point behind the face or
/// a face behind the point.
/// @throws InputError for a face id out of range, a degenerate face, or a non-finite point.
std::vector<double> point_form_factors(const Scene& scene, std::size_t to_face, const std::vector<SurfacePoint>& points,
                                       unsigned threads = 0);

/// Options of form_factor().
struct FormFactorOptions {
  /// Relative tolerance: the quadrature order is doubled until two successive estimates differ
  /// by at most tolerance times the larger (or 1e-12 absolutely).
  double tolerance = 1e-4;
  /// The highest number of Gauss points per direction on each triangle of the receiving face
  /// (orders 2, 4, 8, ... up to this).
  int max_order = 32;
  unsigned threads = 0;  ///< 0: every hardware thread
};

/// A face-to-face form factor and its error estimate.
struct FormFactor {
  double value = 0.0;  ///< F(from -> to): the fraction of from's diffuse power that reaches to
  /// |the last estimate - the one before| (orders n and n/2): the quadrature's error estimate.
  double error = 0.0;
  int order = 0;                ///< the Gauss order of `value`
  std::size_t evaluations = 0;  ///< point form factors computed
};

/// F(from_face -> to_face) with exact visibility: by reciprocity, (1/A_from) times the integral
/// over to_face of the point form factor to from_face (point_form_factors), by Gauss-Legendre
/// quadrature on the triangles of to_face (collapsed squares) at orders 2, 4, 8, ... until two
/// agree within `options.tolerance` or max_order is reached.
/// @throws InputError for a face out of range or degenerate, or bad options.
FormFactor form_factor(const Scene& scene, std::size_t from_face, std::size_t to_face,
                       const FormFactorOptions& options = {});

/// Progress of a radiosity solution.
struct RadiosityProgress {
  std::size_t shots = 0;         ///< patches shot so far (shooting) or gathering iterations (hierarchical)
  double unshot_fraction = 1.0;  ///< unshot power over the power put in
  /// The hierarchical method's share of its links computed (0 to 1; 1 once it iterates, and
  /// always 1 for shooting).
  double links_fraction = 1.0;
  bool shots_are_iterations = false;  ///< `shots` counts gathering iterations (hierarchical)
};

/// How the radiosity equation is solved (docs/radiosity.md).
enum class RadiosityMethod {
  /// Hierarchical above 4,000 patches (unless exact_visibility is asked for), shooting below.
  automatic,
  /// Progressive refinement: the patch with the most unshot power shoots to every element; the
  /// cost grows as patches x elements.
  shooting,
  /// Hierarchical radiosity with clusters: near pairs of patches linked patch to element as in
  /// shooting, groups of patches far apart relative to their size linked as a whole (the kernel
  /// at the two groups' centroids, with each face's own cosine; visibility from rays between
  /// them), then gathering iterations (Jacobi). The links grow about linearly with the scene.
  /// Not with exact_visibility (an InputError).
  hierarchical,
};

/// Options of solve_radiosity().
struct RadiosityOptions {
  /// Elements are refined (longest-edge bisection of the triangles of the fragments) until none
  /// has more area than this (m^2). 0: no refinement beyond the fragments' triangles.
  double max_element_area = 0.0;
  /// Patches, the triangles that shoot (each the mean of its elements' unshot radiosity), are
  /// refined to this area (m^2); 0: 16 times max_element_area. Elements receive; shooting from
  /// fewer, coarser patches is what keeps the cost near patches x elements rather than
  /// elements squared (Cohen, Greenberg, Immel and Brock 1986).
  double patch_area = 0.0;
  /// Stop when the unshot power is at most this fraction of the power put in (emitted plus the
  /// reflected part of the direct light).
  double tolerance = 1e-3;
  /// Shooting: the most shots (0: no limit other than the tolerance). Hierarchical: the most
  /// gathering iterations (0: 10,000).
  std::size_t max_shots = 0;
  /// Visibility between elements: false (the default) cuts the shadows of the faces in the shaft
  /// between receiver and shooter out of the shooter in doubles (about 1e-9 of its size);
  /// true takes CGAL's exact machinery point by point (slow; for checking the default).
  bool exact_visibility = false;
  /// When not empty (one value per scene face, W/m^2 or any unit of irradiance): each face's
  /// incident irradiance from outside the scene, taking the place of the scene's lights (which
  /// are then ignored). The solution is linear in it: irradiation summed over a period gives the
  /// period's reflected irradiation (shadow irradiance --reflections).
  std::vector<double> face_irradiance;
  /// When not empty (one value per scene face, each in [0, 1)): each face's reflectance in place
  /// of its material's (no colour then).
  std::vector<double> face_reflectance;
  unsigned threads = 0;       ///< 0: every hardware thread; at most 1024
  /// Called about every 0.5 s and at the end, from the calling thread. May be empty; what it
  /// throws stops the solution and comes out of the call.
  std::function<void(const RadiosityProgress&)> progress;
  RadiosityMethod method = RadiosityMethod::automatic;
  /// Hierarchical: two groups of patches are linked as a whole when the sum of their radii is
  /// at most this times the distance between their centroids (in [0.1, 1); smaller: more links,
  /// closer to shooting's answer). The kernel's relative error on such a link is of the order
  /// of its square.
  double link_separation = 0.4;
  /// Hierarchical: rays per link between groups for its visibility (1 to 1024).
  int link_rays = 8;
};

/// One element: a triangle of one face.
struct RadiosityElement {
  std::size_t face_id = 0;
  std::vector<glm::dvec3> polygon;  ///< counter-clockwise seen from the face's front
  double area = 0.0;
  double radiosity = 0.0;          ///< B = E + rho H (W/m^2 leaving the front)
  double irradiance = 0.0;         ///< H, all incident (W/m^2): direct + from other elements
  double direct_irradiance = 0.0;  ///< the scene's lights' share of H, with exact shadows
  double reflectance = 0.0;
  double emittance = 0.0;
  /// Red, green and blue radiosity and irradiance (each channel solved with that channel's
  /// reflectance, Material::reflectance_rgb; all three equal the scalar values when no material
  /// is coloured). Sources are white: emittance and the lights are the same in every channel.
  glm::dvec3 radiosity_rgb{0.0};
  glm::dvec3 irradiance_rgb{0.0};
};

/// Area-weighted means over one face.
struct FaceRadiosity {
  std::size_t face_id = 0;
  double area = 0.0;  ///< the elements' total area
  double radiosity = 0.0;
  double irradiance = 0.0;
  double direct_irradiance = 0.0;
  std::size_t elements = 0;
  glm::dvec3 radiosity_rgb{0.0};   ///< area-weighted mean of the elements' radiosity_rgb
  glm::dvec3 irradiance_rgb{0.0};  ///< area-weighted mean of the elements' irradiance_rgb
  /// One per scene light (Scene::lights order): its share of direct_irradiance (empty when the
  /// sources came from RadiosityOptions::face_irradiance).
  std::vector<double> direct_irradiance_by_light;
};

/// The solution and its balance: emitted + direct = absorbed + escaped + unshot (W), where
/// "escaped" is shot power that reached no element (it leaves an open scene; in a closed one it
/// is the quadrature error of the form factors).
struct RadiosityResult {
  std::vector<RadiosityElement> elements;
  std::vector<FaceRadiosity> faces;  ///< one per scene face, by face_id
  std::size_t shots = 0;              ///< shots of the scalar (mean reflectance) solution
  std::size_t patches = 0;            ///< shooters (see RadiosityOptions::patch_area)
  bool colour = false;                ///< some material has an RGB reflectance: channels solved
  double channel_unshot_fraction = 0.0;  ///< the largest unshot fraction of the three channels
  std::size_t exact_evaluations = 0;  ///< point form factors that took the exact visibility route
  bool hierarchical = false;          ///< solved by RadiosityMethod::hierarchical
  std::size_t iterations = 0;         ///< hierarchical: gathering iterations of the scalar solution
  std::size_t near_links = 0;         ///< hierarchical: pairs of patches linked element by element
  std::size_t far_links = 0;          ///< hierarchical: links between groups (visible ones)
  bool converged = false;      ///< unshot_fraction <= tolerance
  double emitted_power = 0.0;  ///< sum of E A
  double direct_power = 0.0;   ///< sum of H_direct A
  double absorbed_power = 0.0; ///< sum of (1 - rho) H A
  double escaped_power = 0.0;  ///< shot power that no element received
  double unshot_power = 0.0;   ///< power still to be shot
  double unshot_fraction = 0.0;
  /// |emitted + direct - absorbed - escaped - unshot| / (emitted + direct), from the final arrays.
  double balance_residual = 0.0;
  /// Estimate of the relative error of the radiosities: the unshot fraction (what is missing,
  /// at most, as a share of what was put in, amplified by the reflections still to come:
  /// unshot / (1 - mean reflectance)) plus the form factors' quadrature error (the change between
  /// one and three receiver points on the elements near each shooter, relative to the power shot;
  /// hierarchical: the far links' kernel and visibility errors weighted by the power they carry).
  double error_estimate = 0.0;
};

/// Solves radiosity on `scene` (docs/radiosity.md). Direct light from the scene's lights comes
/// from the exact shadow engine (compute_shadows: each face's lit fragments; light_irradiance
/// for extended lights), emitting faces are sources too.
/// @throws InputError for bad options or an unusable light.
RadiosityResult solve_radiosity(const Scene& scene, const RadiosityOptions& options = {});

}  // namespace shadow
