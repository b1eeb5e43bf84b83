#include "tracegraph/scenegraph/Group.h"

#include <string>
#include <unordered_set>

#include "tracegraph/backend/Error.h"
#include "tracegraph/scenegraph/NodeVisitor.h"

namespace tg {

Group::~Group() {
  for (const ref_ptr<Node>& c : children_) c->removeParent(this);
}

void Group::checkChild(const char* call, const Node* child) const {
  checkEditable(call);
  if (!child) throw Error(std::string(call) + ": null child");
  // Adding `child` below this group closes a cycle exactly when `child` is this group or one
  // of its ancestors; walk up once per node (DAGs may reach an ancestor along many paths).
  std::vector<const Node*> stack{this};
  std::unordered_set<const Node*> seen;
  while (!stack.empty()) {
    const Node* n = stack.back();
    stack.pop_back();
    if (n == child)
      throw Error(std::string(call) + ": adding " + child->label() + " under " + label() +
                  " would create a cycle");
    if (!seen.insert(n).second) continue;
    for (const Group* p : n->parents()) stack.push_back(p);
  }
}

void Group::addChild(ref_ptr<Node> child) {
  insertAt("Group::addChild", children_.size(), std::move(child));
}

void Group::insertChild(std::size_t index, ref_ptr<Node> child) {
  insertAt("Group::insertChild", index, std::move(child));
}

void Group::insertAt(const char* call, std::size_t index, ref_ptr<Node> child) {
  checkChild(call, child.get());
  if (index > children_.size())
    throw Error(std::string(call) + ": index " + std::to_string(index) + " is past the end (" +
                std::to_string(children_.size()) + " children)");
  Node* c = child.get();
  children_.insert(children_.begin() + static_cast<std::ptrdiff_t>(index), std::move(child));
  c->addParent(this);
  notify(ChangeKind::Structure, nullptr, c);
}

void Group::replaceChild(std::size_t index, ref_ptr<Node> child) {
  checkChild("Group::replaceChild", child.get());
  if (index >= children_.size())
    throw Error("Group::replaceChild: index " + std::to_string(index) + " out of range (" +
                std::to_string(children_.size()) + " children)");
  ref_ptr<Node> old = children_[index];
  Node* c = child.get();
  children_[index] = std::move(child);
  c->addParent(this);
  old->removeParent(this);
  notify(ChangeKind::Structure, nullptr, old.get());
  notify(ChangeKind::Structure, nullptr, c);
}

void Group::removeChild(std::size_t index) {
  checkEditable("Group::removeChild");
  if (index >= children_.size())
    throw Error("Group::removeChild: index " + std::to_string(index) + " out of range (" +
                std::to_string(children_.size()) + " children)");
  // Keep the child alive until observers have heard of its removal.
  ref_ptr<Node> old = children_[index];
  children_.erase(children_.begin() + static_cast<std::ptrdiff_t>(index));
  old->removeParent(this);
  notify(ChangeKind::Structure, nullptr, old.get());
}

bool Group::removeChild(const Node* child) {
  const std::ptrdiff_t i = findChild(child);
  if (i < 0) return false;
  removeChild(static_cast<std::size_t>(i));
  return true;
}

void Group::removeAllChildren() {
  checkEditable("Group::removeAllChildren");
  if (children_.empty()) return;
  std::vector<ref_ptr<Node>> old;
  old.swap(children_);
  for (const ref_ptr<Node>& c : old) c->removeParent(this);
  for (const ref_ptr<Node>& c : old) notify(ChangeKind::Structure, nullptr, c.get());
}

std::ptrdiff_t Group::findChild(const Node* child) const {
  for (std::size_t i = 0; i < children_.size(); ++i)
    if (children_[i].get() == child) return static_cast<std::ptrdiff_t>(i);
  return -1;
}

bool Group::isChildActive(std::size_t) const {
  return true;
}

void Group::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}

}  // namespace tg
