#include "tracegraph/scenegraph/NodeVisitor.h"

#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/CameraNode.h"
#include "tracegraph/scenegraph/Group.h"
#include "tracegraph/scenegraph/LightNode.h"
#include "tracegraph/scenegraph/MaterialNode.h"
#include "tracegraph/scenegraph/ShapeNode.h"
#include "tracegraph/scenegraph/TextureNode.h"
#include "tracegraph/scenegraph/TransformNode.h"

namespace tg {

void NodeVisitor::apply(Node&) {}

void NodeVisitor::apply(Group& group) {
  for (std::size_t i = 0; i < group.numChildren(); ++i)
    if (group.isChildActive(i)) group.child(i)->accept(*this);
}

void NodeVisitor::apply(TransformNode& transform) {
  apply(static_cast<Node&>(transform));
}
void NodeVisitor::apply(ShapeNode& shape) {
  apply(static_cast<Node&>(shape));
}
void NodeVisitor::apply(MaterialNode& material) {
  apply(static_cast<Node&>(material));
}
void NodeVisitor::apply(TextureNode& texture) {
  apply(static_cast<Node&>(texture));
}
void NodeVisitor::apply(LightNode& light) {
  apply(static_cast<Node&>(light));
}
void NodeVisitor::apply(CameraNode& camera) {
  apply(static_cast<Node&>(camera));
}
void NodeVisitor::apply(Animator& animator) {
  apply(static_cast<Node&>(animator));
}

// Each role forwards to its own overload; this is the whole double dispatch.
void TransformNode::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}
void ShapeNode::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}
void MaterialNode::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}
void TextureNode::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}
void LightNode::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}
void CameraNode::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}
void Animator::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}
void Animator::dependencies(std::vector<Node*>&) const {}

}  // namespace tg
