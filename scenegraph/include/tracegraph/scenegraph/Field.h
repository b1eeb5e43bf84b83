/// @file Field.h
/// The base of every field: a named, typed value of a node that notifies its owner when it
/// changes and can be connected to an animator's output (a VRML ROUTE).
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "tracegraph/scenegraph/ChangeKind.h"

namespace tg {

class Node;

/// A named value of a node. Changing it notifies the owner with the field's ChangeKind.
///
/// Connections play the role of VRML ROUTEs and Inventor field connections: a field connected
/// from an animator's field takes that field's value each time the animator is evaluated
/// (SceneGraph::advanceTo). A connected field marks its node as driven, which the classifier
/// reads as "this transform moves" or "this mesh deforms" before any change is observed.
class Field {
 public:
  Field(const Field&) = delete;
  Field& operator=(const Field&) = delete;
  virtual ~Field();

  /// The field's name inside its node ("translation").
  std::string_view name() const { return name_; }
  /// The node holding the field.
  Node& owner() const { return *owner_; }
  /// What a change of this field means for the sync.
  ChangeKind changeKind() const { return kind_; }
  /// Inventor/VRML type name ("SFVec3f", "MFInt32").
  virtual std::string_view typeName() const = 0;

  /// Takes this field's value from `source` whenever its animator is evaluated.
  ///
  /// Throws tg::Error naming "Field::connectFrom" when `source` does not belong to an
  /// Animator, when the types differ, or when the connection would close a cycle of
  /// animators; the field is then left as it was. A previous connection is replaced.
  void connectFrom(Field& source);
  /// Removes the incoming connection, if any; the value stays as last set.
  void disconnect();
  /// The field this one is connected from, or null.
  Field* connectedFrom() const { return source_; }
  /// True when connected from an animator.
  bool isConnected() const { return source_ != nullptr; }
  /// Fields connected from this one.
  std::span<Field* const> connections() const { return targets_; }
  /// Sets this field to `source`'s value; both must have the same type.
  virtual void copyValueFrom(const Field& source) = 0;

  /// Incremented by every connect and disconnect, so that schedules know when to rebuild.
  static std::uint64_t connectionGeneration();
  /// Bumps the connection generation; animators call it when what dependencies() returns
  /// changes, so that evaluation orders are recomputed.
  static void noteDependencyChange();

 protected:
  /// Registers the field with `owner`; `name` must outlive the field (a string literal).
  Field(Node& owner, const char* name, ChangeKind kind);
  /// Rejects the edit while the owner's graph renders (see Node::checkEditable).
  void beginEdit(const char* call) const;
  /// Runs the owner's hook and notifies observers of the owner and its ancestors.
  void valueChanged();

 private:
  Node* owner_;
  const char* name_;
  ChangeKind kind_;
  Field* source_ = nullptr;
  std::vector<Field*> targets_;
};

}  // namespace tg
