#include "ReferenceJudge.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "SceneGenerators.h"
#include "TraceParallel.h"

namespace tg::bench {

std::vector<ReferenceHit> referenceHits(const ReferenceIntersector& reference,
                                        std::span<const Ray> rays) {
  std::vector<ReferenceHit> out(rays.size());
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) out[i] = reference.intersect(rays[i]);
  });
  return out;
}

Judgement judgeOutcomes(std::span<const ReferenceHit> reference,
                        std::span<const RayOutcome> outcomes) {
  Judgement j;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const ReferenceHit& r = reference[i];
    const RayOutcome& o = outcomes[i];
    ++j.rays;
    bool differs = false, acceptable = false;
    if (r.hit != o.hit()) {
      differs = true;
      acceptable = r.hitAmbiguous;
    } else if (r.hit && (r.instanceId != o.instance || r.primId != o.prim)) {
      differs = true;
      acceptable = r.primAmbiguous || r.hitAmbiguous;
    }
    if (differs) ++(acceptable ? j.ambiguous : j.mismatches);
  }
  return j;
}

Judgement judgeOcclusion(const ReferenceIntersector& reference, std::span<const Ray> rays,
                         std::span<const std::uint8_t> occluded) {
  std::vector<std::uint8_t> verdict(rays.size(), 0);  // 1 mismatch, 2 ambiguous difference
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      bool ambiguous = false;
      const bool expected = reference.occluded(rays[i], &ambiguous);
      if (expected != (occluded[i] != 0)) verdict[i] = ambiguous ? 2 : 1;
    }
  });
  Judgement j;
  j.rays = rays.size();
  j.mismatches = static_cast<std::size_t>(std::count(verdict.begin(), verdict.end(), 1));
  j.ambiguous = static_cast<std::size_t>(std::count(verdict.begin(), verdict.end(), 2));
  return j;
}

namespace {
std::size_t strideFor(std::size_t n, std::size_t count) {
  return count == 0 ? n + 1 : std::max<std::size_t>(1, (n + count - 1) / count);
}
}  // namespace

std::vector<Ray> subsampleRays(std::span<const Ray> rays, std::size_t count) {
  std::vector<Ray> out;
  const std::size_t stride = strideFor(rays.size(), count);
  for (std::size_t i = 0; i < rays.size(); i += stride) out.push_back(rays[i]);
  return out;
}

std::vector<RayOutcome> subsampleOutcomes(std::span<const RayOutcome> outcomes, std::size_t count) {
  std::vector<RayOutcome> out;
  const std::size_t stride = strideFor(outcomes.size(), count);
  for (std::size_t i = 0; i < outcomes.size(); i += stride) out.push_back(outcomes[i]);
  return out;
}

std::vector<Ray> makeProbeRays(const Box3f& bounds, std::size_t count, std::uint64_t seed) {
  BenchRandom random(seed);
  const Vec3d lo(bounds.lower), hi(bounds.upper);
  const Vec3d centre = (lo + hi) * 0.5;
  const double radius = 0.5 * length(hi - lo) + 1e-3;
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    const Vec3d from = centre + random.unitVector() * (1.5 * radius);
    const Vec3d to(random.uniform(lo.x, hi.x), random.uniform(lo.y, hi.y),
                   random.uniform(lo.z, hi.z));
    r.origin = Vec3f(from);
    r.direction = Vec3f(normalize(to - from));
  }
  return rays;
}

double eyeLight(const Scene& scene, const Ray& ray, std::uint32_t instance, std::uint32_t prim) {
  if (prim == kInvalidId) return 0.0;
  const TriangleMesh& mesh = scene.objectMesh(scene.instanceObject(instance));
  const Affine3d& m = scene.instanceTransform(instance);
  const Vec3d a = m.transformPoint(Vec3d(mesh.positions[mesh.indices[3 * prim]]));
  const Vec3d b = m.transformPoint(Vec3d(mesh.positions[mesh.indices[3 * prim + 1]]));
  const Vec3d c = m.transformPoint(Vec3d(mesh.positions[mesh.indices[3 * prim + 2]]));
  const Vec3d n = cross(b - a, c - a);
  const Vec3d d(ray.direction);
  const double denominator = length(n) * length(d);
  return denominator > 0.0 ? std::abs(dot(n, d)) / denominator : 0.0;
}

double eyeLightPsnr(const Scene& scene, std::span<const Ray> rays,
                    std::span<const ReferenceHit> reference, std::span<const RayOutcome> outcomes) {
  double sum = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const ReferenceHit& r = reference[i];
    const double expected = r.hit ? eyeLight(scene, rays[i], r.instanceId, r.primId) : 0.0;
    const double got = eyeLight(scene, rays[i], outcomes[i].instance, outcomes[i].prim);
    sum += (got - expected) * (got - expected);
  }
  if (sum == 0.0 || rays.empty()) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(static_cast<double>(rays.size()) / sum);
}

double ulpError(float t, double reference) {
  const auto rf = static_cast<float>(reference);
  const double ulp = static_cast<double>(std::nextafter(std::abs(rf), kInfinity)) -
                     static_cast<double>(std::abs(rf));
  return std::abs(static_cast<double>(t) - reference) / ulp;
}

std::vector<RayOutcome> traceOutcomes(const Scene& scene, std::span<const Ray> rays) {
  std::vector<RayOutcome> out(rays.size());
  traceOutcomes(scene, rays, out);
  return out;
}

void traceOutcomes(const Scene& scene, std::span<const Ray> rays, std::span<RayOutcome> out) {
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    TraversalContext ctx;
    Hit hit;
    for (std::size_t i = begin; i < end; ++i) {
      hit = Hit{};
      out[i] = scene.intersect(rays[i], hit, ctx) ? RayOutcome{hit.instanceId, hit.primId}
                                                  : RayOutcome{};
    }
  });
}

std::vector<RayOutcome> traceOutcomesInPackets(const Scene& scene, std::span<const Ray> rays) {
  std::vector<RayOutcome> out(rays.size());
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    TraversalContext ctx;
    std::vector<Hit> hits(end - begin);
    scene.intersect(rays.subspan(begin, end - begin), std::span<Hit>(hits), ctx);
    for (std::size_t i = begin; i < end; ++i)
      if (hits[i - begin].valid()) out[i] = {hits[i - begin].instanceId, hits[i - begin].primId};
  });
  return out;
}

Judgement probeScene(const Scene& scene, std::uint64_t seed) {
  const std::vector<Ray> rays = makeProbeRays(scene.bounds(), kProbeRays, seed);
  const ReferenceIntersector reference(scene);
  return judgeOutcomes(referenceHits(reference, rays), traceOutcomes(scene, rays));
}

}  // namespace tg::bench
