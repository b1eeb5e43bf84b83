/// @file ShapeNode.h
/// The shape role: a node holding an indexed triangle mesh in its local frame.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/TriangleMesh.h"
#include "tracegraph/backend/Vec3.h"
#include "tracegraph/scenegraph/Node.h"

namespace tg {

/// Views of a shape's arrays, valid until the shape is next edited.
struct ShapeGeometry {
  /// Positions in the local frame.
  std::span<const Vec3f> points;
  std::span<const std::int32_t> indices;  ///< three per triangle
  std::span<const Vec3f> normals;         ///< empty or one per point
  std::span<const Vec2f> uvs;             ///< empty or one per point
};

/// Role of Mesh: geometry drawn with the current transform and material.
class ShapeNode : public Node {
 public:
  /// The arrays as they are now.
  virtual ShapeGeometry geometry() const = 0;
  /// Incremented by every change of points, indices, normals or texture coordinates, so the
  /// sync can tell an unchanged mesh from a changed one without comparing arrays.
  virtual std::uint64_t geometryVersion() const = 0;
  /// Bounds of the referenced points in the local frame (empty when there are none).
  virtual Box3f localBounds() const = 0;
  /// Empty when the geometry can be drawn, else the first problem (index out of range,
  /// index count not a multiple of 3, attribute count mismatch).
  virtual std::string validate() const = 0;
  /// Number of triangles.
  std::size_t triangleCount() const { return geometry().indices.size() / 3; }
  void accept(NodeVisitor& visitor) override;

 protected:
  ShapeNode() = default;
};

}  // namespace tg
