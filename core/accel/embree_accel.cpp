#include "core/accel/embree_accel.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <string>

#include "core/base/error.h"
#include "core/base/timing.h"

namespace gs {

namespace {

// Embree's widest packet: the rays a packet query takes at once.
constexpr size_t kPacketWidth = 16;

// Records the hits rtcOccluded1 and rtcOccluded16 accept, which Embree does not return
// itself: for each ray (its id, our lane in the packet) the first blocking hit.
struct OccludedContext {
  RTCIntersectContext context;  // first: Embree hands the filter a pointer to it
  Hit hits[kPacketWidth];
};

void record_occluder(const RTCFilterFunctionNArguments* args) {
  auto* occluded = reinterpret_cast<OccludedContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned lane = RTCRayN_id(args->ray, args->N, i);
    if (lane >= kPacketWidth) continue;
    occluded->hits[lane] = {int32_t(RTCHitN_primID(args->hit, args->N, i)),
                            RTCRayN_tfar(args->ray, args->N, i), RTCHitN_u(args->hit, args->N, i),
                            RTCHitN_v(args->hit, args->N, i)};
  }
  // valid stays -1: the hits are accepted and those rays' queries end.
}

bool count_memory(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<int64_t>*>(user)->fetch_add(int64_t(bytes), std::memory_order_relaxed);
  return true;
}

[[noreturn]] void fail_embree(RTCDevice device, const std::string& what) {
  const RTCError code = rtcGetDeviceError(device);
  throw InputError("embree: " + what + " failed (error " + std::to_string(int(code)) + ")");
}

RTCRay embree_ray(const Ray& ray) {
  RTCRay r;
  r.org_x = ray.origin.x, r.org_y = ray.origin.y, r.org_z = ray.origin.z;
  r.tnear = ray.tmin;
  r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z;
  r.time = 0.0f;
  r.tfar = ray.tmax;
  r.mask = std::numeric_limits<unsigned>::max();
  r.id = 0;
  r.flags = 0;
  return r;
}

}  // namespace

EmbreeAccel::EmbreeAccel(const AccelParams& params) : build_threads_(params.build_threads) {}

EmbreeAccel::~EmbreeAccel() { release(); }

void EmbreeAccel::release() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
  scene_ = nullptr, device_ = nullptr;
}

void EmbreeAccel::build(const Scene& scene) {
  release();
  memory_bytes_ = 0;
  const auto start = Clock::now();
  const std::string config =
      build_threads_ > 0 ? "threads=" + std::to_string(build_threads_) : std::string();
  device_ = rtcNewDevice(config.c_str());
  if (!device_) fail_embree(nullptr, "creating the device");
  rtcSetDeviceMemoryMonitorFunction(device_, count_memory, &memory_bytes_);

  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               scene.vertices.size()));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), scene.triangles.size()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    fail_embree(device_, "allocating the geometry");
  }
  for (size_t i = 0; i < scene.vertices.size(); ++i) {
    vertices[3 * i + 0] = scene.vertices[i].x;
    vertices[3 * i + 1] = scene.vertices[i].y;
    vertices[3 * i + 2] = scene.vertices[i].z;
  }
  for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
    const glm::uvec3& tri = scene.triangles[i];
    // A degenerate triangle keeps its id (primID) but can never be hit.
    const bool skip = scene.is_degenerate(i);
    indices[3 * size_t(i) + 0] = tri[0];
    indices[3 * size_t(i) + 1] = skip ? tri[0] : tri[1];
    indices[3 * size_t(i) + 2] = skip ? tri[0] : tri[2];
  }
  rtcSetGeometryOccludedFilterFunction(geometry, record_occluder);
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene_, geometry, 0);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene_);
  if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) fail_embree(device_, "building the scene");
  bounds_ = scene.bounds();
  build_seconds_ = seconds_since(start);
}

std::unique_ptr<ThreadContext> EmbreeAccel::make_context() const {
  return std::make_unique<ThreadContext>();
}

