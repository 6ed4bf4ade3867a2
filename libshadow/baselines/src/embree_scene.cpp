// SPDX-License-Identifier: GPL-3.0-or-later
#include "embree_scene.hpp"

#include <shadow/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace shadow::baselines_detail {

EmbreeScene::~EmbreeScene() {
  if (scene) rtcReleaseScene(scene);
  if (device) rtcReleaseDevice(device);
}

namespace {
[[noreturn]] void embree_failed(RTCDevice device, const char* place, const char* what) {
  const RTCError e = device ? rtcGetDeviceError(device) : RTC_ERROR_UNKNOWN;
  throw InputError({"", place}, std::string(what) + " (Embree error " + std::to_string(static_cast<int>(e)) + ")");
}
}  // namespace

void build_embree_scene(const Scene& scene, const Setup& setup, unsigned threads, const char* place, EmbreeScene& es) {
  // One triangle mesh of every non-degenerate face, in float32 after the shift.
  std::vector<float> vertices;
  std::vector<unsigned> indices;
  double max_coordinate = 0;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const FaceFrame& fr = setup.frames[f];
    if (!fr.ok) continue;
    const auto base = static_cast<unsigned>(vertices.size() / 3);
    for (const glm::dvec3& p : scene.faces[f].vertices) {
      const glm::dvec3 q = p - setup.shift;
      for (int a = 0; a < 3; ++a) {
        vertices.push_back(static_cast<float>(q[a]));
        max_coordinate = std::max(max_coordinate, std::abs(q[a]));
      }
    }
    for (const auto& t : triangulate(fr.polygon)) {
      for (std::uint32_t i : t) indices.push_back(base + i);
      es.triangle_face.push_back(static_cast<std::uint32_t>(f));
    }
  }
  es.max_coordinate = max_coordinate;
  const std::string config = "threads=" + std::to_string(threads);
  es.device = rtcNewDevice(config.c_str());
  if (!es.device) embree_failed(nullptr, place, "cannot create an Embree device");
  es.scene = rtcNewScene(es.device);
  // Watertight traversal: without it rays leak through the shared diagonal of a triangulated quad.
  rtcSetSceneFlags(es.scene, RTC_SCENE_FLAG_ROBUST);
  if (!indices.empty()) {
    RTCGeometry geom = rtcNewGeometry(es.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), vertices.size() / 3));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), indices.size() / 3));
    if (!vb || !ib) {
      rtcReleaseGeometry(geom);
      embree_failed(es.device, place, "cannot allocate Embree buffers");
    }
    std::copy(vertices.begin(), vertices.end(), vb);
    std::copy(indices.begin(), indices.end(), ib);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(es.scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(es.scene);
  if (rtcGetDeviceError(es.device) != RTC_ERROR_NONE) embree_failed(es.device, place, "cannot build the Embree scene");
}

}  // namespace shadow::baselines_detail
