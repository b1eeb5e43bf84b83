/// @file Classifier.h
/// Decides which transforms are dynamic and which meshes deform, from connections and from
/// observed changes, with hysteresis on the way back to static (internal).
#pragma once

#include <cstdint>
#include <queue>
#include <unordered_map>
#include <vector>

#include "tracegraph/scenegraph/Node.h"
#include "tracegraph/scenegraph/SyncOptions.h"

namespace tg::sync {

/// Dynamics state per transform or shape node.
///
/// A node is dynamic when it is driven (a Transform/Points/Topology field connected to an
/// animator) or was observed to change less than its rest threshold ago. The threshold is
/// restFrames doubled once per earlier demotion (at most maxRestDoublings times): a part that
/// moves every few frames stays dynamic instead of being rebuilt into static geometry and out
/// again. Checks of resting nodes are scheduled by frame number, so a sync looks only at
/// nodes due this frame, never at all dynamic nodes.
class Classifier {
 public:
  explicit Classifier(const SyncOptions& options) : options_(options) {}

  /// True when `node` is currently dynamic (driven or observed moving).
  bool isDynamic(const Node& node) const;
  /// Records a change of `node` in `frame`; true when this promotes it from static.
  bool noteChange(Node& node, std::uint64_t frame);
  /// Nodes whose rest period ends by `frame`; they are static from now on.
  std::vector<ref_ptr<Node>> takeDemotions(std::uint64_t frame);
  /// Drops the state of a node that left the graph.
  void forget(const Node* node);
  /// Frames of rest `node` needs before its next demotion.
  std::uint64_t restThreshold(const Node& node) const;
  /// Number of nodes with state.
  std::size_t size() const { return states_.size(); }

 private:
  struct State {
    ref_ptr<Node> node;
    bool moving = false;     ///< observed to change and not yet at rest
    bool scheduled = false;  ///< has an entry in the rest queue
    std::uint64_t lastChange = 0;
    std::uint32_t demotions = 0;
  };
  std::uint64_t threshold(const State& s) const;
  static bool driven(const Node& node);

  SyncOptions options_;
  std::unordered_map<const Node*, State> states_;
  using Due = std::pair<std::uint64_t, const Node*>;
  std::priority_queue<Due, std::vector<Due>, std::greater<Due>> queue_;
};

}  // namespace tg::sync