Hit EmbreeAccel::intersect(const Ray& ray, ThreadContext& /*context*/) const {
  if (!scene_ || !ray_is_valid(ray)) return {};
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit;
  rayhit.ray = embree_ray(ray);
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rayhit);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
  return {int32_t(rayhit.hit.primID), rayhit.ray.tfar, rayhit.hit.u, rayhit.hit.v};
}

Hit EmbreeAccel::any_hit(const Ray& ray, ThreadContext& /*context*/) const {
  if (!scene_ || !ray_is_valid(ray)) return {};
  OccludedContext occluded;
  rtcInitIntersectContext(&occluded.context);
  RTCRay r = embree_ray(ray);
  rtcOccluded1(scene_, &occluded.context, &r);
  // Embree marks an occluded ray with tfar = -inf; the filter has recorded the hit it took.
  return r.tfar == -std::numeric_limits<float>::infinity() ? occluded.hits[0] : Hit{};
}

// Embree's packet mode (rtcIntersect16 / rtcOccluded16, coherent-rays hint), 16 rays at a
// time: the fair comparison for grid1d's packets (docs/design.md §6.9).
void EmbreeAccel::trace_packet(std::span<const Ray> rays, std::span<const uint64_t> /*keys*/,
                               std::span<Hit> hits, bool any_hit,
                               ThreadContext& /*context*/) const {
  for (size_t first = 0; first < rays.size(); first += kPacketWidth) {
    const size_t n = std::min(kPacketWidth, rays.size() - first);
    alignas(64) int valid[kPacketWidth] = {};
    RTCRayHit16 packet;
    for (size_t k = 0; k < kPacketWidth; ++k) {
      const Ray& ray = rays[first + std::min(k, n - 1)];
      valid[k] = k < n && scene_ && ray_is_valid(ray) ? -1 : 0;
      packet.ray.org_x[k] = ray.origin.x, packet.ray.org_y[k] = ray.origin.y;
      packet.ray.org_z[k] = ray.origin.z, packet.ray.tnear[k] = ray.tmin;
      packet.ray.dir_x[k] = ray.dir.x, packet.ray.dir_y[k] = ray.dir.y;
      packet.ray.dir_z[k] = ray.dir.z, packet.ray.time[k] = 0.0f;
      packet.ray.tfar[k] = ray.tmax, packet.ray.mask[k] = std::numeric_limits<unsigned>::max();
      packet.ray.id[k] = unsigned(k), packet.ray.flags[k] = 0;
      packet.hit.geomID[k] = packet.hit.primID[k] = packet.hit.instID[0][k] =
          RTC_INVALID_GEOMETRY_ID;
    }
    if (!scene_) {
      std::fill(hits.begin() + ptrdiff_t(first), hits.begin() + ptrdiff_t(first + n), Hit{});
      continue;
    }
    OccludedContext occluded;
    rtcInitIntersectContext(&occluded.context);
    occluded.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    if (any_hit)
      rtcOccluded16(valid, scene_, &occluded.context, &packet.ray);
    else
      rtcIntersect16(valid, scene_, &occluded.context, &packet);
    for (size_t k = 0; k < n; ++k) {
      Hit& hit = hits[first + k];
      if (valid[k] == 0)
        hit = {};
      else if (any_hit)
        hit = packet.ray.tfar[k] == -std::numeric_limits<float>::infinity() ? occluded.hits[k]
                                                                            : Hit{};
      else
        hit = packet.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID
                  ? Hit{}
                  : Hit{int32_t(packet.hit.primID[k]), packet.ray.tfar[k], packet.hit.u[k],
                        packet.hit.v[k]};
    }
  }
}

StructureStats EmbreeAccel::stats() const {
  StructureStats s;  // nodes, leaves, voxels, states: Embree does not expose them (null)
  s.memory_bytes = uint64_t(std::max<int64_t>(0, memory_bytes_.load()));
  s.build_seconds = build_seconds_;
  s.counts_tests = false;
  s.counts_steps = false;
  return s;
}

}  // namespace gs
