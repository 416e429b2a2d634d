#include "photoscene/raytrace/accel.hpp"

#include <atomic>

#if __has_include(<embree4/rtcore.h>)
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif

#include "photoscene/core/error.hpp"
#include "photoscene/core/timer.hpp"

namespace ps {

struct RayAccel::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {
void attachTriangles(RTCDevice device, RTCScene scene, const std::vector<Vec3f>& vertices,
                     const std::vector<Eigen::Vector3i>& tris, unsigned id) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), std::max<size_t>(1, vertices.size())));
  for (size_t i = 0; i < vertices.size(); ++i) {
    vb[3 * i + 0] = vertices[i].x();
    vb[3 * i + 1] = vertices[i].y();
    vb[3 * i + 2] = vertices[i].z();
  }
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), tris.size()));
  for (size_t i = 0; i < tris.size(); ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = static_cast<unsigned>(tris[i][k]);
  rtcCommitGeometry(g);
  rtcAttachGeometryByID(scene, g, id);
  rtcReleaseGeometry(g);
}

/// Embree's ray from `org` along `dir` over [tnear, tfar] (every geometry mask, no motion).
RTCRay embreeRay(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) {
  RTCRay ray;
  ray.org_x = org.x();
  ray.org_y = org.y();
  ray.org_z = org.z();
  ray.dir_x = dir.x();
  ray.dir_y = dir.y();
  ray.dir_z = dir.z();
  ray.tnear = tnear;
  ray.tfar = tfar;
  ray.time = 0;
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
  return ray;
}
}  // namespace

RayAccel::RayAccel(const Mesh& mesh, const std::vector<Vec3f>& shapeVertices)
    : impl_(new Impl), mesh_(mesh) {
  build(shapeVertices);
}

RayAccel::RayAccel(const Mesh& mesh, const std::vector<AreaLight>& lights) : impl_(new Impl), mesh_(mesh) {
  std::vector<Vec3f> v;
  for (size_t i = 0; i < lights.size(); ++i) {
    const size_t first = v.size();
    lights[i].shapes(&v, nullptr);
    for (size_t k = first; k + 2 < v.size(); k += 3) shapeLight_.push_back(static_cast<int>(i));
  }
  build(v);
}

void RayAccel::build(const std::vector<Vec3f>& shapeVertices) {
  Timer timer;
  impl_->device = rtcNewDevice(nullptr);
  PS_Check(impl_->device, "rtcNewDevice failed: " << rtcGetDeviceError(nullptr));
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  PS_Check(!mesh_.triangles.empty(), "RayAccel: empty mesh");
  attachTriangles(impl_->device, impl_->scene, mesh_.positions, mesh_.triangles, 0);
  PS_Check(shapeVertices.size() % 3 == 0, "RayAccel: light shapes are triangles (3 vertices each)");
  shapeVertices_ = shapeVertices;
  std::vector<Eigen::Vector3i> shapeTris;
  for (int k = 0; 3 * k < static_cast<int>(shapeVertices_.size()); ++k)
    shapeTris.emplace_back(3 * k, 3 * k + 1, 3 * k + 2);
  if (!shapeTris.empty())
    attachTriangles(impl_->device, impl_->scene, shapeVertices_, shapeTris, 1);
  rtcCommitScene(impl_->scene);
  const RTCError err = rtcGetDeviceError(impl_->device);
  PS_Check(err == RTC_ERROR_NONE, "Embree error " << static_cast<int>(err) << " while building the BVH");
  buildSeconds_ = timer.seconds();
}

RayAccel::~RayAccel() = default;

void RayAccel::rectangleTriangle(int prim, Vec3f* p0, Vec3f* p1, Vec3f* p2) const {
  *p0 = shapeVertices_[3 * prim];
  *p1 = shapeVertices_[3 * prim + 1];
  *p2 = shapeVertices_[3 * prim + 2];
}

RayHit RayAccel::intersect(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) const {
  RTCRayHit rh;
  rh.ray = embreeRay(org, dir, tnear, tfar);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if RTC_VERSION_MAJOR >= 4
  rtcIntersect1(impl_->scene, &rh);
#else
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(impl_->scene, &ctx, &rh);
#endif
  RayHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.t = rh.ray.tfar;
  hit.geom = static_cast<int>(rh.hit.geomID);
  hit.prim = static_cast<int>(rh.hit.primID);
  hit.b1 = rh.hit.u;
  hit.b2 = rh.hit.v;
  return hit;
}

bool RayAccel::occluded(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) const {
  RTCRay ray = embreeRay(org, dir, tnear, tfar);
#if RTC_VERSION_MAJOR >= 4
  rtcOccluded1(impl_->scene, &ray);
#else
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcOccluded1(impl_->scene, &ctx, &ray);
#endif
  return ray.tfar < 0;  // Embree sets tfar = -inf on a hit
}

}  // namespace ps
