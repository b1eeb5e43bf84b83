/// @file TriangleMesh.h
/// Indexed triangle meshes as the engine stores them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Texture coordinate.
struct Vec2f {
  ///@{
  /// The coordinates.
  float u = 0.0f, v = 0.0f;
  ///@}
  /// Exact equality.
  bool operator==(const Vec2f&) const = default;
};

/// Indexed triangle mesh: float positions, three 32-bit indices per triangle, and optional
/// per-vertex normals and texture coordinates (empty, or one per position).
struct TriangleMesh {
  /// Vertex positions.
  std::vector<Vec3f> positions;
  std::vector<std::uint32_t> indices;  ///< 3 per triangle
  std::vector<Vec3f> normals;          ///< empty or positions.size()
  std::vector<Vec2f> uvs;              ///< empty or positions.size()

  /// indices.size() / 3.
  std::size_t triangleCount() const { return indices.size() / 3; }
  /// Bounds of the positions referenced by triangles.
  Box3f bounds() const;

  /// Checks the mesh and returns an empty string, or a message naming the first problem:
  /// an index count not a multiple of 3, an index out of range, a NaN/Inf position,
  /// attribute arrays of the wrong size. Degenerate triangles are legal (never hit).
  std::string validate() const;
};

/// True when the triangle has zero area in exact arithmetic on its float vertices
/// (repeated or collinear vertices). Such triangles are never hit and are counted by builders.
bool isDegenerateTriangle(const Vec3f& a, const Vec3f& b, const Vec3f& c);

}  // namespace tg
