#include "raytrace/triangle_scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "core/bounds.h"
#include "core/error.h"

namespace sss {

namespace {

void checkDevice(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) {
    fail("", std::string("Embree error ") + std::to_string(static_cast<int>(error)) + " " + what);
  }
}

}  // namespace

struct TriangleScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

TriangleScene::TriangleScene(std::span<const glm::vec3> positions,
                             std::span<const glm::uvec3> triangles,
                             const TriangleSceneOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (positions.empty() || triangles.empty()) fail("", "triangle scene: empty mesh");
  const std::string config = "threads=" + std::to_string(std::max(options.threads, 0));
  impl_->device = rtcNewDevice(config.c_str());
  if (!impl_->device) fail("", "Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  if (options.robust) rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, options.quality == TriangleSceneOptions::BuildQuality::High
                                            ? RTC_BUILD_QUALITY_HIGH
                                            : RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Copied into Embree-allocated (padded) buffers: Embree reads vertices with 16-byte loads.
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
  auto* f = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                           RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                           triangles.size()));
  if (!v || !f) {
    rtcReleaseGeometry(geometry);
    checkDevice(impl_->device, "allocating the mesh buffers");
    fail("", "Embree: cannot allocate the mesh buffers");
  }
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float) &&
                sizeof(glm::uvec3) == 3 * sizeof(unsigned));
  std::memcpy(v, positions.data(), positions.size() * sizeof(glm::vec3));
  std::memcpy(f, triangles.data(), triangles.size() * sizeof(glm::uvec3));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  checkDevice(impl_->device, "building the BVH");

  float maxAbs = 0.0f;
  for (const auto& p : positions) {
    maxAbs = std::max({maxAbs, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  diagonal_ = glm::length(boundsOf(positions).extent());
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

void requireSceneOfMesh(const TriangleScene& scene, std::span<const glm::uvec3> triangles) {
  if (scene.triangleCount() != triangles.size())
    fail("", "triangle scene: the scene given is of another mesh");
}

const TriangleScene& givenOrBuilt(const TriangleScene* given, std::optional<TriangleScene>& own,
                                  std::span<const glm::vec3> positions,
                                  std::span<const glm::uvec3> triangles,
                                  const TriangleSceneOptions& options) {
  if (!given) return own.emplace(positions, triangles, options);
  requireSceneOfMesh(*given, triangles);
  return *given;
}

namespace {

RTCRay makeRay(const glm::vec3& o, const glm::vec3& d, float tNear, float tFar, unsigned id) {
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
  ray.id = id;
  ray.flags = 0;
  return ray;
}

}  // namespace

SceneHit TriangleScene::intersect(const glm::vec3& o, const glm::vec3& d, float tNear,
                                  float tFar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray = makeRay(o, d, tNear, tFar, 0);
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
  RTCRay ray = makeRay(o, d, tNear, tFar, 0);
  rtcOccluded1(impl_->scene, &context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

// One rtcOccluded1M stream per batch: faster than single rays and than packets of 8 or 16 on the
// dragons (docs/tools/sss-bake.md, "Lighting and visibility").
void TriangleScene::occluded(std::span<const OcclusionRay> rays, std::vector<char>& blocked) const {
  thread_local std::vector<RTCRay> stream;  // reused across calls: no allocation per batch
  stream.resize(rays.size());
  for (std::size_t k = 0; k < rays.size(); ++k) {
    stream[k] = makeRay(rays[k].origin, rays[k].direction, rays[k].tNear, rays[k].tFar,
                        static_cast<unsigned>(k));
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  rtcOccluded1M(impl_->scene, &context, stream.data(), static_cast<unsigned>(stream.size()),
                sizeof(RTCRay));
  blocked.resize(rays.size());
  for (std::size_t k = 0; k < rays.size(); ++k) blocked[k] = stream[k].tfar < 0.0f;
}

void TriangleScene::intersect(std::span<const OcclusionRay> rays,
                              std::vector<SceneHit>& hits) const {
  thread_local std::vector<RTCRayHit> stream;
  stream.resize(rays.size());
  for (std::size_t k = 0; k < rays.size(); ++k) {
    stream[k].ray = makeRay(rays[k].origin, rays[k].direction, rays[k].tNear, rays[k].tFar,
                            static_cast<unsigned>(k));
    stream[k].hit.geomID = RTC_INVALID_GEOMETRY_ID;
    stream[k].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  rtcIntersect1M(impl_->scene, &context, stream.data(), static_cast<unsigned>(stream.size()),
                 sizeof(RTCRayHit));
  hits.assign(rays.size(), SceneHit{});
  for (std::size_t k = 0; k < rays.size(); ++k) {
    const RTCRayHit& rh = stream[k];
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    hits[k] = {rh.ray.tfar, faceNormals_[rh.hit.primID], rh.hit.primID, true};
  }
}

}  // namespace sss
