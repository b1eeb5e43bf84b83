/// @file Separator.h
/// Group that isolates transform and material state, as in Open Inventor.
#pragma once

#include "tracegraph/scenegraph/Group.h"

namespace tg::nodes {

/// Group that saves the current transform, material and texture before its children and
/// restores them after, so nothing inside affects the siblings that follow. It is also the
/// unit of sharing (a Separator with several parents becomes one object with one instance per
/// path) and of incremental re-traversal. Loaders map VRML/X3D `Transform { children }` to a
/// Separator holding a Transform followed by the children.
class Separator : public Group {
 public:
  /// A new, empty separator.
  static ref_ptr<Separator> create() { return ref_ptr<Separator>(new Separator()); }
  std::string_view className() const override { return "Separator"; }
  bool isolatesState() const override { return true; }

 protected:
  Separator() = default;
};

}  // namespace tg::nodes
