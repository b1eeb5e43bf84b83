#include "EmbreeFlatScene.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <iostream>
#include <string>
#include <vector>

#include "tracegraph/backend/Error.h"

namespace tg::bench {
namespace {

void reportError(void* /*user*/, RTCError code, const char* message) {
  std::cerr << "embree: error " << static_cast<int>(code) << ": "
            << (message ? message : "(no message)") << '\n';
}

/// Where one instance's copy lives in the flat buffers.
struct Slice {
  ObjectId object = 0;
  std::size_t vertexBegin = 0;
  std::size_t vertexCount = 0;
  std::size_t triangleCount = 0;
  bool operator==(const Slice&) const = default;
};

}  // namespace

struct EmbreeFlatScene::State {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCGeometry geometry = nullptr;  ///< null while the scene has no triangles
  unsigned geometryId = RTC_INVALID_GEOMETRY_ID;
  std::vector<Slice> layout;  ///< of the last flatten()
  std::size_t triangles = 0;
  std::size_t topologyChanges = 0;

  void check(const char* what) const {
    const RTCError code = rtcGetDeviceError(device);
    if (code != RTC_ERROR_NONE)
      throw Error(std::string("Embree: ") + what + " failed (error " +
                  std::to_string(static_cast<int>(code)) + ")");
  }

  void dropGeometry() {
    if (geometry == nullptr) return;
    rtcDetachGeometry(scene, geometryId);
    rtcReleaseGeometry(geometry);
    geometry = nullptr;
    geometryId = RTC_INVALID_GEOMETRY_ID;
  }
};

EmbreeFlatScene::EmbreeFlatScene(int threads, const std::string& extraConfig)
    : state_(std::make_unique<State>()) {
  std::string config = "threads=" + std::to_string(threads) + ",verbose=0";
  if (!extraConfig.empty()) config += "," + extraConfig;
  state_->device = rtcNewDevice(config.c_str());
  if (state_->device == nullptr)
    throw Error("Embree: rtcNewDevice(\"" + config + "\") failed (error " +
                std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(state_->device, reportError, nullptr);
  state_->scene = rtcNewScene(state_->device);
  rtcSetSceneFlags(state_->scene, RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(state_->scene, RTC_BUILD_QUALITY_LOW);
  state_->check("creating the flat scene");
}

EmbreeFlatScene::~EmbreeFlatScene() {
  state_->dropGeometry();
  rtcReleaseScene(state_->scene);
  rtcReleaseDevice(state_->device);
}

void EmbreeFlatScene::flatten(const Scene& scene, std::span<const InstanceId> instances) {
  State& s = *state_;
  std::vector<Slice> layout;
  layout.reserve(instances.size());
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  for (const InstanceId id : instances) {
    Slice slice;
    slice.object = scene.instanceObject(id);
    const TriangleMesh& mesh = scene.objectMesh(slice.object);
    slice.vertexBegin = vertices;
    slice.vertexCount = mesh.positions.size();
    slice.triangleCount = mesh.triangleCount();
    vertices += slice.vertexCount;
    triangles += slice.triangleCount;
    layout.push_back(slice);
  }

  if (layout != s.layout || s.geometry == nullptr) {
    // New topology: fresh buffers (Embree allocates them with the padding its vector loads
    // need past the last vertex) and a rewritten index buffer.
    ++s.topologyChanges;
    s.dropGeometry();
    s.layout = std::move(layout);
    s.triangles = triangles;
    if (triangles == 0) return;
    s.geometry = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(s.geometry, RTC_BUILD_QUALITY_LOW);
    rtcSetNewGeometryBuffer(s.geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(Vec3f),
                            vertices);
    auto* indices = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(s.geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), triangles));
    s.check("allocating the flat buffers");
    std::vector<std::size_t> triangleBegin(s.layout.size());
    std::size_t t = 0;
    for (std::size_t i = 0; i < s.layout.size(); ++i) {
      triangleBegin[i] = t;
      t += s.layout[i].triangleCount;
    }
    tbb::parallel_for(std::size_t{0}, s.layout.size(), [&](std::size_t i) {
      const Slice& slice = s.layout[i];
      const std::vector<std::uint32_t>& in = scene.objectMesh(slice.object).indices;
      std::uint32_t* out = indices + 3 * triangleBegin[i];
      const auto base = static_cast<std::uint32_t>(slice.vertexBegin);
      for (std::size_t k = 0; k < in.size(); ++k) out[k] = in[k] + base;
    });
    s.geometryId = rtcAttachGeometry(s.scene, s.geometry);
  }
  if (s.geometry == nullptr) return;

  // Every point of every instance is moved to world space, every frame: a flat structure has
  // no instance matrices to absorb the motion.
  auto* world =
      static_cast<Vec3f*>(rtcGetGeometryBufferData(s.geometry, RTC_BUFFER_TYPE_VERTEX, 0));
  tbb::parallel_for(std::size_t{0}, instances.size(), [&](std::size_t i) {
    const Slice& slice = s.layout[i];
    const Affine3f m(scene.instanceTransform(instances[i]));
    const std::vector<Vec3f>& points = scene.objectMesh(slice.object).positions;
    Vec3f* out = world + slice.vertexBegin;
    for (std::size_t k = 0; k < points.size(); ++k) out[k] = m.transformPoint(points[k]);
  });
  rtcUpdateGeometryBuffer(s.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
}

void EmbreeFlatScene::commit() {
  if (state_->geometry != nullptr) rtcCommitGeometry(state_->geometry);
  rtcCommitScene(state_->scene);
  state_->check("building the flat scene");
}

std::size_t EmbreeFlatScene::triangleCount() const {
  return state_->triangles;
}

std::size_t EmbreeFlatScene::topologyChanges() const {
  return state_->topologyChanges;
}

}  // namespace tg::bench
