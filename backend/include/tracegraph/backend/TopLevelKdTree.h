/// @file TopLevelKdTree.h
/// The paper's top-level kd-tree over instance bounds, built with its Algorithm 1.
#pragma once

#include <vector>

#include "tracegraph/backend/KdTree.h"
#include "tracegraph/backend/TopLevelAccel.h"

namespace tg {

namespace detail {
/// An instance's world box and index, as the top-level builder moves it between node lists
/// (padded to 32 bytes: the builder copies items as two 16-byte halves).
struct alignas(16) TopLevelBuildItem {
  float lower[3], upper[3];
  std::uint32_t instance, padding;
};

/// Scratch buffers of the top-level build.
struct TopLevelBuildScratch {
  std::vector<TopLevelBuildItem> items;  ///< stack of the nodes' instance lists
  std::vector<float> centres;            ///< box centres of one node along one axis
  std::vector<float> borders;            ///< box borders of one node along one axis
};
}  // namespace detail

/// Top-level kd-tree (Wald, Benthin, Slusallek 2003, Algorithm 1): each cell is split in its
/// dimension of largest extent, only at a border of an instance box, choosing the border
/// nearest the point halfway between the cell centre and the object median. Rebuilt from
/// scratch whenever an instance changed; with hundreds of instances that takes well under a
/// millisecond, which is why the paper can afford it every frame.
class TopLevelKdTree final : public TopLevelAccel {
 public:
  TopLevelKind kind() const override { return TopLevelKind::KdTree; }
  void build(std::span<const InstanceRecord> instances) override;
  bool intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const override;
  bool occluded(const Ray& ray, TraversalContext& ctx) const override;
  const TopLevelStats& stats() const override { return stats_; }

  /// The tree's nodes (root first), for validation and statistics.
  const std::vector<KdNode>& nodes() const { return nodes_; }
  /// Instance indices of the leaves, grouped by leaf.
  const std::vector<std::uint32_t>& references() const { return refs_; }
  /// World bounds of the non-empty instances at the last build.
  const Box3f& bounds() const { return bounds_; }

 private:
  std::span<const InstanceRecord> instances_;
  std::vector<KdNode> nodes_;
  std::vector<std::uint32_t> refs_;  ///< indices into instances_, grouped by leaf
  Box3f bounds_;
  TopLevelStats stats_;
  /// Build scratch, kept between builds so that the per-frame rebuild reuses its memory.
  detail::TopLevelBuildScratch scratch_;
};

}  // namespace tg
