// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/render_image.hpp"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

namespace shadow::render {
namespace {

/// Linear RGB in [0, 1] to an 8-bit sRGB value: the models compute linear light, screens and
/// PNG viewers expect sRGB (without it mid-tones look far too dark).
std::uint8_t to_byte(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  const double encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return static_cast<std::uint8_t>(std::lround(255.0 * encoded));
}

vtkSmartPointer<vtkUnsignedCharArray> colour_array(const std::vector<glm::dvec3>& colours) {
  auto array = vtkSmartPointer<vtkUnsignedCharArray>::New();
  array->SetName("colour");
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(colours.size()));
  for (std::size_t i = 0; i < colours.size(); ++i) {
    const auto id = static_cast<vtkIdType>(i);
    array->SetTypedComponent(id, 0, to_byte(colours[i].r));
    array->SetTypedComponent(id, 1, to_byte(colours[i].g));
    array->SetTypedComponent(id, 2, to_byte(colours[i].b));
  }
  return array;
}

/// Collects VTK's error messages so that a failure becomes one RenderError line.
class ErrorCollector : public vtkCommand {
 public:
  static ErrorCollector* New() { return new ErrorCollector; }
  void Execute(vtkObject*, unsigned long, void* call_data) override {
    if (call_data != nullptr && message.empty()) message = static_cast<const char*>(call_data);
  }
  std::string message;
};

}  // namespace

bool display_available() {
  const char* display = std::getenv("DISPLAY");
  return display != nullptr && display[0] != '\0';
}

Image render_mesh(const ColouredMesh& mesh, const RenderOptions& options) {
  if (options.width <= 0 || options.height <= 0)
    throw RenderError("image size must be positive, got " + std::to_string(options.width) + "x" +
                      std::to_string(options.height));
  // Debian's VTK opens an X connection even off screen and aborts the process without one.
  if (!display_available())
    throw RenderError("no X display (DISPLAY is not set): VTK's OpenGL needs one; run under "
                      "`xvfb-run -a` on a headless machine");

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.points.size()));
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), mesh.points[i].x, mesh.points[i].y, mesh.points[i].z);
  vtkNew<vtkCellArray> triangles;
  for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    const vtkIdType ids[3] = {static_cast<vtkIdType>(mesh.triangles[t]),
                              static_cast<vtkIdType>(mesh.triangles[t + 1]),
                              static_cast<vtkIdType>(mesh.triangles[t + 2])};
    triangles->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(triangles);

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOn();
  mapper->SetColorModeToDirectScalars();  // our colours as they are, no lookup table
  if (!mesh.triangle_colours.empty()) {
    poly->GetCellData()->SetScalars(colour_array(mesh.triangle_colours));
    mapper->SetScalarModeToUseCellData();
  } else {
    poly->GetPointData()->SetScalars(colour_array(mesh.point_colours));
    mapper->SetScalarModeToUsePointData();
    mapper->InterpolateScalarsBeforeMappingOff();
  }

  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  // The lighting model has been evaluated already: VTK must show the colours unchanged.
  actor->GetProperty()->LightingOff();
  actor->GetProperty()->SetAmbient(1.0);
  actor->GetProperty()->SetDiffuse(0.0);
  actor->GetProperty()->SetSpecular(0.0);

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->SetBackground(options.background.r, options.background.g, options.background.b);
  renderer->AutomaticLightCreationOff();
  vtkCamera* camera = renderer->GetActiveCamera();
  const Camera& c = options.shade.camera;
  camera->SetPosition(c.eye.x, c.eye.y, c.eye.z);
  camera->SetFocalPoint(c.target.x, c.target.y, c.target.z);
  camera->SetViewUp(c.up.x, c.up.y, c.up.z);
  camera->SetViewAngle(c.fov_degrees);
  camera->OrthogonalizeViewUp();
  renderer->ResetCameraClippingRange();

  vtkNew<vtkRenderWindow> window;
  vtkNew<ErrorCollector> errors;
  window->AddObserver(vtkCommand::ErrorEvent, errors);
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);  // no multisampling: the same pixels on every run
  window->SetSize(options.width, options.height);
  window->AddRenderer(renderer);
  window->Render();
  if (!errors->message.empty()) throw RenderError("VTK could not render: " + errors->message);

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* frame = grab->GetOutput();
  int dims[3];
  frame->GetDimensions(dims);
  if (dims[0] != options.width || dims[1] != options.height)
    throw RenderError("VTK returned a " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) +
                      " image instead of " + std::to_string(options.width) + "x" + std::to_string(options.height));

  Image image;
  image.width = dims[0];
  image.height = dims[1];
  image.rgb.resize(static_cast<std::size_t>(3) * static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]));
  const auto* source = static_cast<const std::uint8_t*>(frame->GetScalarPointer());
  const std::size_t row_bytes = static_cast<std::size_t>(3) * static_cast<std::size_t>(dims[0]);
  for (int y = 0; y < dims[1]; ++y)  // VTK's rows run from the bottom
    std::memcpy(image.rgb.data() + static_cast<std::size_t>(y) * row_bytes,
                source + static_cast<std::size_t>(dims[1] - 1 - y) * row_bytes, row_bytes);
  return image;
}

Image render_scene(const Scene& scene, const ShadowResult& result, const RenderOptions& options) {
  RenderOptions adjusted = options;
  adjusted.shade.image_height = options.height;
  const std::vector<OverlayCell> cells = overlay_fragments(scene, result);
  const ColouredMesh mesh = shade_cells(scene, cells, adjusted.shade);
  Image image = render_mesh(mesh, adjusted);
  image.exposure = mesh.exposure;
  return image;
}

void write_png(const Image& image, const std::filesystem::path& path) {
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* target = static_cast<std::uint8_t*>(data->GetScalarPointer());
  const std::size_t row_bytes = static_cast<std::size_t>(3) * static_cast<std::size_t>(image.width);
  for (int y = 0; y < image.height; ++y)
    std::memcpy(target + static_cast<std::size_t>(image.height - 1 - y) * row_bytes,
                image.rgb.data() + static_cast<std::size_t>(y) * row_bytes, row_bytes);
  vtkNew<vtkPNGWriter> writer;
  vtkNew<ErrorCollector> errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  writer->SetFileName(path.string().c_str());
  writer->SetInputData(data);
  writer->Write();
  if (writer->GetErrorCode() != 0 || !errors->message.empty()) {
    std::string reason = errors->message;
    while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' ')) reason.pop_back();
    if (const std::size_t colon = reason.find("): "); colon != std::string::npos) reason.erase(0, colon + 3);
    throw RenderError(path.string() + ": " + (reason.empty() ? "could not write the PNG file" : reason));
  }
}

}  // namespace shadow::render
