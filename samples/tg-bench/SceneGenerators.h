/// @file SceneGenerators.h
/// Deterministic synthetic inputs: meshes, random triangle soups, random instance placements
/// and the built-in scenes. The same seed gives the same geometry on every run, so repeated
/// benchmarks and the peer implementations see identical input.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "BenchScene.h"
#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/TriangleMesh.h"

namespace tg::bench {

/// Uniform random numbers from a fully specified engine (std::mt19937_64 and a fixed
/// bits-to-float mapping; the standard distributions differ between library vendors).
class BenchRandom {
 public:
  explicit BenchRandom(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniformly distributed unit vector.
  Vec3d unitVector();

 private:
  std::mt19937_64 engine_;
};

/// Axis-aligned box centred at the origin with the given half extents: 8 points, 12 triangles.
TriangleMesh makeBoxMesh(const Vec3f& halfExtent);

/// Unit sphere around the origin (latitude/longitude tessellation, poles on the y axis):
/// 2 * slices * (stacks - 1) triangles. slices >= 3, stacks >= 2.
TriangleMesh makeSphereMesh(int slices, int stacks);

/// Edge length of the cube that holds `count` random triangles at unit density (one triangle
/// per unit volume), so that triangles per unit volume stay constant as `count` grows.
double randomTriangleCubeSide(std::size_t count);

/// `count` independent triangles (3 unshared points each) whose centres are uniform in
/// [0, randomTriangleCubeSide(count)]^3; each point lies within 0.5 of its centre per axis,
/// so edges are about (volume / count)^(1/3) = 1 long.
TriangleMesh makeRandomTriangles(std::size_t count, std::uint64_t seed);

/// `count` rigid placements: a uniformly random rotation followed by a translation uniform in
/// [0, cubeSide]^3.
std::vector<Affine3d> makeRandomPlacements(std::size_t count, double cubeSide, std::uint64_t seed);

/// out[i] = base[i] + a random offset in [-amplitude, amplitude]^3: the per-frame motion of a
/// deforming mesh. `out` and `base` have the same size.
void perturbPositions(std::span<const Vec3f> base, float amplitude, std::uint64_t seed,
                      std::span<Vec3f> out);

/// Haines' sphereflake: a unit sphere with nine spheres of a third its radius on its surface,
/// recursively `depth` times (1 + 9 + ... + 9^depth instances of one sphere mesh, y up), on a
/// ground square just below it (a second mesh with an identity instance, the last instance).
BenchScene makeSphereflakeScene(int depth);

/// One mesh of makeRandomTriangles(count) under one identity instance.
BenchScene makeRandomTriangleScene(std::size_t count);

}  // namespace tg::bench
