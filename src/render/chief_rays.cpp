#include "render/chief_rays.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lt {

namespace {

// A hit this close to a triangle's edge (in Embree's barycentrics) is traced
// again ray by ray. Where two triangles share an edge, a ray through it meets
// both at the same float distance, and the one reported is the last the
// traversal tests, an order that differs between packets and single rays (on
// the demo's ground plane, 252 of 307 200 chief rays crossing its diagonal had
// the other triangle, with |u| or |v| below 1e-8). Embree's float barycentrics
// are good to about 1e-7 of the triangle, so this margin holds every such tie;
// it re-traces some 0.1% of the rays.
constexpr float kEdgeBarycentric = 1e-4f;
constexpr int kPacket = 4;  // packets of kPacket x kPacket pixels

}  // namespace

uint64_t TraceChiefRays(const EmbreeScene& embree, const Camera& cam, const Pose& world_from_cam, int x0, int y0, int x1,
                        int y1, std::span<ChiefRay> rays) {
  const int w = x1 - x0;
  if (w <= 0 || y1 <= y0 || rays.size() != size_t(w) * size_t(y1 - y0)) {
    throw std::invalid_argument("TraceChiefRays: rays.size() must equal the block's pixel count");
  }
  const Eigen::Vector3d origin = world_from_cam.translation();
  // As EmbreeScene::Intersect's rays: render-frame origin and direction in float,
  // t in [0, inf).
  const Eigen::Vector3d origin_in_render = origin - embree.render_origin();
  const bool finite_origin = origin.allFinite();
  // An Embree built without ray packets (EMBREE_RAY_PACKETS off) reports no
  // native packet size: then every ray is traced alone.
  RTCDevice device = rtcGetSceneDevice(embree.handle());
  const bool packets = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED) != 0;
  rtcReleaseDevice(device);
  uint64_t count = 0;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  for (int py = y0; py < y1; py += kPacket) {
    for (int px = x0; px < x1; px += kPacket) {
      alignas(64) int valid[16];
      alignas(64) RTCRayHit16 rh;
      ChiefRay* lane_ray[16] = {};
      for (int k = 0; k < 16; ++k) {
        const int x = px + k % kPacket, y = py + k / kPacket;
        valid[k] = 0;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        if (x >= x1 || y >= y1) continue;
        ChiefRay& r = rays[size_t(y - y0) * size_t(w) + size_t(x - x0)];
        r = ChiefRay{};
        auto dir = cam.Unproject(Eigen::Vector2d(x, y));
        if (!dir) continue;
        r.traced = true;
        r.direction = world_from_cam.linear() * *dir;
        ++count;
        if (!packets || !finite_origin || !r.direction.allFinite() || r.direction.squaredNorm() == 0.0) {
          // Alone; a bad ray gets EmbreeScene::Intersect's own check and error.
          Ray ray;
          ray.origin = origin;
          ray.direction = r.direction;
          r.hit = embree.Intersect(ray);
          continue;
        }
        lane_ray[k] = &r;
        valid[k] = -1;
        rh.ray.org_x[k] = float(origin_in_render.x());
        rh.ray.org_y[k] = float(origin_in_render.y());
        rh.ray.org_z[k] = float(origin_in_render.z());
        rh.ray.dir_x[k] = float(r.direction.x());
        rh.ray.dir_y[k] = float(r.direction.y());
        rh.ray.dir_z[k] = float(r.direction.z());
        rh.ray.tnear[k] = 0.0f;
        rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
        rh.ray.time[k] = 0.0f;
        rh.ray.mask[k] = 0xFFFFFFFFu;
        rh.ray.id[k] = 0;
        rh.ray.flags[k] = 0;
        rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      if (std::none_of(valid, valid + 16, [](int v) { return v != 0; })) continue;
      rtcIntersect16(valid, embree.handle(), &context, &rh);
      for (int k = 0; k < 16; ++k) {
        if (!valid[k] || rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
        ChiefRay& r = *lane_ray[k];
        Ray ray;
        ray.origin = origin;
        ray.direction = r.direction;
        const float u = rh.hit.u[k], v = rh.hit.v[k];
        if (u < kEdgeBarycentric || v < kEdgeBarycentric || u + v > 1.0f - kEdgeBarycentric) {
          r.hit = embree.Intersect(ray);
          continue;
        }
        Hit hit = embree.MakeHit(ray, rh.hit.instID[0][k], rh.hit.primID[k], u, v);
        if (hit.t > ray.t_min) {
          r.hit = hit;
        } else {
          r.hit = embree.Intersect(ray);  // a float self-hit behind the origin: Intersect looks further
        }
      }
    }
  }
  embree.CheckDevice();
  return count;
}

}  // namespace lt
