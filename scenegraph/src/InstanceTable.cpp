#include "InstanceTable.h"

#include <algorithm>

namespace tg::sync {

void InstanceTable::count(const InstanceInfo& info, bool add) {
  std::size_t* total = info.cls == DynamicsClass::Static  ? &totals_.statics
                       : info.cls == DynamicsClass::Rigid ? &totals_.rigid
                                                          : &totals_.deforming;
  if (add)
    *total += info.triangles;
  else
    *total -= info.triangles;
}

void InstanceTable::set(InstanceId id, InstanceInfo info) {
  auto it = infos_.find(id);
  if (it != infos_.end()) {
    count(it->second, false);
    it->second = std::move(info);
    count(it->second, true);
  } else {
    count(info, true);
    infos_.emplace(id, std::move(info));
  }
}

void InstanceTable::erase(InstanceId id) {
  auto it = infos_.find(id);
  if (it == infos_.end()) return;
  count(it->second, false);
  infos_.erase(it);
}

const InstanceInfo* InstanceTable::find(InstanceId id) const {
  auto it = infos_.find(id);
  return it == infos_.end() ? nullptr : &it->second;
}

const Segment* InstanceTable::segment(InstanceId id, std::uint32_t primId) const {
  const InstanceInfo* info = find(id);
  if (!info || primId >= info->triangles || info->segments.empty()) return nullptr;
  auto it = std::upper_bound(info->segments.begin(), info->segments.end(), primId,
                             [](std::uint32_t p, const Segment& s) { return p < s.primBegin; });
  if (it == info->segments.begin()) return nullptr;
  return &*(it - 1);
}

}  // namespace tg::sync
