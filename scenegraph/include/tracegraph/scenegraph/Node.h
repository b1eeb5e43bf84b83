/// @file Node.h
/// The base of every scene-graph node: reference count, fields, parents, change notification.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tracegraph/scenegraph/ChangeKind.h"
#include "tracegraph/scenegraph/Notification.h"
#include "tracegraph/scenegraph/Referenced.h"
#include "tracegraph/scenegraph/ref_ptr.h"

namespace tg {

class Field;
class Group;
class NodeVisitor;

/// A scene-graph node: owns named fields, knows its parents, and notifies upwards when a field
/// or its children change.
///
/// A node may have several parents (DEF/USE sharing); parent back-links are raw pointers kept
/// up to date by Group, while ownership flows downwards through ref_ptr. Nodes are created on
/// the heap through each class's create() and deleted when the last ref_ptr goes.
class Node : public Referenced {
 public:
  /// Class name as Inventor/VRML writes it ("Transform", "Separator").
  virtual std::string_view className() const { return "Node"; }
  /// The DEF name, empty when unnamed.
  const std::string& name() const { return name_; }
  /// Sets the DEF name (used by loaders and in error messages).
  void setName(std::string name) { name_ = std::move(name); }
  /// "Transform 'arm'" or "Transform" when unnamed, for messages.
  std::string label() const;

  /// The node's fields in declaration order.
  std::span<Field* const> fields() const { return fields_; }
  /// The field called `name`, or null.
  Field* field(std::string_view name) const;
  /// True when a field of one of `kinds` is connected to an animator (the node is driven).
  bool isDriven(ChangeKind kinds) const;
  /// True when any field is connected to an animator.
  bool hasConnectedField() const;

  /// Parent groups, one entry per link (a group holding this node twice appears twice).
  std::span<Group* const> parents() const { return parents_; }

  /// Registers an observer of this node and everything below it (not owned).
  void addObserver(NodeObserver* observer);
  /// Unregisters an observer; unknown observers are ignored.
  void removeObserver(NodeObserver* observer);
  /// Sends a notification to the observers of this node and of all its ancestors, each once.
  void notify(ChangeKind kind, const Field* field = nullptr, const Node* child = nullptr);

  /// Double dispatch to the visitor overload of this node's role.
  virtual void accept(NodeVisitor& visitor);

  /// Throws tg::Error naming `call` when this node lies under a scene graph that is being
  /// rendered (see SceneGraph::setRendering): frames must never observe half-done edits.
  void checkEditable(const char* call) const;

 protected:
  Node() = default;
  ~Node() override;
  /// Hook run before observers hear of a field change (caches, version counters).
  virtual void fieldChanged(const Field& field);

 private:
  friend class Field;
  friend class Group;
  void addParent(Group* parent) { parents_.push_back(parent); }
  void removeParent(Group* parent);
  void registerField(Field* field) { fields_.push_back(field); }
  void unregisterField(Field* field);

  std::string name_;
  std::vector<Field*> fields_;
  std::vector<Group*> parents_;
  std::vector<NodeObserver*> observers_;
  std::uint64_t lastNotification_ = 0;
};

}  // namespace tg
