// Queries over a node graph for loader tests: walk every node, collect distinct nodes of a
// type, find a node by name.
#pragma once

#include <set>
#include <string>

#include "tracegraph/scenegraph/Group.h"

namespace tg::test {

/// Calls f on every node below `n` (depth first, shared nodes once per path).
template <typename F>
void walk(Node* n, F&& f) {
  f(n);
  if (auto* g = dynamic_cast<Group*>(n))
    for (const ref_ptr<Node>& c : g->children()) walk(c.get(), f);
}

/// The distinct nodes of type T below `root`.
template <typename T>
std::set<T*> distinct(Node* root) {
  std::set<T*> out;
  walk(root, [&](Node* n) {
    if (auto* t = dynamic_cast<T*>(n)) out.insert(t);
  });
  return out;
}

/// The first node named `name` below `root` (depth first), as a T, or null.
template <typename T>
T* named(Node* root, const std::string& name) {
  T* found = nullptr;
  walk(root, [&](Node* n) {
    if (!found && n->name() == name) found = dynamic_cast<T*>(n);
  });
  return found;
}

}  // namespace tg::test
