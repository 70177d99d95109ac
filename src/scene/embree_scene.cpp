#include "scene/embree_scene.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>

namespace lt {

namespace {

const char* ErrorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "error";
  }
}

float ToFloatT(double t) {
  if (std::isinf(t)) return t > 0 ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity();
  return float(t);
}

RTCRay MakeRtcRay(const Ray& ray, const Eigen::Vector3d& render_origin) {
  const Eigen::Vector3d o = ray.origin - render_origin;
  RTCRay r;
  r.org_x = float(o.x());
  r.org_y = float(o.y());
  r.org_z = float(o.z());
  r.dir_x = float(ray.direction.x());
  r.dir_y = float(ray.direction.y());
  r.dir_z = float(ray.direction.z());
  r.tnear = std::max(0.0f, ToFloatT(ray.t_min));
  r.tfar = ToFloatT(ray.t_max);
  r.time = 0.0f;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
  return r;
}

void CheckRay(const Ray& ray) {
  if (!ray.origin.allFinite() || !ray.direction.allFinite() || ray.direction.squaredNorm() == 0.0 ||
      std::isnan(ray.t_min) || std::isnan(ray.t_max)) {
    throw std::invalid_argument("EmbreeScene: ray origin and direction must be finite and the direction non-zero");
  }
}

}  // namespace

// Collects errors Embree reports through its callback (from any thread).
struct EmbreeScene::DeviceErrors {
  std::mutex mutex;
  std::string first;
  static void Callback(void* user, RTCError code, const char* message) {
    auto* self = static_cast<DeviceErrors*>(user);
    std::lock_guard<std::mutex> lock(self->mutex);
    if (self->first.empty()) self->first = std::string(ErrorName(code)) + (message ? std::string(": ") + message : "");
  }
};

void EmbreeScene::ThrowIfError(const char* stage) const {
  std::string message;
  {
    std::lock_guard<std::mutex> lock(errors_->mutex);
    message = errors_->first;
  }
  RTCError code = device_ ? rtcGetDeviceError(device_) : RTC_ERROR_NONE;
  if (message.empty() && code != RTC_ERROR_NONE) message = ErrorName(code);
  if (!message.empty()) throw std::runtime_error(std::string("Embree error while ") + stage + ": " + message);
}

EmbreeScene::EmbreeScene(std::shared_ptr<const SceneGeometry> geometry)
    : geometry_(std::move(geometry)), errors_(std::make_unique<DeviceErrors>()) {
  Build();
}

EmbreeScene::EmbreeScene(std::shared_ptr<SceneGeometry> geometry)
    : geometry_(geometry), mutable_geometry_(geometry.get()), errors_(std::make_unique<DeviceErrors>()) {
  Build();
}

// One scene per mesh, holding its triangles in object space, re-centred: Embree
// gets positions minus the mesh's bounds centre c (rounded to float, so the
// subtraction is exact) and the instance transform gains T(c). Float arithmetic
// inside Embree then works on small numbers even for meshes whose vertices lie
// far from their origin (georeferenced exports). An empty mesh gets an empty scene.
Eigen::Vector3d EmbreeScene::BuildMeshScene(size_t mesh_index) {
  const Mesh& mesh = geometry_->meshes[mesh_index];
  RTCScene ms = mesh_scenes_[mesh_index];
  if (mesh_attached_[mesh_index]) rtcDetachGeometry(ms, 0);
  mesh_attached_[mesh_index] = mesh.TriangleCount() > 0;
  mesh_alpha_filtered_[mesh_index] = 0;
  Eigen::AlignedBox3d b = mesh.Bounds();
  Eigen::Vector3f c = b.isEmpty() ? Eigen::Vector3f::Zero() : Eigen::Vector3f(b.center().cast<float>());
  if (mesh.TriangleCount() > 0 && MeshNeedsAlphaFilter(mesh_index)) {
    if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED) == 0) {
      throw std::runtime_error("mesh \"" + mesh.name + "\" has a MASK or BLEND material, but this Embree library "
                               "was built without filter functions (EMBREE_FILTER_FUNCTION), which they need");
    }
    mesh_alpha_filtered_[mesh_index] = 1;
  }
  if (mesh.TriangleCount() > 0) {
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Vertices are copied (Embree pads the buffer for its SIMD loads); the
    // index buffer is shared in place.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.VertexCount()));
    if (vertices) {
      for (size_t v = 0; v < mesh.VertexCount(); ++v) {
        for (int k = 0; k < 3; ++k) vertices[3 * v + size_t(k)] = mesh.positions[v][k] - c[k];
      }
    }
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                               3 * sizeof(uint32_t), mesh.TriangleCount());
    if (mesh_alpha_filtered_[mesh_index]) {
      rtcSetGeometryUserData(geom, this);
      rtcSetGeometryIntersectFilterFunction(geom, &EmbreeScene::AlphaFilter);
      rtcSetGeometryOccludedFilterFunction(geom, &EmbreeScene::AlphaFilter);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(ms, geom, 0);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(ms);
  ThrowIfError(("building mesh \"" + mesh.name + "\"").c_str());
  return c.cast<double>();
}

