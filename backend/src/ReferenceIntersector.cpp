#include "tracegraph/backend/ReferenceIntersector.h"

#include <algorithm>
#include <cmath>

namespace tg {
namespace {

/// Relative width (of the coordinates' magnitude) of the band around an edge or an interval
/// end inside which float and double may legitimately disagree: about 32 float ulps. The float
/// test shears the triangle relative to the ray origin, so its lateral error is a few ulps of
/// the origin-to-vertex distance, amplified by the edge functions' products.
constexpr double kAmbiguityBand = 4e-6;

struct DoubleHit {
  double t, u, v;
  double margin;  ///< signed distance of the plane hit to the nearest edge (negative outside)
};

/// Möller–Trumbore in double without early rejection, so that callers see how far outside
/// (margin) a near miss is.
std::optional<DoubleHit> intersectDouble(const Vec3d& o, const Vec3d& d, const Vec3d& v0,
                                         const Vec3d& v1, const Vec3d& v2) {
  const Vec3d e1 = v1 - v0, e2 = v2 - v0;
  const Vec3d p = cross(d, e2);
  const double det = dot(e1, p);
  if (det == 0.0) return std::nullopt;  // ray parallel to the plane
  const double inv = 1.0 / det;
  const Vec3d s = o - v0;
  const double u = dot(s, p) * inv;
  const Vec3d q = cross(s, e1);
  const double v = dot(d, q) * inv;
  const double t = dot(e2, q) * inv;
  // Barycentric i times twice the area over the length of edge i is the distance to that edge:
  // measuring in space, not in barycentrics, keeps slivers from looking safely inside.
  const double twiceArea = length(cross(e1, e2));
  const double w = 1.0 - u - v;
  const double inPlane = std::min(
      {w * twiceArea / length(v2 - v1), u * twiceArea / length(e2), v * twiceArea / length(e1)});
  // The float test decides in the plane perpendicular to the ray, where in-plane distances
  // shrink by the cosine of the incidence angle: grazing hits are ambiguous over a wider band.
  const double cosine = std::abs(det) / (twiceArea * length(d));
  return DoubleHit{t, u, v, inPlane * cosine};
}

}  // namespace

ReferenceIntersector::ReferenceIntersector(const Scene& scene) {
  // Scene ids are dense indices; walk them until every live instance has been seen.
  const std::size_t live = scene.instanceCount();
  std::size_t seen = 0;
  for (InstanceId id = 0; seen < live; ++id) {
    ObjectId object;
    try {
      object = scene.instanceObject(id);
    } catch (const std::exception&) {
      continue;  // destroyed instance
    }
    ++seen;
    const Affine3d& m = scene.instanceTransform(id);
    const TriangleMesh& mesh = scene.objectMesh(object);
    if (index_.size() <= id) index_.resize(id + 1);
    index_[id].assign(mesh.triangleCount(), SIZE_MAX);
    for (std::uint32_t prim = 0; prim < mesh.triangleCount(); ++prim) {
      const Vec3f& a = mesh.positions[mesh.indices[3 * prim]];
      const Vec3f& b = mesh.positions[mesh.indices[3 * prim + 1]];
      const Vec3f& c = mesh.positions[mesh.indices[3 * prim + 2]];
      if (isDegenerateTriangle(a, b, c)) continue;  // the engine's rule: never hit
      index_[id][prim] = triangles_.size();
      triangles_.push_back({m.transformPoint(Vec3d(a)), m.transformPoint(Vec3d(b)),
                            m.transformPoint(Vec3d(c)), id, prim});
    }
  }
}

double ReferenceIntersector::tolerance(const Ray& ray, double t) {
  // Float geometry carries a relative error of ~1e-7 of the coordinates' magnitude; expressed
  // in t units (the direction need not be unit length) that is |position| / |direction|.
  const Vec3d o(ray.origin), d(ray.direction);
  const double scale = (length(o) + std::abs(t) * length(d)) / length(d);
  return kAmbiguityBand * std::max(scale, 1e-30);
}

ReferenceHit ReferenceIntersector::intersect(const Ray& ray) const {
  const Vec3d o(ray.origin), d(ray.direction);
  const double tnear = ray.tnear, tfar = ray.tfar;
  ReferenceHit best;
  best.t = std::numeric_limits<double>::infinity();
  double nearestAmbiguousT = std::numeric_limits<double>::infinity();
  // Pass 1: the closest sure hit, and the nearest t where a near-edge or near-end case sits.
  for (const Triangle& tri : triangles_) {
    const auto h = intersectDouble(o, d, tri.v0, tri.v1, tri.v2);
    if (!h || !std::isfinite(h->t)) continue;
    const double tol = tolerance(ray, h->t);
    const double band = tol * length(d);  // the same tolerance in world units
    const bool nearEdge = std::abs(h->margin) <= band;
    const bool nearEnd = std::abs(h->t - tnear) <= tol || std::abs(h->t - tfar) <= tol;
    const bool inside = h->margin >= 0.0 && h->t >= tnear && h->t <= tfar;
    if ((nearEdge || nearEnd) && h->t >= tnear - tol && h->t <= tfar + tol)
      nearestAmbiguousT = std::min(nearestAmbiguousT, h->t);
    if (!inside) continue;
    if (h->t < best.t || (h->t == best.t && std::pair(tri.instanceId, tri.primId) <
                                                std::pair(best.instanceId, best.primId))) {
      best.hit = true;
      best.t = h->t;
      best.instanceId = tri.instanceId;
      best.primId = tri.primId;
    }
  }
  if (std::isfinite(nearestAmbiguousT) &&
      nearestAmbiguousT <= best.t + tolerance(ray, best.hit ? best.t : nearestAmbiguousT))
    best.hitAmbiguous = true;
  if (best.hit) {
    // Pass 2: does another triangle compete within the tolerance?
    const double tol = tolerance(ray, best.t);
    for (const Triangle& tri : triangles_) {
      if (tri.instanceId == best.instanceId && tri.primId == best.primId) continue;
      const auto h = intersectDouble(o, d, tri.v0, tri.v1, tri.v2);
      if (h && h->margin >= -tol * length(d) && std::abs(h->t - best.t) <= tol) {
        best.primAmbiguous = true;
        break;
      }
    }
  }
  return best;
}

bool ReferenceIntersector::occluded(const Ray& ray, bool* ambiguous) const {
  const Vec3d o(ray.origin), d(ray.direction);
  const double tnear = ray.tnear, tfar = ray.tfar;
  bool sure = false, unsure = false;
  for (const Triangle& tri : triangles_) {
    const auto h = intersectDouble(o, d, tri.v0, tri.v1, tri.v2);
    if (!h || !std::isfinite(h->t)) continue;
    const double tol = tolerance(ray, h->t);
    const bool inRange = h->t >= tnear && h->t <= tfar;
    const bool nearEnd = std::abs(h->t - tnear) <= tol || std::abs(h->t - tfar) <= tol;
    const double band = tol * length(d);
    const bool nearEdge = std::abs(h->margin) <= band;
    if (h->margin >= 0.0 && inRange && !nearEdge && !nearEnd) {
      sure = true;
      break;
    }
    if ((nearEdge || nearEnd) && h->t >= tnear - tol && h->t <= tfar + tol && h->margin >= -band)
      unsure = true;
  }
  if (ambiguous) *ambiguous = !sure && unsure;
  return sure;
}

std::optional<double> ReferenceIntersector::intersectTriangle(const Ray& ray,
                                                              std::uint32_t instanceId,
                                                              std::uint32_t primId) const {
  if (instanceId >= index_.size() || primId >= index_[instanceId].size()) return std::nullopt;
  const std::size_t slot = index_[instanceId][primId];
  if (slot == SIZE_MAX) return std::nullopt;
  const Triangle& tri = triangles_[slot];
  const auto h = intersectDouble(Vec3d(ray.origin), Vec3d(ray.direction), tri.v0, tri.v1, tri.v2);
  if (!h || h->margin < -tolerance(ray, h->t) * length(Vec3d(ray.direction))) return std::nullopt;
  return h->t;
}

}  // namespace tg
