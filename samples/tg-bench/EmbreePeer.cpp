#include "EmbreePeer.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "TraceParallel.h"
#include "tracegraph/backend/Error.h"

namespace tg::bench {

struct EmbreeDevice::State {
  RTCDevice device = nullptr;
  std::atomic<std::int64_t> bytes{0};  ///< net bytes reported by the memory monitor
};

namespace {

void reportError(void* /*user*/, RTCError code, const char* message) {
  std::cerr << "embree: error " << static_cast<int>(code) << ": "
            << (message ? message : "(no message)") << '\n';
}

/// Embree's memory monitor: called before (post = false) every allocation and after every free
/// with a negative size; counting both gives the bytes held.
bool countBytes(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<std::int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
  return true;  // never veto an allocation
}

RTCBuildQuality sceneQuality(EmbreeQuality q) {
  switch (q) {
    case EmbreeQuality::Low:
      return RTC_BUILD_QUALITY_LOW;
    case EmbreeQuality::Medium:
      return RTC_BUILD_QUALITY_MEDIUM;
    case EmbreeQuality::High:
      return RTC_BUILD_QUALITY_HIGH;
    // Embree uses per-geometry qualities (here: refit) only in the two-level structure it
    // builds for scenes of LOW quality.
    case EmbreeQuality::Refit:
      return RTC_BUILD_QUALITY_LOW;
  }
  return RTC_BUILD_QUALITY_MEDIUM;
}

RTCBuildQuality geometryQuality(EmbreeQuality q) {
  return q == EmbreeQuality::Refit ? RTC_BUILD_QUALITY_REFIT : sceneQuality(q);
}

RTCScene newScene(RTCDevice device, EmbreeQuality q) {
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, q == EmbreeQuality::Refit ? RTC_SCENE_FLAG_DYNAMIC : RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(scene, sceneQuality(q));
  return scene;
}

/// A triangle geometry holding its own copy of the mesh (Embree-allocated buffers carry the
/// padding its vector loads need past the last vertex; a std::vector does not).
RTCGeometry newTriangleGeometry(RTCDevice device, const TriangleMesh& mesh, EmbreeQuality q) {
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  void* vertices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                           sizeof(Vec3f), mesh.positions.size());
  void* indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                          3 * sizeof(std::uint32_t), mesh.triangleCount());
  if (vertices != nullptr)
    std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f));
  if (indices != nullptr)
    std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
  rtcSetGeometryBuildQuality(geometry, geometryQuality(q));
  rtcCommitGeometry(geometry);
  return geometry;
}

void setTransform(RTCGeometry geometry, const Affine3d& m) {
  float rows[12];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) rows[r * 4 + c] = static_cast<float>(m.m[r][c]);
  rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, rows);
}

void toEmbree(const Ray& ray, RTCRay& out) {
  out.org_x = ray.origin.x;
  out.org_y = ray.origin.y;
  out.org_z = ray.origin.z;
  out.tnear = ray.tnear;
  out.dir_x = ray.direction.x;
  out.dir_y = ray.direction.y;
  out.dir_z = ray.direction.z;
  out.time = 0.0f;
  out.tfar = ray.tfar;
  out.mask = 0xFFFFFFFFu;
  out.id = 0;
  out.flags = 0;
}

/// Instance id of a hit: the instance geometry's id, or for a directly attached mesh the
/// mesh geometry's id (both equal the BenchScene instance index).
RayOutcome outcome(unsigned geomId, unsigned instId, unsigned primId) {
  if (geomId == RTC_INVALID_GEOMETRY_ID) return {};
  return {instId != RTC_INVALID_GEOMETRY_ID ? instId : geomId, primId};
}

}  // namespace

std::string embreeImplName(EmbreeQuality quality) {
  switch (quality) {
    case EmbreeQuality::Low:
      return "embree-low";
    case EmbreeQuality::Medium:
      return "embree-medium";
    case EmbreeQuality::High:
      return "embree-high";
    case EmbreeQuality::Refit:
      return "embree-refit";
  }
  return "embree";
}

std::string embreeVersion() {
  return RTC_VERSION_STRING;
}

// --- EmbreeDevice -------------------------------------------------------------------------

