// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow render SCENE -o view.svg|view.pdf`: loads the scene, computes the exact vector view and
// hands it to the render component's SVG or PDF drawing (shadow/render/vector_drawing.hpp).
#include "render_command.hpp"

#include <shadow/render/camera.hpp>
#include <shadow/render/render_image.hpp>
#include <shadow/render/shaded_mesh.hpp>
#include <shadow/render/vector_drawing.hpp>
#include <shadow/shadow.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

namespace shadow::render {

ViewCamera vector_camera(const Scene& scene, const RenderArgs& args) {
  // The PNG's camera, from the one function that chooses it (render/camera.hpp): its default
  // framing, then the scene's camera, then the options; errors name the options or the scene.
  CameraRequest request;
  auto vec = [](const std::vector<double>& v) { return glm::dvec3(v[0], v[1], v[2]); };
  if (!args.eye.empty()) request.eye = vec(args.eye);
  if (!args.target.empty()) request.target = vec(args.target);
  if (!args.up.empty()) request.up = vec(args.up);
  if (args.fov_given) request.fov_degrees = args.fov;
  request.framing = args.frame == "scene" ? Framing::Scene : Framing::Shadows;
  request.scene_file = args.scene;
  const Camera c = resolve_camera(scene, request, static_cast<double>(args.width) / args.height);
  ViewCamera camera;
  camera.eye = c.eye;
  camera.target = c.target;
  camera.up = c.up;
  camera.fov_degrees = c.fov_degrees;
  camera.width = args.width;
  camera.height = args.height;
  return camera;
}

int run_vector_render(const RenderArgs& args) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  Scene scene = load_scene(args.scene, render_load_options(args));
  if (!args.quiet)
    for (const Warning& warning : scene.warnings) std::cerr << "shadow: warning: " << warning.to_string() << "\n";
  // The exact view's cost grows faster than the face count (each face is clipped by the faces
  // in front of it): bounded, so that a city asks for a PNG instead of running for minutes.
  std::size_t faces = 0;
  for (const Face& face : scene.faces) faces += face.degenerate ? 0 : 1;
  if (faces > args.max_faces)
    throw InputError({args.scene, ""},
                     "the exact vector view of " + std::to_string(faces) + " faces is refused: it is bounded to " +
                         std::to_string(args.max_faces) +
                         " faces (--max-faces), as its cost grows with the faces and with how many lie behind "
                         "one another (a whole city took minutes); draw a PNG instead (-o view.png), or raise "
                         "--max-faces");
  const ViewCamera camera = vector_camera(scene, args);  // checked there, naming options or scene
  VectorViewOptions options;
  options.threads = args.threads;
  if (args.light >= 0) {
    if (static_cast<std::size_t>(args.light) >= scene.lights.size())
      throw InputError({"", "--light"}, "light " + std::to_string(args.light) + " is out of range (" + args.scene +
                                            " has " + std::to_string(scene.lights.size()) + " lights)");
    options.light = static_cast<std::size_t>(args.light);
  } else if (!scene.lights.empty()) {
    options.light = 0;
  }
  VectorView view;
  try {
    const ShadowEngine engine(scene, args.threads);
    view = compute_vector_view(engine, camera, options);
  } catch (const InputError& e) {
    throw InputError({e.where().file.empty() ? args.scene : e.where().file, e.where().place}, e.problem());
  }
  VectorStyle style;
  style.edges = args.edges;
  // The PNG's colours: each mesh's material, or the palette by type or role for faces without one.
  const DisplayGroups groups =
      display_groups(scene, args.colours == "palette" ? std::optional<Palette>(Palette{}) : std::nullopt);
  for (const std::size_t g : groups.face_group) style.face_colours.push_back(groups.groups[g].material.color);
  style.title = std::filesystem::path(args.scene).filename().string();
  if (view.light_id) {
    const Light& light = scene.lights[*view.light_id];
    style.title += ", light " + std::to_string(*view.light_id) + (light.name.empty() ? "" : " (" + light.name + ")");
  }
  style.title += ": exact vector view, libshadow " + std::string(version());
  const auto computed = Clock::now();
  std::string ext = std::filesystem::path(args.image).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".pdf")
    write_pdf(scene, view, args.image, style);
  else
    write_svg(scene, view, args.image, style);
  if (!args.quiet) {
    auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    std::size_t lit = 0;
    for (const ViewPiece& p : view.pieces) lit += p.lit ? 1 : 0;
    std::printf("shadow %s: %zu faces, %zu visible pieces (%zu lit), %dx%d\n", version(), scene.faces.size(),
                view.pieces.size(), lit, args.width, args.height);
    std::printf("  view in %.3f s, written in %.3f s: %s\n", seconds(computed - start),
                seconds(Clock::now() - computed), args.image.c_str());
  }
  return 0;
}

}  // namespace shadow::render
