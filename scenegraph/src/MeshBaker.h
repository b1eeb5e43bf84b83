/// @file MeshBaker.h
/// Concatenates shapes into one backend mesh, applying each shape's baked matrix (internal).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/TriangleMesh.h"
#include "tracegraph/scenegraph/ShapeNode.h"

namespace tg::sync {

/// One shape of an object's content: which mesh, at which version, with which matrix.
struct ContentItem {
  const ShapeNode* shape = nullptr;
  std::uint64_t version = 0;  ///< 0 for deforming content (it follows the mesh)
  Affine3d bake;
  bool operator==(const ContentItem& o) const {
    return shape == o.shape && version == o.version && bake == o.bake;
  }
};

/// Builds the concatenation of `items` (triangles in item order) and writes the first
/// triangle index of each item into `primBegin`. Points are mapped by the bake matrix in
/// double and rounded to float once; normals by its inverse transpose. Items without normals
/// (or texture coordinates) get zero normals ((0, 0) coordinates) when other items have them:
/// the renderer then falls back to the geometric normal.
TriangleMesh bakeMesh(std::span<const ContentItem> items, std::vector<std::uint32_t>& primBegin);

/// Bounds of a shape's local bounds mapped by `bake`.
Box3d bakedBounds(const ShapeNode& shape, const Affine3d& bake);

}  // namespace tg::sync
