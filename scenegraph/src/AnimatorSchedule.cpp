#include "AnimatorSchedule.h"

#include <unordered_map>

#include "tracegraph/scenegraph/Field.h"

namespace tg::sync {
namespace {

/// Animators whose outputs `node` reads: sources of its connected fields and, for an
/// animator, of the fields of the nodes it depends on.
void upstream(const Node& node, std::vector<Animator*>& out) {
  auto add = [&out](const Node& n) {
    for (const Field* f : n.fields())
      if (const Field* src = f->connectedFrom())
        if (auto* a = dynamic_cast<Animator*>(&src->owner())) out.push_back(a);
  };
  add(node);
  if (const auto* a = dynamic_cast<const Animator*>(&node)) {
    std::vector<Node*> deps;
    a->dependencies(deps);
    for (const Node* d : deps) add(*d);
  }
}

}  // namespace

void AnimatorSchedule::rebuild(const std::vector<const Node*>& seeds) {
  order_.clear();
  // Depth-first post-order from the seeds: an animator is appended after everything it reads.
  enum class Mark { InProgress, Done };
  std::unordered_map<const Node*, Mark> marks;
  struct Item {
    const Node* node;
    bool expanded;
  };
  std::vector<Item> stack;
  std::vector<Animator*> ups;
  for (const Node* seed : seeds) {
    stack.push_back({seed, false});
    while (!stack.empty()) {
      Item item = stack.back();
      stack.pop_back();
      if (item.expanded) {
        marks[item.node] = Mark::Done;
        if (auto* a = dynamic_cast<const Animator*>(item.node))
          order_.emplace_back(const_cast<Animator*>(a));
        continue;
      }
      if (marks.count(item.node)) continue;  // done, or a cycle through dependencies()
      marks[item.node] = Mark::InProgress;
      stack.push_back({item.node, true});
      ups.clear();
      upstream(*item.node, ups);
      for (Animator* a : ups)
        if (!marks.count(a)) stack.push_back({a, false});
    }
  }
}

void AnimatorSchedule::evaluate(double time) const {
  for (const ref_ptr<Animator>& a : order_) {
    a->evaluate(time);
    for (const Field* out : a->fields())
      for (Field* target : out->connections()) target->copyValueFrom(*out);
  }
}

}  // namespace tg::sync
