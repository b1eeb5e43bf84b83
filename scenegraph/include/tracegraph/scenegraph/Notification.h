/// @file Notification.h
/// The message a node sends to its observers and ancestors when it changes.
#pragma once

#include "tracegraph/scenegraph/ChangeKind.h"

namespace tg {

class Field;
class Node;

/// One change: which node, what kind, through which field, and for structure changes which
/// child was added or removed.
struct Notification {
  Node* source = nullptr;  ///< the node that changed
  /// What changed.
  ChangeKind kind = ChangeKind::None;
  const Field* field = nullptr;  ///< the field that changed, or null (structure changes)
  const Node* child = nullptr;   ///< the child added/removed by a structure change, or null
};

/// Receives the notifications of a node and of everything below it.
///
/// Observers must not edit the graph from nodeChanged(); they record what changed and act
/// later (the sync keeps a dirty set and works through it once per frame).
class NodeObserver {
 public:
  virtual ~NodeObserver() = default;
  /// Called once per change for each observed node at or above the changed one.
  virtual void nodeChanged(const Notification& notification) = 0;
};

}  // namespace tg
