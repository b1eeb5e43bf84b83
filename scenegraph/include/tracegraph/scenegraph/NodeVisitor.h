/// @file NodeVisitor.h
/// Double-dispatch visitor over the node roles.
#pragma once

namespace tg {

class Animator;
class CameraNode;
class Group;
class LightNode;
class MaterialNode;
class Node;
class ShapeNode;
class TextureNode;
class TransformNode;

/// Visits nodes by role. Each role overload defaults to apply(Node&), which does nothing;
/// apply(Group&) defaults to visiting the active children in order. Derived visitors override
/// the roles they care about (and add `using NodeVisitor::apply;`).
class NodeVisitor {
 public:
  virtual ~NodeVisitor() = default;
  /// Any node without a more specific role.
  virtual void apply(Node& node);
  /// Groups; by default visits the active children in order.
  virtual void apply(Group& group);
  /// Transform and MatrixTransform.
  virtual void apply(TransformNode& transform);
  /// Meshes.
  virtual void apply(ShapeNode& shape);
  /// Materials.
  virtual void apply(MaterialNode& material);
  /// Textures.
  virtual void apply(TextureNode& texture);
  /// Lights.
  virtual void apply(LightNode& light);
  /// Cameras.
  virtual void apply(CameraNode& camera);
  /// Animators (interpolators, time sensors, deformers).
  virtual void apply(Animator& animator);
};

}  // namespace tg
