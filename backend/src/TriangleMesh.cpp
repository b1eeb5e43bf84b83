#include "tracegraph/backend/TriangleMesh.h"

#include <cmath>

namespace tg {

Box3f TriangleMesh::bounds() const {
  Box3f b;
  for (std::uint32_t i : indices) b.extend(positions[i]);
  return b;
}

std::string TriangleMesh::validate() const {
  if (indices.size() % 3 != 0)
    return "index count " + std::to_string(indices.size()) + " is not a multiple of 3";
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!isFinite(positions[i])) return "position " + std::to_string(i) + " is NaN or infinite";
  for (std::size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= positions.size())
      return "index " + std::to_string(indices[i]) + " (at " + std::to_string(i) +
             ") is out of range for " + std::to_string(positions.size()) + " positions";
  if (!normals.empty() && normals.size() != positions.size())
    return std::to_string(normals.size()) + " normals for " + std::to_string(positions.size()) +
           " positions";
  for (std::size_t i = 0; i < normals.size(); ++i)
    if (!isFinite(normals[i])) return "normal " + std::to_string(i) + " is NaN or infinite";
  if (!uvs.empty() && uvs.size() != positions.size())
    return std::to_string(uvs.size()) + " texture coordinates for " +
           std::to_string(positions.size()) + " positions";
  for (std::size_t i = 0; i < uvs.size(); ++i)
    if (!std::isfinite(uvs[i].u) || !std::isfinite(uvs[i].v))
      return "texture coordinate " + std::to_string(i) + " is NaN or infinite";
  return {};
}

bool isDegenerateTriangle(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  // Differences of floats are exact in double, and so are products of two of them, so the
  // cross product below is zero exactly when the float vertices are collinear (up to one
  // rounding in the final subtraction, which cannot turn a non-zero result into zero).
  const Vec3d e1 = Vec3d(b) - Vec3d(a);
  const Vec3d e2 = Vec3d(c) - Vec3d(a);
  const Vec3d n = cross(e1, e2);
  return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
}

}  // namespace tg
