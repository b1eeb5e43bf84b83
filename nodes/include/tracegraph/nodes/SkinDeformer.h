/// @file SkinDeformer.h
/// Linear-blend skinning driven by joint transforms.
#pragma once

#include <vector>

#include "tracegraph/nodes/Deformer.h"
#include "tracegraph/scenegraph/TransformNode.h"

namespace tg::nodes {

/// Linear-blend skinning: each point moves with up to four joints,
/// p = sum_k w_k * G_k * B_k * rest, where G_k is joint k's global matrix (its parents'
/// local matrices times its own, along `jointParents`) and B_k its inverse bind matrix.
/// The joints are transform nodes (usually Transforms driven by interpolators); they need not
/// be in the graph. Normals, when given, follow the joints' linear parts and are renormalised.
class SkinDeformer : public Deformer {
 public:
  /// A new deformer without joints.
  static ref_ptr<SkinDeformer> create() { return ref_ptr<SkinDeformer>(new SkinDeformer()); }
  std::string_view className() const override { return "SkinDeformer"; }
  void evaluate(double time) override;
  void dependencies(std::vector<Node*>& out) const override;

  /// Sets the joints (index = joint number in jointIndices and jointParents).
  void setJoints(std::vector<ref_ptr<TransformNode>> joints);
  /// The joints.
  const std::vector<ref_ptr<TransformNode>>& joints() const { return joints_; }

  /// Points in the bind pose.
  MFVec3f restPoints{*this, "restPoints", ChangeKind::Parameter};
  /// Normals in the bind pose (empty: no normals output).
  MFVec3f restNormals{*this, "restNormals", ChangeKind::Parameter};
  MFInt32 jointIndices{*this, "jointIndices", ChangeKind::Parameter};  ///< 4 per point
  MFFloat jointWeights{*this, "jointWeights", ChangeKind::Parameter};  ///< 4 per point
  MFInt32 jointParents{*this, "jointParents", ChangeKind::Parameter};  ///< -1 or a lower index
  /// Per joint: world-to-joint matrix of the bind pose.
  MFMatrix inverseBindMatrices{*this, "inverseBindMatrices", ChangeKind::Parameter};

 protected:
  SkinDeformer() = default;
  bool producesNormals() const override { return !restNormals.empty(); }

 private:
  std::vector<ref_ptr<TransformNode>> joints_;
};

}  // namespace tg::nodes