void EmbreeScene::SetInstanceTransform(size_t instance_index, RTCGeometry geom) const {
  const SceneInstance& inst = geometry_->instances[instance_index];
  const Eigen::Translation3d render_from_world(-render_origin_);
  const Eigen::Affine3d render_from_mesh =
      render_from_world * inst.world_from_mesh * Eigen::Translation3d(mesh_center_[inst.mesh]);  // in double
  const Eigen::Matrix<float, 3, 4> m = render_from_mesh.matrix().topRows<3>().cast<float>();
  float xfm[12];
  std::memcpy(xfm, m.data(), sizeof xfm);  // Eigen is column-major
  rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
}

void EmbreeScene::Build() {
  if (!geometry_) throw std::invalid_argument("EmbreeScene: no geometry");
  const SceneGeometry& g = *geometry_;
  bounds_ = g.WorldBounds();
  render_origin_ = bounds_.isEmpty() ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(bounds_.center());

  device_ = rtcNewDevice(nullptr);
  if (!device_) {
    throw std::runtime_error(std::string("Embree error while creating the device: ") +
                             ErrorName(rtcGetDeviceError(nullptr)));
  }
  rtcSetDeviceErrorFunction(device_, &DeviceErrors::Callback, errors_.get());

  try {
    if (std::any_of(g.materials.begin(), g.materials.end(),
                    [](const Material& m) { return m.alpha_mode != AlphaMode::kOpaque; })) {
      for (const Material& m : g.materials) {
        material_min_alpha_.push_back(m.alpha_mode == AlphaMode::kOpaque ? 1.0f : m.MinAlpha());
      }
    }
    for (size_t i = 0; i < g.meshes.size(); ++i) {
      RTCScene ms = rtcNewScene(device_);
      rtcSetSceneFlags(ms, RTC_SCENE_FLAG_ROBUST);  // watertight: no ray slips through a shared edge
      mesh_scenes_.push_back(ms);
      mesh_attached_.push_back(0);
      mesh_alpha_filtered_.push_back(0);
      rtcSetSceneBuildQuality(ms, RTC_BUILD_QUALITY_MEDIUM);
      mesh_center_.push_back(BuildMeshScene(i));
    }

    // The top scene: one instance per SceneInstance, geometry id = instance index.
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
    for (size_t i = 0; i < g.instances.size(); ++i) {
      const SceneInstance& inst = g.instances[i];
      RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(geom, mesh_scenes_[inst.mesh]);
      rtcSetGeometryTimeStepCount(geom, 1);
      SetInstanceTransform(i, geom);
      rtcCommitGeometry(geom);
      rtcAttachGeometryByID(scene_, geom, unsigned(i));
      rtcReleaseGeometry(geom);
      normal_from_mesh_.push_back(inst.world_from_mesh.linear().inverse().transpose());
    }
    rtcCommitScene(scene_);
    ThrowIfError("building the scene");
  } catch (...) {
    if (scene_) rtcReleaseScene(scene_);
    for (RTCScene s : mesh_scenes_) rtcReleaseScene(s);
    rtcReleaseDevice(device_);
    throw;
  }
}

void EmbreeScene::ReplaceMesh(size_t mesh_index, Mesh mesh) {
  if (!mutable_geometry_) throw std::logic_error("EmbreeScene::ReplaceMesh: the scene was built from immutable geometry");
  if (mesh_index >= mutable_geometry_->meshes.size()) throw std::out_of_range("EmbreeScene::ReplaceMesh: no such mesh");
  mesh.Validate();
  // Embree reads the old index buffer in place until the mesh scene is rebuilt:
  // keep it alive until then.
  Mesh old = std::move(mutable_geometry_->meshes[mesh_index]);
  mutable_geometry_->meshes[mesh_index] = std::move(mesh);
  mesh_center_[mesh_index] = BuildMeshScene(mesh_index);
  const SceneGeometry& g = *geometry_;
  for (size_t i = 0; i < g.instances.size(); ++i) {
    const SceneInstance& inst = g.instances[i];
    if (inst.mesh != mesh_index) continue;
    RTCGeometry geom = rtcGetGeometry(scene_, unsigned(i));
    SetInstanceTransform(i, geom);
    rtcCommitGeometry(geom);
    for (const auto& p : g.meshes[mesh_index].positions) bounds_.extend(inst.world_from_mesh * p.cast<double>());
  }
  rtcCommitScene(scene_);
  ThrowIfError("rebuilding a mesh");
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
  for (RTCScene s : mesh_scenes_) rtcReleaseScene(s);
  if (device_) rtcReleaseDevice(device_);
}