EmbreeDevice::EmbreeDevice(int threads, const std::string& extraConfig, bool monitorMemory)
    : state_(std::make_unique<State>()) {
  std::string config = "threads=" + std::to_string(threads) + ",verbose=0";
  if (!extraConfig.empty()) config += "," + extraConfig;
  state_->device = rtcNewDevice(config.c_str());
  if (state_->device == nullptr)
    throw Error("Embree: rtcNewDevice(\"" + config + "\") failed (error " +
                std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(state_->device, reportError, nullptr);
  if (monitorMemory) rtcSetDeviceMemoryMonitorFunction(state_->device, countBytes, &state_->bytes);
}

std::int64_t EmbreeDevice::allocatedBytes() const {
  return state_->bytes.load(std::memory_order_relaxed);
}

EmbreeDevice::~EmbreeDevice() {
  rtcReleaseDevice(state_->device);
}

void EmbreeDevice::check(const char* what) const {
  const RTCError code = rtcGetDeviceError(state_->device);
  if (code != RTC_ERROR_NONE)
    throw Error(std::string("Embree: ") + what + " failed (error " +
                std::to_string(static_cast<int>(code)) + ")");
}

// --- EmbreeInstanceScene ------------------------------------------------------------------

struct EmbreeInstanceScene::State {
  RTCScene child = nullptr;
  RTCScene top = nullptr;
  std::vector<RTCGeometry> instances;
};

EmbreeInstanceScene::EmbreeInstanceScene(const EmbreeDevice& device, const TriangleMesh& child,
                                         std::size_t instances, EmbreeQuality quality)
    : state_(std::make_unique<State>()) {
  RTCDevice d = device.state().device;
  // The child is built once, at the quality Tracegraph uses for rigid objects; only the top
  // level is measured.
  state_->child = newScene(d, EmbreeQuality::High);
  RTCGeometry mesh = newTriangleGeometry(d, child, EmbreeQuality::High);
  rtcAttachGeometry(state_->child, mesh);
  rtcReleaseGeometry(mesh);
  rtcCommitScene(state_->child);

  state_->top = newScene(d, quality);
  state_->instances.reserve(instances);
  for (std::size_t i = 0; i < instances; ++i) {
    RTCGeometry inst = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, state_->child);
    rtcSetGeometryBuildQuality(inst, geometryQuality(quality));
    setTransform(inst, Affine3d::identity());
    rtcCommitGeometry(inst);
    rtcAttachGeometryByID(state_->top, inst, static_cast<unsigned>(i));
    state_->instances.push_back(inst);
  }
  device.check("creating the instance scene");
}

EmbreeInstanceScene::~EmbreeInstanceScene() {
  for (RTCGeometry g : state_->instances) rtcReleaseGeometry(g);
  rtcReleaseScene(state_->top);
  rtcReleaseScene(state_->child);
}

void EmbreeInstanceScene::setTransforms(std::span<const Affine3d> objectToWorld) {
  if (objectToWorld.size() != state_->instances.size())
    throw Error("EmbreeInstanceScene::setTransforms: one matrix per instance expected");
  for (std::size_t i = 0; i < objectToWorld.size(); ++i) {
    setTransform(state_->instances[i], objectToWorld[i]);
    rtcCommitGeometry(state_->instances[i]);
  }
}

void EmbreeInstanceScene::commit() {
  rtcCommitScene(state_->top);
}

// --- EmbreeDeformingMesh ------------------------------------------------------------------

struct EmbreeDeformingMesh::State {
  RTCScene scene = nullptr;
  RTCGeometry geometry = nullptr;
  std::size_t vertexCount = 0;
};

EmbreeDeformingMesh::EmbreeDeformingMesh(const EmbreeDevice& device, const TriangleMesh& mesh,
                                         EmbreeQuality quality)
    : state_(std::make_unique<State>()) {
  RTCDevice d = device.state().device;
  state_->scene = newScene(d, quality);
  state_->geometry = newTriangleGeometry(d, mesh, quality);
  state_->vertexCount = mesh.positions.size();
  rtcAttachGeometry(state_->scene, state_->geometry);
  device.check("creating the deforming mesh");
}

