/// @file Animator.h
/// The animator role: a node evaluated from the clock whose output fields drive other fields.
#pragma once

#include <vector>

#include "tracegraph/scenegraph/Node.h"

namespace tg {

/// Base of time sensors, interpolators and deformers (Inventor's engines, VRML's
/// interpolators). SceneGraph::advanceTo evaluates every animator that feeds the graph, in
/// dependency order, then copies each output field to the fields connected from it.
///
/// Animators need not be in the graph; they are found through the connections of the nodes
/// that are. Evaluation must only write the animator's own fields.
class Animator : public Node {
 public:
  /// Updates the output fields for `time` (seconds on the SceneGraph's clock).
  virtual void evaluate(double time) = 0;
  /// Nodes read by evaluate() other than through connected fields (skin joints), so that
  /// animators driving them are evaluated first.
  virtual void dependencies(std::vector<Node*>& out) const;
  void accept(NodeVisitor& visitor) override;

 protected:
  Animator() = default;
};

}  // namespace tg