Hit EmbreeScene::MakeHit(const Ray& ray, uint32_t instance_id, uint32_t primitive_id, float u, float v) const {
  const SceneGeometry& g = *geometry_;
  const SceneInstance& inst = g.instances.at(instance_id);
  const Mesh& mesh = g.meshes[inst.mesh];
  const uint32_t* tri = &mesh.indices.at(3 * size_t(primitive_id));
  Hit hit;
  hit.instance_id = instance_id;
  hit.primitive_id = primitive_id;
  hit.material_id = g.MaterialOf(inst, primitive_id);

  const Eigen::Vector3d p0 = mesh.positions[tri[0]].cast<double>(), p1 = mesh.positions[tri[1]].cast<double>(),
                        p2 = mesh.positions[tri[2]].cast<double>();
  // Refine the hit in double: intersect the ray with the triangle's plane in the
  // world frame. Embree found the triangle; its float barycentrics are only
  // accurate to ~1e-7 of the distances involved, the refined point to ~1e-16.
  const Eigen::Vector3d w0 = inst.world_from_mesh * p0, w1 = inst.world_from_mesh * p1, w2 = inst.world_from_mesh * p2;
  const Eigen::Vector3d e1 = w1 - w0, e2 = w2 - w0;
  const Eigen::Vector3d pvec = ray.direction.cross(e2);
  const double det = e1.dot(pvec);
  double bu = u, bv = v;
  if (std::abs(det) > 1e-9 * e1.norm() * e2.norm() * ray.direction.norm()) {  // not grazing
    const Eigen::Vector3d tvec = ray.origin - w0;
    const Eigen::Vector3d qvec = tvec.cross(e1);
    bu = tvec.dot(pvec) / det;
    bv = ray.direction.dot(qvec) / det;
    hit.t = e2.dot(qvec) / det;
    hit.position = ray.origin + hit.t * ray.direction;
  } else {
    hit.position = (1.0 - bu - bv) * w0 + bu * w1 + bv * w2;
    hit.t = (hit.position - ray.origin).dot(ray.direction) / ray.direction.squaredNorm();
  }
  // Barycentrics for interpolation, kept inside the triangle (the refined point
  // can lie a rounding error outside an edge Embree decided it was inside of).
  bu = std::clamp(bu, 0.0, 1.0);
  bv = std::clamp(bv, 0.0, 1.0 - bu);
  const double bw = 1.0 - bu - bv;
  hit.barycentric = {float(bu), float(bv)};

  const Eigen::Matrix3d& nm = normal_from_mesh_[instance_id];
  hit.geometric_normal = (nm * (p1 - p0).cross(p2 - p0)).normalized();
  const Eigen::Vector3d n_obj = bw * mesh.normals[tri[0]].cast<double>() + bu * mesh.normals[tri[1]].cast<double>() +
                                bv * mesh.normals[tri[2]].cast<double>();
  Eigen::Vector3d ns = nm * n_obj;
  hit.shading_normal = ns.norm() > 1e-12 ? Eigen::Vector3d(ns.normalized()) : hit.geometric_normal;
  if (!mesh.texcoords.empty()) {
    hit.uv = (bw * mesh.texcoords[tri[0]].cast<double>() + bu * mesh.texcoords[tri[1]].cast<double>() +
              bv * mesh.texcoords[tri[2]].cast<double>())
                 .cast<float>();
  }
  if (!mesh.colors.empty()) {
    hit.vertex_color = (bw * mesh.colors[tri[0]].cast<double>() + bu * mesh.colors[tri[1]].cast<double>() +
                        bv * mesh.colors[tri[2]].cast<double>())
                           .cast<float>();
  }
  hit.front_face = ray.direction.dot(hit.geometric_normal) < 0;
  return hit;
}

std::optional<Hit> EmbreeScene::Intersect(const Ray& ray) const {
  CheckRay(ray);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray = MakeRtcRay(ray, render_origin_);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  const float t_far = rh.ray.tfar;
  // Embree intersects in float: a ray leaving a large triangle (vertices far
  // from the ray's origin, relative to the offset the caller started it at)
  // can find that triangle again. The refined (double) intersection of such a
  // hit lies at or behind the ray's origin, where a planar triangle, crossed
  // at most once, cannot be met: skip it and look further along the ray.
  for (int attempt = 0; attempt < 4; ++attempt) {
    rtcIntersect1(scene_, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    Hit hit = MakeHit(ray, rh.hit.instID[0], rh.hit.primID, rh.hit.u, rh.hit.v);
    if (hit.t > ray.t_min) return hit;
    rh.ray.tnear = std::nextafter(rh.ray.tfar, std::numeric_limits<float>::infinity());
    rh.ray.tfar = t_far;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  }
  return std::nullopt;
}

bool EmbreeScene::Occluded(const Ray& ray) const {
  CheckRay(ray);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r = MakeRtcRay(ray, render_origin_);
  rtcOccluded1(scene_, &context, &r);
  if (r.tfar != -std::numeric_limits<float>::infinity()) return false;
  // Confirm with the refined hit: float rounding can report the surface the
  // ray starts from (see Intersect).
  return Intersect(ray).has_value();
}

void EmbreeScene::IntersectMany(std::span<const Ray> rays, std::span<std::optional<Hit>> hits) const {
  if (rays.size() != hits.size()) throw std::invalid_argument("EmbreeScene::IntersectMany: size mismatch");
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = Intersect(rays[i]);
  });
}

}  // namespace lt