EmbreeDeformingMesh::~EmbreeDeformingMesh() {
  rtcReleaseGeometry(state_->geometry);
  rtcReleaseScene(state_->scene);
}

void EmbreeDeformingMesh::setPositions(std::span<const Vec3f> positions) {
  if (positions.size() != state_->vertexCount)
    throw Error("EmbreeDeformingMesh::setPositions: point count changed");
  void* vertices = rtcGetGeometryBufferData(state_->geometry, RTC_BUFFER_TYPE_VERTEX, 0);
  if (vertices != nullptr) std::memcpy(vertices, positions.data(), positions.size_bytes());
}

void EmbreeDeformingMesh::commit() {
  rtcUpdateGeometryBuffer(state_->geometry, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(state_->geometry);
  rtcCommitScene(state_->scene);
}

// --- EmbreeBenchScene ---------------------------------------------------------------------

struct EmbreeBenchScene::State {
  RTCScene top = nullptr;
  std::vector<RTCScene> children;  ///< per mesh; null when not instanced through a child scene
};

EmbreeBenchScene::EmbreeBenchScene(const EmbreeDevice& device, const BenchScene& scene,
                                   EmbreeQuality quality)
    : state_(std::make_unique<State>()) {
  RTCDevice d = device.state().device;
  state_->top = newScene(d, quality);
  state_->children.assign(scene.meshes.size(), nullptr);
  std::vector<std::size_t> uses(scene.meshes.size(), 0);
  for (const BenchInstance& inst : scene.instances) ++uses.at(inst.mesh);

  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const BenchInstance& inst = scene.instances[i];
    const TriangleMesh& mesh = scene.meshes[inst.mesh];
    if (mesh.triangleCount() == 0) continue;
    const auto id = static_cast<unsigned>(i);
    if (uses[inst.mesh] == 1 && inst.objectToWorld == Affine3d::identity()) {
      RTCGeometry geometry = newTriangleGeometry(d, mesh, quality);
      rtcAttachGeometryByID(state_->top, geometry, id);
      rtcReleaseGeometry(geometry);
      continue;
    }
    RTCScene& child = state_->children[inst.mesh];
    if (child == nullptr) {
      child = newScene(d, quality);
      RTCGeometry geometry = newTriangleGeometry(d, mesh, quality);
      rtcAttachGeometry(child, geometry);
      rtcReleaseGeometry(geometry);
    }
    RTCGeometry instance = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, child);
    setTransform(instance, inst.objectToWorld);
    rtcCommitGeometry(instance);
    rtcAttachGeometryByID(state_->top, instance, id);
    rtcReleaseGeometry(instance);
  }
  device.check("creating the scene");
}

EmbreeBenchScene::~EmbreeBenchScene() {
  rtcReleaseScene(state_->top);
  for (RTCScene child : state_->children)
    if (child != nullptr) rtcReleaseScene(child);
}

void EmbreeBenchScene::commit() {
  // Child scenes are independent, so they are built concurrently, as Tracegraph's commit()
  // builds its objects; each build is itself parallel inside Embree.
  tbb::parallel_for(std::size_t(0), state_->children.size(), [&](std::size_t i) {
    if (state_->children[i] != nullptr) rtcCommitScene(state_->children[i]);
  });
  rtcCommitScene(state_->top);
}

void EmbreeBenchScene::intersect1(std::span<const Ray> rays, std::span<RayOutcome> out) const {
  RTCScene top = state_->top;
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rayhit;
    for (std::size_t i = begin; i < end; ++i) {
      toEmbree(rays[i], rayhit.ray);
      rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(top, &context, &rayhit);
      out[i] = outcome(rayhit.hit.geomID, rayhit.hit.instID[0], rayhit.hit.primID);
    }
  });
}

