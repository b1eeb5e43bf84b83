/// @file Group.h
/// Node with ordered children; the base of Separator and Switch.
#pragma once

#include <cstddef>
#include <vector>

#include "tracegraph/scenegraph/Node.h"

namespace tg {

/// Holds ordered, reference-counted children. A plain Group does not isolate traversal state:
/// a Transform or Material among its children also applies to the siblings that follow the
/// Group (Open Inventor semantics); Separator isolates.
///
/// Every edit checks its arguments first and throws tg::Error naming the call (a null child,
/// an index out of range, a child that would make the graph cyclic), leaving the group as it
/// was; a successful edit notifies ChangeKind::Structure with the child concerned.
class Group : public Node {
 public:
  /// A new, empty group.
  static ref_ptr<Group> create() { return ref_ptr<Group>(new Group()); }
  std::string_view className() const override { return "Group"; }

  /// Appends a child.
  void addChild(ref_ptr<Node> child);
  /// Inserts a child before position `index` (index == numChildren() appends).
  void insertChild(std::size_t index, ref_ptr<Node> child);
  /// Replaces the child at `index`.
  void replaceChild(std::size_t index, ref_ptr<Node> child);
  /// Removes the child at `index`.
  void removeChild(std::size_t index);
  /// Removes the first occurrence of `child`; returns false when it is not a child.
  bool removeChild(const Node* child);
  /// Removes every child.
  void removeAllChildren();

  /// Number of children.
  std::size_t numChildren() const { return children_.size(); }
  /// Child `index` (unchecked).
  Node* child(std::size_t index) const { return children_[index].get(); }
  /// All children in order.
  const std::vector<ref_ptr<Node>>& children() const { return children_; }
  /// Index of the first occurrence of `child`, or -1.
  std::ptrdiff_t findChild(const Node* child) const;

  /// True when the group saves and restores transform and material state around its children
  /// (Separator); false for Group and Switch.
  virtual bool isolatesState() const { return false; }
  /// True when traversal visits child `index` (Switch selects one).
  virtual bool isChildActive(std::size_t index) const;

  void accept(NodeVisitor& visitor) override;

 protected:
  Group() = default;
  ~Group() override;

 private:
  void checkChild(const char* call, const Node* child) const;
  void insertAt(const char* call, std::size_t index, ref_ptr<Node> child);

  std::vector<ref_ptr<Node>> children_;
};

}  // namespace tg
