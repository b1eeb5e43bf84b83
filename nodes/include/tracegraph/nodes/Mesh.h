/// @file Mesh.h
/// Indexed triangle mesh with optional normals and texture coordinates.
#pragma once

#include <cstdint>
#include <vector>

#include "tracegraph/scenegraph/MField.h"
#include "tracegraph/scenegraph/ShapeNode.h"

namespace tg::nodes {

/// Triangles drawn with the current transform, material and texture. `indices` holds three
/// point indices per triangle (no -1 separators). A mesh whose points change (directly, or
/// through a connected deformer) is classified deforming; otherwise it is static or rigid by
/// the transforms above it.
///
/// Fields may be set in any order; the mesh is checked when synced, and an invalid mesh
/// (index out of range, wrong attribute count) is skipped, not drawn, until it is valid.
class Mesh : public ShapeNode {
 public:
  /// A new, empty mesh.
  static ref_ptr<Mesh> create() { return ref_ptr<Mesh>(new Mesh()); }
  /// A new mesh with points and indices.
  static ref_ptr<Mesh> create(std::vector<Vec3f> points, std::vector<std::int32_t> indices);
  std::string_view className() const override { return "Mesh"; }

  ShapeGeometry geometry() const override;
  std::uint64_t geometryVersion() const override { return version_; }
  Box3f localBounds() const override;
  std::string validate() const override;

  /// Positions in the local frame.
  MFVec3f points{*this, "points", ChangeKind::Points};
  /// Three point indices per triangle.
  MFInt32 indices{*this, "indices", ChangeKind::Topology};
  MFVec3f normals{*this, "normals", ChangeKind::Points};        ///< empty or one per point
  MFVec2f texCoords{*this, "texCoords", ChangeKind::Topology};  ///< empty or one per point

 protected:
  Mesh() = default;
  void fieldChanged(const Field& field) override;

 private:
  std::uint64_t version_ = 1;
  mutable Box3f bounds_;
  mutable bool boundsValid_ = false;
};

}  // namespace tg::nodes
