/// @file KdTreeAccel.h
/// The paper's object accelerators: a kd-tree built with the SAH builder (static and rigid
/// objects) or with the fast builder (deforming objects), behind the ObjectAccel interface.
#pragma once

#include <vector>

#include "tracegraph/backend/KdTree.h"
#include "tracegraph/backend/ObjectAccel.h"

namespace tg {

/// A kd-tree over one mesh; `kind` chooses the builder.
class KdTreeAccel final : public ObjectAccel {
 public:
  /// An unbuilt tree; `kind` chooses the builder.
  explicit KdTreeAccel(AccelKind kind) : kind_(kind) {}

  AccelKind kind() const override { return kind_; }
  void build(const TriangleMesh& mesh) override;
  Box3f bounds() const override { return tree_.bounds; }
  bool intersect(ObjectRay& ray, Hit& hit, TraversalContext& ctx) const override {
    return intersectKdTree(tree_, triangles_, ray, hit, ctx);
  }
  bool occluded(const ObjectRay& ray, TraversalContext& ctx) const override {
    return occludedKdTree(tree_, triangles_, ray, ctx);
  }
  const BuildStats& stats() const override { return tree_.stats; }

  /// The built tree (for tests and statistics).
  const KdTree& tree() const { return tree_; }
  /// The triangles the tree indexes, in mesh order.
  const std::vector<TriangleVertices>& triangles() const { return triangles_; }

 private:
  AccelKind kind_;
  std::vector<TriangleVertices> triangles_;
  KdTree tree_;
};

}  // namespace tg
