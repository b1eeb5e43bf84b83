// Animators for X3D features the nodes library does not model: TimeSensor.stopTime,
// NormalInterpolator, and ROUTEs into Coordinate/Normal nodes that were meshed with
// re-indexed vertices.
#include <algorithm>
#include <cmath>

#include "X3dImpl.h"
#include "tracegraph/nodes/KeyInterval.h"

namespace tg::x3d {
namespace {

/// Spherical interpolation of two directions (normalised; linear when nearly parallel).
Vec3f slerpDirection(const Vec3f& a, const Vec3f& b, float w) {
  const double la = length(Vec3d(a)), lb = length(Vec3d(b));
  if (la == 0.0 || lb == 0.0) return a + (b - a) * w;
  const Vec3d ua = Vec3d(a) / la, ub = Vec3d(b) / lb;
  const double c = std::clamp(dot(ua, ub), -1.0, 1.0);
  const double omega = std::acos(c);
  const double s = std::sin(omega);
  const double t = static_cast<double>(w);
  if (s < 1e-6) {
    const Vec3d v = ua + (ub - ua) * t;
    const double lv = length(v);
    return lv > 0.0 ? Vec3f(v / lv) : Vec3f(ua);
  }
  return Vec3f(ua * (std::sin((1.0 - t) * omega) / s) + ub * (std::sin(t * omega) / s));
}

}  // namespace

void TimeSensor::evaluate(double now) {
  const double stop = stopTime.getValue();
  // X3D ignores a stopTime not later than startTime; otherwise the outputs freeze at it.
  if (stop > startTime.getValue() && now > stop) now = stop;
  nodes::TimeSensor::evaluate(now);
}

void NormalInterpolator::evaluate(double) {
  const std::vector<float>& keys = key.getValues();
  const std::vector<Vec3f>& values = keyValue.getValues();
  if (keys.empty() || values.size() < keys.size()) return;
  const std::size_t n = values.size() / keys.size();
  const nodes::KeyInterval s = nodes::findKeyInterval(keys, set_fraction.getValue());
  std::vector<Vec3f> out(n);
  const std::size_t a = s.index * n;
  for (std::size_t i = 0; i < n; ++i)
    out[i] = s.weight == 0.0f ? values[a + i]
                              : slerpDirection(values[a + i], values[a + n + i], s.weight);
  value_changed.setValues(std::move(out));
}

ref_ptr<MeshDeformer> MeshDeformer::create(const MeshPart& part, std::vector<Vec3f> restCoords,
                                           std::vector<Vec3f> restNormals) {
  ref_ptr<MeshDeformer> d(new MeshDeformer());
  d->part_ = part;
  d->part_.mesh = nullptr;  // the mesh holds the deformer through its connection, not back
  d->set_point.setValues(std::move(restCoords));
  d->set_vector.setValues(std::move(restNormals));
  d->drive(*part.mesh);
  return d;
}

void MeshDeformer::evaluate(double) {
  const std::vector<Vec3f>& coords = set_point.getValues();
  const std::size_t nv = part_.vertexCoord.size();
  std::vector<Vec3f> points(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    const auto c = static_cast<std::size_t>(part_.vertexCoord[v]);
    // A routed list shorter than the Coordinate leaves the missing points at the origin,
    // which keeps the mesh valid whatever the interpolator holds.
    points[v] = c < coords.size() ? coords[c] : Vec3f{};
  }
  std::vector<Vec3f> normals(nv, Vec3f(0.0f, 1.0f, 0.0f));
  if (!part_.vertexNormal.empty()) {
    const std::vector<Vec3f>& given = set_vector.getValues();
    for (std::size_t v = 0; v < nv; ++v) {
      const auto i = static_cast<std::size_t>(part_.vertexNormal[v]);
      if (i < given.size()) {
        const float len = length(given[i]);
        if (len > 0.0f) normals[v] = given[i] / len;
      }
    }
  } else if (part_.faces) {
    normals = smoothNormals(faceNormals(*part_.faces, coords), part_);
  }
  normals_changed.setValues(std::move(normals));
  points_changed.setValues(std::move(points));
}

}  // namespace tg::x3d
