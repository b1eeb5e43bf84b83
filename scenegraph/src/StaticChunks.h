/// @file StaticChunks.h
/// The static world geometry, split into world-space chunks by grid cell (internal).
///
/// Merging all static geometry into one object gives the best accelerator, but then any
/// static part that starts moving rebuilds all of it. Chunks bound that cost: a shape belongs
/// to the cell holding the centre of its world bounds, and only the chunks whose shapes
/// changed are rebuilt.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include "SyncRecords.h"

namespace tg::sync {

/// One cell's static shapes and the backend object and instance holding them.
struct Chunk {
  std::map<Path, ShapeOcc> shapes;
  ObjectEntry* object = nullptr;
  InstanceId instance = kInvalidId;
  bool dirty = false;
};

/// Static shapes by cell.
class StaticChunks {
 public:
  explicit StaticChunks(std::uint32_t grid) : grid_(grid == 0 ? 1 : grid) {}
  /// Adds a static shape occurrence (world-space bake).
  void add(const Path& path, const ShapeOcc& shape);
  /// Removes a static shape occurrence.
  void remove(const Path& path);
  /// Places shapes added before the grid existed (the grid is fixed from their bounds the
  /// first time), then returns the chunks whose content changed, clearing their marks.
  std::vector<Chunk*> takeDirty();
  /// Forgets chunks that hold nothing and no backend object.
  void dropEmpty();
  /// Number of chunks.
  std::size_t size() const { return chunks_.size(); }
  /// All chunks (for teardown).
  std::map<std::array<std::int64_t, 3>, Chunk>& chunks() { return chunks_; }

 private:
  using Cell = std::array<std::int64_t, 3>;
  Cell cellOf(const ShapeOcc& shape) const;
  void place(const Path& path, const ShapeOcc& shape);

  std::uint32_t grid_;
  double cellSize_ = 0.0;
  std::map<Path, Cell> cells_;
  std::map<Cell, Chunk> chunks_;
  std::map<Path, ShapeOcc> pending_;
};

}  // namespace tg::sync
