#include "pathtrace/triangle_scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "core/error.h"

namespace sss {

struct TriangleScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

TriangleScene::TriangleScene(const std::vector<glm::vec3>& positions,
                             const std::vector<glm::uvec3>& triangles)
    : impl_(std::make_unique<Impl>()) {
  if (positions.empty() || triangles.empty()) fail("", "path tracer: empty mesh");
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) fail("", "Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  // Robust mode: watertight hits on edges and vertices (a walk through a vertex must not leak).
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
  auto* f = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                           RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                           triangles.size()));
  if (!v || !f) {
    rtcReleaseGeometry(geometry);
    fail("", "Embree: cannot allocate the mesh buffers");
  }
  std::memcpy(v, positions.data(), positions.size() * sizeof(glm::vec3));
  std::memcpy(f, triangles.data(), triangles.size() * sizeof(glm::uvec3));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) fail("", "Embree: scene build failed");

  glm::vec3 lo(INFINITY), hi(-INFINITY);
  float maxAbs = 0.0f;
  for (const auto& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    maxAbs = std::max({maxAbs, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  diagonal_ = glm::length(hi - lo);
  epsilon_ = 4e-6f * std::max(diagonal_, maxAbs);
  faceNormals_.reserve(triangles.size());
  for (const auto& t : triangles) {
    const glm::vec3 n =
        glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]);
    const float len = glm::length(n);
    faceNormals_.push_back(len > 0.0f ? n / len : glm::vec3(0.0f));
  }
}

TriangleScene::~TriangleScene() = default;

SceneHit TriangleScene::intersect(const glm::vec3& o, const glm::vec3& d, float tNear,
                                  float tFar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = o.x;
  rh.ray.org_y = o.y;
  rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x;
  rh.ray.dir_y = d.y;
  rh.ray.dir_z = d.z;
  rh.ray.tnear = tNear;
  rh.ray.tfar = tFar;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  SceneHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.hit = true;
  hit.t = rh.ray.tfar;
  hit.faceNormal = faceNormals_[rh.hit.primID];
  hit.triangle = rh.hit.primID;
  return hit;
}

bool TriangleScene::occluded(const glm::vec3& o, const glm::vec3& d, float tNear,
                             float tFar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  ray.org_x = o.x;
  ray.org_y = o.y;
  ray.org_z = o.z;
  ray.dir_x = d.x;
  ray.dir_y = d.y;
  ray.dir_z = d.z;
  ray.tnear = tNear;
  ray.tfar = tFar;
  ray.time = 0.0f;
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
  rtcOccluded1(impl_->scene, &context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

}  // namespace sss
