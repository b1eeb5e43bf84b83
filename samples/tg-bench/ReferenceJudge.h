/// @file ReferenceJudge.h
/// Judging traces against the double-precision brute-force reference (never against the code
/// under test), and the error figures derived from that: mismatches, t in ulps, image PSNR.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "HitComparison.h"
#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/ReferenceIntersector.h"
#include "tracegraph/backend/Scene.h"

namespace tg::bench {

/// Reference answers for `rays`, computed in parallel in the calling task arena.
std::vector<ReferenceHit> referenceHits(const ReferenceIntersector& reference,
                                        std::span<const Ray> rays);

/// How a trace compares with the reference.
struct Judgement {
  std::size_t rays = 0;        ///< rays judged
  std::size_t mismatches = 0;  ///< wrong where the reference is unambiguous
  std::size_t ambiguous = 0;   ///< differ from the reference where either answer is acceptable
};

/// Closest-hit outcomes against reference answers: a hit/miss disagreement counts unless the
/// reference's hit is ambiguous, a different (instance, triangle) unless its triangle is.
Judgement judgeOutcomes(std::span<const ReferenceHit> reference,
                        std::span<const RayOutcome> outcomes);

/// Any-hit answers (non-zero = occluded) against the reference's, ambiguity as above.
Judgement judgeOcclusion(const ReferenceIntersector& reference, std::span<const Ray> rays,
                         std::span<const std::uint8_t> occluded);

/// Every k-th ray so that at most `count` remain (all when there are fewer).
std::vector<Ray> subsampleRays(std::span<const Ray> rays, std::size_t count);
/// The same selection applied to outcomes traced for all of `rays`.
std::vector<RayOutcome> subsampleOutcomes(std::span<const RayOutcome> outcomes, std::size_t count);

/// `count` rays from random points on a sphere around `bounds` through random points inside it.
std::vector<Ray> makeProbeRays(const Box3f& bounds, std::size_t count, std::uint64_t seed);

/// Eye-light shading of a hit, |cos| between the ray and the triangle's world normal computed in
/// double from the scene's mesh and matrix; 0 for a miss. The "image" of the PSNR figures.
double eyeLight(const Scene& scene, const Ray& ray, std::uint32_t instance, std::uint32_t prim);

/// PSNR in dB of eye-light values of `outcomes` against those of the reference hits (values in
/// [0, 1]); +inf when they are identical.
double eyeLightPsnr(const Scene& scene, std::span<const Ray> rays,
                    std::span<const ReferenceHit> reference, std::span<const RayOutcome> outcomes);

/// Distance in float ulps (of the reference value) between t and the reference's t.
double ulpError(float t, double reference);

/// Outcomes of tracing `rays` through `scene` (parallel in the calling arena).
std::vector<RayOutcome> traceOutcomes(const Scene& scene, std::span<const Ray> rays);
/// The same into `out` (one per ray), so that timed loops allocate nothing.
void traceOutcomes(const Scene& scene, std::span<const Ray> rays, std::span<RayOutcome> out);

/// The same through the packet interface (Scene::intersect over spans): consecutive rays form
/// the packets.
std::vector<RayOutcome> traceOutcomesInPackets(const Scene& scene, std::span<const Ray> rays);

/// Rays every build-style suite traces once after its timed builds, to show that what it timed
/// still answers correctly.
inline constexpr std::size_t kProbeRays = 512;

/// Traces kProbeRays probe rays (makeProbeRays over the scene's bounds) through the committed
/// `scene` and judges them against a reference built from it.
Judgement probeScene(const Scene& scene, std::uint64_t seed = 99);

}  // namespace tg::bench
