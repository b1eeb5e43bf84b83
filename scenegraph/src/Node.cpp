#include "tracegraph/scenegraph/Node.h"

#include <algorithm>
#include <atomic>

#include "RenderingRegistry.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/scenegraph/Field.h"
#include "tracegraph/scenegraph/Group.h"
#include "tracegraph/scenegraph/NodeVisitor.h"

namespace tg {
namespace {

// Serial numbers let one notification reach each ancestor once even when the graph is a DAG
// with many paths up to the root: a node already stamped with the serial is skipped.
std::atomic<std::uint64_t> gNotificationSerial{0};

}  // namespace

Node::~Node() = default;

std::string Node::label() const {
  std::string s(className());
  if (!name_.empty()) s += " '" + name_ + "'";
  return s;
}

Field* Node::field(std::string_view name) const {
  for (Field* f : fields_)
    if (f->name() == name) return f;
  return nullptr;
}

bool Node::isDriven(ChangeKind kinds) const {
  for (const Field* f : fields_)
    if (f->isConnected() && hasAny(f->changeKind(), kinds)) return true;
  return false;
}

bool Node::hasConnectedField() const {
  for (const Field* f : fields_)
    if (f->isConnected()) return true;
  return false;
}

void Node::addObserver(NodeObserver* observer) {
  if (observer && std::find(observers_.begin(), observers_.end(), observer) == observers_.end())
    observers_.push_back(observer);
}

void Node::removeObserver(NodeObserver* observer) {
  observers_.erase(std::remove(observers_.begin(), observers_.end(), observer), observers_.end());
}

void Node::notify(ChangeKind kind, const Field* field, const Node* child) {
  const Notification n{this, kind, field, child};
  const std::uint64_t serial = gNotificationSerial.fetch_add(1, std::memory_order_relaxed) + 1;
  std::vector<Node*> stack{this};
  while (!stack.empty()) {
    Node* node = stack.back();
    stack.pop_back();
    if (node->lastNotification_ == serial) continue;
    node->lastNotification_ = serial;
    for (NodeObserver* o : node->observers_) o->nodeChanged(n);
    for (Group* p : node->parents_) stack.push_back(p);
  }
}

void Node::accept(NodeVisitor& visitor) {
  visitor.apply(*this);
}

void Node::checkEditable(const char* call) const {
  if (detail::isUnderRenderingRoot(*this))
    throw Error(label() + ": " + call +
                " rejected: the scene graph is being rendered (edit between frames)");
}

void Node::fieldChanged(const Field&) {}

void Node::removeParent(Group* parent) {
  auto it = std::find(parents_.begin(), parents_.end(), parent);
  if (it != parents_.end()) parents_.erase(it);
}

void Node::unregisterField(Field* field) {
  fields_.erase(std::remove(fields_.begin(), fields_.end(), field), fields_.end());
}

}  // namespace tg
