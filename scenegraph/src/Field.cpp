#include "tracegraph/scenegraph/Field.h"

#include <algorithm>
#include <atomic>
#include <string>
#include <unordered_set>

#include "RenderingRegistry.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/Node.h"

namespace tg {
namespace {

std::atomic<std::uint64_t> gConnectionGeneration{0};

std::string describe(const Field& f) {
  return f.owner().label() + "." + std::string(f.name()) + " (" + std::string(f.typeName()) + ")";
}

/// True when `target` is `start` or feeds it, directly or through animators upstream of it:
/// then connecting `target` from a field of `start` would close a cycle.
bool feeds(const Node& target, Node& start) {
  std::vector<Node*> stack{&start};
  std::unordered_set<const Node*> seen;
  std::vector<Node*> deps;
  while (!stack.empty()) {
    Node* n = stack.back();
    stack.pop_back();
    if (n == &target) return true;
    if (!seen.insert(n).second) continue;
    for (const Field* f : n->fields())
      if (f->connectedFrom()) stack.push_back(&f->connectedFrom()->owner());
    if (const auto* a = dynamic_cast<const Animator*>(n)) {
      deps.clear();
      a->dependencies(deps);
      for (Node* d : deps) stack.push_back(d);
    }
  }
  return false;
}

}  // namespace

Field::Field(Node& owner, const char* name, ChangeKind kind)
    : owner_(&owner), name_(name), kind_(kind) {
  owner.registerField(this);
}

Field::~Field() {
  if (source_) {
    auto& t = source_->targets_;
    t.erase(std::remove(t.begin(), t.end(), this), t.end());
    source_->owner_->unref();
    source_ = nullptr;
  }
  // Targets hold a reference to our owner, so this list is normally empty here.
  for (Field* t : targets_) t->source_ = nullptr;
  owner_->unregisterField(this);
}

std::uint64_t Field::connectionGeneration() {
  return gConnectionGeneration.load(std::memory_order_relaxed);
}

void Field::noteDependencyChange() {
  gConnectionGeneration.fetch_add(1, std::memory_order_relaxed);
}

void Field::connectFrom(Field& source) {
  beginEdit("connectFrom");
  if (!dynamic_cast<const Animator*>(source.owner_))
    throw Error("Field::connectFrom: source " + describe(source) +
                " does not belong to an animator");
  if (source.typeName() != typeName())
    throw Error("Field::connectFrom: cannot connect " + describe(*this) + " from " +
                describe(source) + ": types differ");
  if (feeds(*owner_, *source.owner_))
    throw Error("Field::connectFrom: connecting " + describe(*this) + " from " + describe(source) +
                " would create a cycle of animators");
  if (source_ == &source) return;
  source.owner_->ref();
  if (source_) {
    auto& t = source_->targets_;
    t.erase(std::remove(t.begin(), t.end(), this), t.end());
    source_->owner_->unref();
  }
  source_ = &source;
  source.targets_.push_back(this);
  gConnectionGeneration.fetch_add(1, std::memory_order_relaxed);
  owner_->notify(ChangeKind::Connection, this);
}

void Field::disconnect() {
  if (!source_) return;
  beginEdit("disconnect");
  auto& t = source_->targets_;
  t.erase(std::remove(t.begin(), t.end(), this), t.end());
  source_->owner_->unref();
  source_ = nullptr;
  gConnectionGeneration.fetch_add(1, std::memory_order_relaxed);
  owner_->notify(ChangeKind::Connection, this);
}

void Field::beginEdit(const char* call) const {
  // Cheap (one atomic load) unless some graph is being rendered.
  if (detail::isUnderRenderingRoot(*owner_))
    throw Error(owner_->label() + "." + name_ + "::" + call +
                " rejected: the scene graph is being rendered (edit between frames)");
}

void Field::valueChanged() {
  owner_->fieldChanged(*this);
  owner_->notify(kind_, this);
}

}  // namespace tg
