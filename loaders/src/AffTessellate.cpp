#include "AffTessellate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <numbers>

namespace tg::aff_detail {
namespace {

/// Single-precision copy; components beyond the float range become ±infinity (a plain cast
/// would be undefined behaviour) so that the parser can reject the primitive.
Vec3f toFloat(const Vec3d& v) {
  const auto narrow = [](double x) {
    constexpr auto kMax = static_cast<double>(std::numeric_limits<float>::max());
    if (x > kMax) return std::numeric_limits<float>::infinity();
    if (x < -kMax) return -std::numeric_limits<float>::infinity();
    return static_cast<float>(x);
  };
  return {narrow(v.x), narrow(v.y), narrow(v.z)};
}

/// Unit vector, or `fallback` when v has no usable length (degenerate primitives must not
/// produce NaN normals).
Vec3d unitOr(const Vec3d& v, const Vec3d& fallback) {
  const double len = length(v);
  return len > 0.0 && std::isfinite(len) ? v / len : fallback;
}

/// Appends one triangle with separate position and normal index triples.
void addTriangle(AffMesh& m, std::initializer_list<std::uint32_t> p,
                 std::initializer_list<std::uint32_t> n) {
  m.positionIndices.insert(m.positionIndices.end(), p);
  m.normalIndices.insert(m.normalIndices.end(), n);
}

}  // namespace

AffMesh tessellateCone(const AffShape& shape, int segments) {
  const auto s = static_cast<std::uint32_t>(segments);
  AffMesh m;
  m.primitive = AffPrimitive::Cone;
  m.shape = shape;
  const Vec3d d = shape.apex - shape.base;
  const double len = length(d);
  const Vec3d axis = unitOr(d, {0, 1, 0});
  // Any unit u perpendicular to the axis, and v = axis × u, so that (u, v, axis) is
  // right-handed and increasing angles run counter-clockwise seen from the apex side.
  const Vec3d helper = std::abs(axis.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  const Vec3d u = unitOr(cross(axis, helper), {1, 0, 0});
  const Vec3d v = cross(axis, u);
  const bool baseIsPoint = shape.baseRadius == 0.0;
  const bool apexIsPoint = shape.apexRadius == 0.0 && !baseIsPoint;

  // Positions: base ring (or its single point), then apex ring (or its single point).
  const std::uint32_t baseCount = baseIsPoint ? 1 : s;
  const std::uint32_t apexCount = apexIsPoint ? 1 : s;
  m.positions.reserve(baseCount + apexCount);
  m.normals.reserve(s);
  for (std::uint32_t k = 0; k < s; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / s;
    const Vec3d e = u * std::cos(phi) + v * std::sin(phi);
    if (!baseIsPoint) m.positions.push_back(toFloat(shape.base + e * shape.baseRadius));
    // The surface P(h, phi) = base + h·d + r(h)·e has normal ∝ |d|·e − (r_apex − r_base)·axis.
    m.normals.push_back(toFloat(unitOr(e * len - axis * (shape.apexRadius - shape.baseRadius), e)));
  }
  if (baseIsPoint) m.positions.push_back(toFloat(shape.base));
  for (std::uint32_t k = 0; k < s && !apexIsPoint; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / s;
    m.positions.push_back(
        toFloat(shape.apex + (u * std::cos(phi) + v * std::sin(phi)) * shape.apexRadius));
  }
  if (apexIsPoint) m.positions.push_back(toFloat(shape.apex));

  const std::uint32_t triangles = (baseIsPoint || apexIsPoint) ? s : 2 * s;
  m.positionIndices.reserve(3 * triangles);
  m.normalIndices.reserve(3 * triangles);
  for (std::uint32_t k = 0; k < s; ++k) {
    const std::uint32_t k1 = (k + 1) % s;
    const std::uint32_t b0 = baseIsPoint ? 0 : k, b1 = baseIsPoint ? 0 : k1;
    const std::uint32_t a0 = baseCount + (apexIsPoint ? 0 : k);
    const std::uint32_t a1 = baseCount + (apexIsPoint ? 0 : k1);
    if (baseIsPoint) {
      addTriangle(m, {b0, a1, a0}, {k, k1, k});
    } else if (apexIsPoint) {
      addTriangle(m, {b0, b1, a0}, {k, k1, k});
    } else {
      addTriangle(m, {b0, b1, a1}, {k, k1, k1});
      addTriangle(m, {b0, a1, a0}, {k, k1, k});
    }
  }
  return m;
}

AffMesh tessellateSphere(const AffShape& shape, int segments) {
  const auto s = static_cast<std::uint32_t>(segments);
  const std::uint32_t rings = std::max<std::uint32_t>(2, s / 2);
  AffMesh m;
  m.primitive = AffPrimitive::Sphere;
  m.shape = shape;
  // Direction for polar angle theta (from +y) and azimuth phi. With this parametrisation
  // ∂/∂phi × ∂/∂theta points outwards, which fixes the corner order below.
  const auto dir = [](double theta, double phi) {
    return Vec3d{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
  };
  const auto addVertex = [&](const Vec3d& n) {
    m.positions.push_back(toFloat(shape.base + n * shape.baseRadius));
    m.normals.push_back(toFloat(n));
  };
  const std::uint32_t vertexCount = 2 + (rings - 1) * s;
  m.positions.reserve(vertexCount);
  m.normals.reserve(vertexCount);
  addVertex({0, 1, 0});  // north pole: index 0
  for (std::uint32_t i = 1; i < rings; ++i) {
    const double theta = std::numbers::pi * i / rings;
    for (std::uint32_t k = 0; k < s; ++k) addVertex(dir(theta, 2.0 * std::numbers::pi * k / s));
  }
  addVertex({0, -1, 0});  // south pole: last index
  const std::uint32_t south = vertexCount - 1;
  const auto ring = [s](std::uint32_t i, std::uint32_t k) { return 1 + (i - 1) * s + k % s; };
  const auto tri = [&m](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    m.positionIndices.insert(m.positionIndices.end(), {a, b, c});
  };
  m.positionIndices.reserve(6 * s * (rings - 1));
  for (std::uint32_t k = 0; k < s; ++k) tri(0, ring(1, k + 1), ring(1, k));
  for (std::uint32_t i = 1; i + 1 < rings; ++i) {
    for (std::uint32_t k = 0; k < s; ++k) {
      tri(ring(i, k), ring(i, k + 1), ring(i + 1, k));
      tri(ring(i, k + 1), ring(i + 1, k + 1), ring(i + 1, k));
    }
  }
  for (std::uint32_t k = 0; k < s; ++k) tri(ring(rings - 1, k), ring(rings - 1, k + 1), south);
  m.normalIndices = m.positionIndices;
  return m;
}

}  // namespace tg::aff_detail
