/// @file EmbreePeer.h
/// Everything the benchmarks do with Embree 3, the peer they measure against, behind a small
/// interface free of Embree types. Only compiled when CMake found Embree (TG_HAVE_EMBREE).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "BenchScene.h"
#include "BenchTiming.h"
#include "HitComparison.h"
#include "RayGenerators.h"
#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/TriangleMesh.h"

namespace tg::bench {

/// Embree build configurations compared against.
enum class EmbreeQuality {
  Low,     ///< scene RTC_BUILD_QUALITY_LOW (fastest build; a two-level structure)
  Medium,  ///< scene RTC_BUILD_QUALITY_MEDIUM (Embree's default)
  High,    ///< scene RTC_BUILD_QUALITY_HIGH (may use spatial splits)
  Refit,   ///< RTC_SCENE_FLAG_DYNAMIC, scene LOW, geometry RTC_BUILD_QUALITY_REFIT
};

/// The build qualities of the rebuild-style rows, in report order.
inline constexpr EmbreeQuality kEmbreeBuildQualities[] = {EmbreeQuality::Low, EmbreeQuality::Medium,
                                                          EmbreeQuality::High};

/// Row name: "embree-low", "embree-medium", "embree-high", "embree-refit".
std::string embreeImplName(EmbreeQuality quality);

/// Version of the Embree headers compiled against, e.g. "3.13.5".
std::string embreeVersion();

/// An Embree device limited to `threads` worker threads. Errors Embree reports are printed to
/// stderr as they happen and turned into tg::Error by check().
class EmbreeDevice {
 public:
  /// With `monitorMemory`, installs Embree's memory-monitor callback to count the bytes the
  /// device holds (see allocatedBytes); off by default, since it runs on every allocation.
  /// `extraConfig`, when not empty, is appended to the device configuration string (see
  /// CommonOptions::embreeConfig). Embree reads the keys it knows and ignores the others.
  EmbreeDevice(int threads, const std::string& extraConfig, bool monitorMemory = false);
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;

  /// Throws tg::Error naming `what` when Embree reported an error on this thread since the
  /// last check.
  void check(const char* what) const;

  /// Bytes the device holds now (allocations minus frees, geometry buffers and acceleration
  /// structures alike) as its memory monitor reported them; 0 without monitoring.
  std::int64_t allocatedBytes() const;

  struct State;
  /// Implementation access for the other peer classes.
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

/// The toplevel suite's peer: a top-level scene of instances of one committed child mesh.
class EmbreeInstanceScene {
 public:
  EmbreeInstanceScene(const EmbreeDevice& device, const TriangleMesh& child, std::size_t instances,
                      EmbreeQuality quality);
  ~EmbreeInstanceScene();
  EmbreeInstanceScene(const EmbreeInstanceScene&) = delete;
  EmbreeInstanceScene& operator=(const EmbreeInstanceScene&) = delete;

  /// Sets every instance's matrix (one per instance) and commits the instance geometries.
  void setTransforms(std::span<const Affine3d> objectToWorld);
  /// Rebuilds (or refits) the top-level structure: rtcCommitScene. The part that is timed.
  void commit();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The rebuild suite's peer: one deforming triangle mesh in its own scene.
class EmbreeDeformingMesh {
 public:
  EmbreeDeformingMesh(const EmbreeDevice& device, const TriangleMesh& mesh, EmbreeQuality quality);
  ~EmbreeDeformingMesh();
  EmbreeDeformingMesh(const EmbreeDeformingMesh&) = delete;
  EmbreeDeformingMesh& operator=(const EmbreeDeformingMesh&) = delete;

  /// Writes new point positions into Embree's vertex buffer (same count as the mesh).
  void setPositions(std::span<const Vec3f> positions);
  /// rtcUpdateGeometryBuffer + rtcCommitGeometry + rtcCommitScene: what a renderer does per
  /// frame after moving the points, and the part that is timed.
  void commit();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// A BenchScene in Embree: one child scene per instanced mesh and one instance geometry per
/// BenchInstance, whose geometry id is the instance's index. A mesh with a single identity
/// instance is attached directly instead (no instance transform on the way), mirroring
/// Tracegraph's identity fast path. Meshes without triangles are left out.
class EmbreeBenchScene {
 public:
  /// Sets everything up (copies the geometry into Embree buffers); builds nothing yet.
  EmbreeBenchScene(const EmbreeDevice& device, const BenchScene& scene, EmbreeQuality quality);
  ~EmbreeBenchScene();
  EmbreeBenchScene(const EmbreeBenchScene&) = delete;
  EmbreeBenchScene& operator=(const EmbreeBenchScene&) = delete;

  /// Builds all child scenes (in parallel) and then the top-level scene.
  void commit();

  /// rtcIntersect1 per ray, parallel over chunks of rays in the calling task arena.
  void intersect1(std::span<const Ray> rays, std::span<RayOutcome> out) const;
  /// rtcIntersect8 per 4x2 pixel block of an image's row-major primary rays; lanes outside the
  /// image are masked off.
  void intersect8(std::span<const Ray> rays, ImageSize size, std::span<RayOutcome> out) const;
  /// rtcIntersect16 per 4x4 pixel block, as intersect8 does per 4x2 block.
  void intersect16(std::span<const Ray> rays, ImageSize size, std::span<RayOutcome> out) const;
  /// rtcOccluded1 per ray; out[i] = 1 when ray i is occluded.
  void occluded1(std::span<const Ray> rays, std::span<std::uint8_t> out) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Times `reps` from-scratch builds of `scene` at `quality`: a new EmbreeBenchScene per sample
/// (copying the geometry in is setup), its commit() timed, after one untimed warm-up. Throws
/// tg::Error when Embree reports an error.
TimingSummary timeEmbreeBuilds(const EmbreeDevice& device, const BenchScene& scene,
                               EmbreeQuality quality, int reps);

}  // namespace tg::bench
