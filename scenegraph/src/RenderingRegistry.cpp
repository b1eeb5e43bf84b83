#include "RenderingRegistry.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <unordered_set>
#include <vector>

#include "tracegraph/scenegraph/Group.h"

namespace tg::detail {
namespace {

std::atomic<int> gRenderingCount{0};
std::mutex gMutex;
std::vector<const Node*> gRoots;  // one entry per beginRendering

}  // namespace

void beginRendering(const Node* root) {
  std::lock_guard lock(gMutex);
  gRoots.push_back(root);
  gRenderingCount.fetch_add(1, std::memory_order_release);
}

void endRendering(const Node* root) {
  std::lock_guard lock(gMutex);
  auto it = std::find(gRoots.begin(), gRoots.end(), root);
  if (it == gRoots.end()) return;
  gRoots.erase(it);
  gRenderingCount.fetch_sub(1, std::memory_order_release);
}

bool isUnderRenderingRoot(const Node& node) {
  if (gRenderingCount.load(std::memory_order_acquire) == 0) return false;
  std::lock_guard lock(gMutex);
  // Walk the ancestors once each (a shared node may be reached along several parents).
  std::vector<const Node*> stack{&node};
  std::unordered_set<const Node*> seen;
  while (!stack.empty()) {
    const Node* n = stack.back();
    stack.pop_back();
    if (!seen.insert(n).second) continue;
    if (std::find(gRoots.begin(), gRoots.end(), n) != gRoots.end()) return true;
    for (const Group* p : n->parents()) stack.push_back(p);
  }
  return false;
}

}  // namespace tg::detail