namespace {

/// rtcIntersect8 or rtcIntersect16 on one packet (Embree's packet types differ only in width).
void intersectPacket(const int* valid, RTCScene scene, RTCIntersectContext* context,
                     RTCRayHit8& packet) {
  rtcIntersect8(valid, scene, context, &packet);
}
void intersectPacket(const int* valid, RTCScene scene, RTCIntersectContext* context,
                     RTCRayHit16& packet) {
  rtcIntersect16(valid, scene, context, &packet);
}

/// Embree's packets of Lanes rays over BlockWidth x (Lanes / BlockWidth) pixel blocks of an
/// image's row-major primary rays; lanes outside the image are masked off.
template <class Packet, int Lanes, int BlockWidth>
void intersectBlocks(RTCScene top, std::span<const Ray> rays, ImageSize size,
                     std::span<RayOutcome> out) {
  constexpr int kBlockHeight = Lanes / BlockWidth;
  const int blocksX = (size.width + BlockWidth - 1) / BlockWidth;
  const int blocksY = (size.height + kBlockHeight - 1) / kBlockHeight;
  // Each task takes whole blocks: a block row covers kBlockHeight image rows.
  tbb::parallel_for(
      tbb::blocked_range<int>(0, blocksX * blocksY, 32), [&](const tbb::blocked_range<int>& r) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        // Embree loads the packet and the valid mask with aligned full-width moves: both need
        // the packet's alignment (its type declares it, the mask must be given it).
        Packet packet;
        alignas(64) int valid[Lanes];
        std::size_t index[Lanes];
        for (int block = r.begin(); block != r.end(); ++block) {
          const int x0 = (block % blocksX) * BlockWidth, y0 = (block / blocksX) * kBlockHeight;
          for (int lane = 0; lane < Lanes; ++lane) {
            const int x = x0 + lane % BlockWidth, y = y0 + lane / BlockWidth;
            valid[lane] = x < size.width && y < size.height ? -1 : 0;
            index[lane] = valid[lane] ? static_cast<std::size_t>(y) * size.width + x : 0;
            const Ray& ray = rays[index[lane]];
            packet.ray.org_x[lane] = ray.origin.x;
            packet.ray.org_y[lane] = ray.origin.y;
            packet.ray.org_z[lane] = ray.origin.z;
            packet.ray.tnear[lane] = ray.tnear;
            packet.ray.dir_x[lane] = ray.direction.x;
            packet.ray.dir_y[lane] = ray.direction.y;
            packet.ray.dir_z[lane] = ray.direction.z;
            packet.ray.time[lane] = 0.0f;
            packet.ray.tfar[lane] = ray.tfar;
            packet.ray.mask[lane] = 0xFFFFFFFFu;
            packet.ray.id[lane] = static_cast<unsigned>(lane);
            packet.ray.flags[lane] = 0;
            packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
            packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
          }
          intersectPacket(valid, top, &context, packet);
          for (int lane = 0; lane < Lanes; ++lane) {
            if (!valid[lane]) continue;
            out[index[lane]] = outcome(packet.hit.geomID[lane], packet.hit.instID[0][lane],
                                       packet.hit.primID[lane]);
          }
        }
      });
}

}  // namespace

void EmbreeBenchScene::intersect8(std::span<const Ray> rays, ImageSize size,
                                  std::span<RayOutcome> out) const {
  intersectBlocks<RTCRayHit8, 8, 4>(state_->top, rays, size, out);
}

void EmbreeBenchScene::intersect16(std::span<const Ray> rays, ImageSize size,
                                   std::span<RayOutcome> out) const {
  intersectBlocks<RTCRayHit16, 16, 4>(state_->top, rays, size, out);
}

void EmbreeBenchScene::occluded1(std::span<const Ray> rays, std::span<std::uint8_t> out) const {
  RTCScene top = state_->top;
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray;
    for (std::size_t i = begin; i < end; ++i) {
      toEmbree(rays[i], ray);
      rtcOccluded1(top, &context, &ray);
      // Embree marks an occluded ray by setting tfar to -infinity.
      out[i] = ray.tfar < 0.0f ? 1 : 0;
    }
  });
}

// --- Build timing ----------------------------------------------------------------------------

TimingSummary timeEmbreeBuilds(const EmbreeDevice& device, const BenchScene& scene,
                               EmbreeQuality quality, int reps) {
  return measureRepeated(reps, [&](int) {
    EmbreeBenchScene peer(device, scene, quality);
    const double ms = timeMs([&] { peer.commit(); });
    device.check("committing the scene");
    return ms;
  });
}

}  // namespace tg::bench
