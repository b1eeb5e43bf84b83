#include "StaticChunks.h"

#include <algorithm>
#include <cmath>

#include "MeshBaker.h"

namespace tg::sync {

StaticChunks::Cell StaticChunks::cellOf(const ShapeOcc& shape) const {
  const Box3d b = bakedBounds(*shape.shape, shape.bake);
  const Vec3d c = b.empty() ? Vec3d{} : b.center();
  Cell cell{};
  for (int a = 0; a < 3; ++a) {
    // Clamp so that absurd coordinates cannot overflow the integer cell index.
    const double i = std::floor(c[static_cast<std::size_t>(a)] / cellSize_);
    cell[static_cast<std::size_t>(a)] =
        static_cast<std::int64_t>(std::isfinite(i) ? std::clamp(i, -1e15, 1e15) : 0.0);
  }
  return cell;
}

void StaticChunks::place(const Path& path, const ShapeOcc& shape) {
  const Cell cell = cellOf(shape);
  cells_[path] = cell;
  Chunk& chunk = chunks_[cell];
  chunk.shapes[path] = shape;
  chunk.dirty = true;
}

void StaticChunks::add(const Path& path, const ShapeOcc& shape) {
  if (cellSize_ > 0.0)
    place(path, shape);
  else
    pending_[path] = shape;
}

void StaticChunks::remove(const Path& path) {
  auto it = cells_.find(path);
  if (it == cells_.end()) {
    pending_.erase(path);
    return;
  }
  Chunk& chunk = chunks_[it->second];
  chunk.shapes.erase(path);
  chunk.dirty = true;
  cells_.erase(it);
}

std::vector<Chunk*> StaticChunks::takeDirty() {
  if (!pending_.empty()) {
    if (cellSize_ <= 0.0) {
      Box3d all;
      for (const auto& [path, shape] : pending_) all.extend(bakedBounds(*shape.shape, shape.bake));
      const double extent = all.empty() ? 0.0 : maxComponent(all.extent());
      cellSize_ = extent > 0.0 && std::isfinite(extent) ? extent / grid_ : 1.0;
    }
    for (const auto& [path, shape] : pending_) place(path, shape);
    pending_.clear();
  }
  std::vector<Chunk*> dirty;
  for (auto& [cell, chunk] : chunks_) {
    if (!chunk.dirty) continue;
    chunk.dirty = false;
    dirty.push_back(&chunk);
  }
  return dirty;
}

void StaticChunks::dropEmpty() {
  std::erase_if(chunks_, [](const auto& kv) {
    return kv.second.shapes.empty() && kv.second.object == nullptr &&
           kv.second.instance == kInvalidId;
  });
}

}  // namespace tg::sync
