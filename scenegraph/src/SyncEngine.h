/// @file SyncEngine.h
/// The incremental sync of a node graph into a backend scene (internal; SceneGraph's core).
///
/// One sync: (1) turn the dirty nodes into cheap updates (matrices of dynamic transforms,
/// points of deforming meshes) or into regions to walk again (structure, visibility, a node
/// whose class changes); (2) walk those regions, replacing what they produced; (3) build or
/// reuse the objects of changed frames and chunks, update instances; (4) commit. Nothing in
/// this path is proportional to the graph's size unless the root itself must be walked.
#pragma once

#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "Classifier.h"
#include "InstanceTable.h"
#include "ObjectCache.h"
#include "StaticChunks.h"
#include "SyncRecords.h"
#include "tracegraph/scenegraph/FrameStats.h"
#include "tracegraph/scenegraph/SceneGraph.h"
#include "tracegraph/scenegraph/SyncDebugStats.h"

namespace tg::sync {

class RegionBuilder;

/// Keeps a backend scene equal to a graph, frame by frame.
class SyncEngine {
 public:
  SyncEngine(Scene& scene, const SyncOptions& options);
  ~SyncEngine();

  /// Forgets everything; the next sync walks `root` from scratch.
  void setRoot(Node* root);
  /// Records a notification (called from the root's observer).
  void noteChange(const Notification& n);
  /// Runs one sync (frame numbers start at 1).
  FrameStats sync(double time);

  const SyncDebugStats& debug() const { return debug_; }
  std::uint64_t frame() const { return frame_; }
  const InstanceTable& instances() const { return instances_; }
  const Classifier& classifier() const { return classifier_; }
  std::vector<WorldLight> lights() const;
  std::optional<WorldCamera> camera() const;

  /// Nodes with connected fields seen by the last traversals (seeds of the animator schedule).
  const std::unordered_map<const Node*, int>& connectedNodes() const { return connected_; }
  /// Nodes added to the graph (or the new root) since the last sync, not yet walked.
  std::vector<const Node*> pendingSubtrees() const;

 private:
  friend class RegionBuilder;

  // Traversal (RegionTraversal.cpp).
  void walk(Region& region);
  void clear(Region& region);
  FrameOcc* beginFrame(Region& region, const EntryState& state, DynamicsClass cls,
                       ObjectUsage usage);
  void addShape(Region& region, const EntryState& state, const ShapeOcc& shape);
  void addToFrame(Region& region, FrameOcc* frame, const Path& path, const ShapeOcc& shape);
  void killFrame(FrameOcc& frame);
  void queueFrame(FrameOcc* frame);
  void queueMatrix(FrameOcc* frame);
  bool shapeValid(const ShapeNode& shape);

  // Dirty handling and backend updates (SyncEngine.cpp).
  void collectRegions(const Node* node, bool opened, std::vector<Region*>& out) const;
  void finishFrame(FrameOcc& frame);
  void finishMatrix(FrameOcc& frame);
  void finishChunk(Chunk& chunk);
  void setInstance(InstanceId& instance, ObjectEntry* entry, const Affine3d& matrix,
                   bool objectChanged, InstanceInfo info);
  void dropInstance(InstanceId& instance);
  void teardown();

  Scene& scene_;
  SyncOptions options_;
  Classifier classifier_;
  ObjectCache cache_;
  StaticChunks chunks_;
  InstanceTable instances_;
  SyncDebugStats debug_;
  std::uint64_t frame_ = 0;

  ref_ptr<Node> root_;
  bool rootDirty_ = false;
  std::unique_ptr<Region> rootRegion_;

  struct Dirty {
    ref_ptr<Node> node;
    ChangeKind kinds = ChangeKind::None;
  };
  std::unordered_map<const Node*, Dirty> dirty_;
  std::vector<ref_ptr<Node>> structureChildren_;

  std::unordered_map<const Node*, RegionList> visitedIn_;
  std::unordered_map<const Node*, RegionList> opened_;
  std::unordered_map<const TransformNode*, std::list<FrameOcc*>> framesOf_;
  std::unordered_map<const Node*, int> connected_;
  std::map<Path, const PlacedOcc<LightNode>*> lights_;
  std::map<Path, const PlacedOcc<CameraNode>*> cameras_;
  struct Validity {
    std::uint64_t version = 0;
    bool valid = false;
  };
  std::unordered_map<const ShapeNode*, Validity> validity_;

  std::vector<FrameOcc*> queuedFrames_;
  std::vector<FrameOcc*> queuedMatrices_;
  // Removed records stay alive until the sync ends: queued lists may still point at them and
  // their node references keep addresses from being reused while maps are keyed by them.
  std::vector<std::unique_ptr<FrameOcc>> deadFrames_;
  std::vector<std::unique_ptr<Region>> deadRegions_;
  std::vector<ref_ptr<Node>> leftNodes_;
};

}  // namespace tg::sync
