/// @file SyncRecords.h
/// What the sync remembers of the last traversal (internal): regions, frames, occurrences.
///
/// Vocabulary. A *path* is the list of child indices from the root to a node occurrence; a
/// DAG node reached along two paths has two occurrences. A *region* is one occurrence of a
/// Separator (or the root): the unit the sync walks again when something inside changed,
/// because no state change can leak out of a Separator. A *frame* is one occurrence of an
/// instancing boundary (a dynamic transform, a shared Separator, a shared or deforming mesh):
/// its shapes become one backend object in the boundary's local frame, held by one instance
/// whose matrix is the product of the transforms on the way there (the chain). Shapes in no
/// frame are static world geometry, merged into chunks.
#pragma once

#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <vector>

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/scenegraph/CameraNode.h"
#include "tracegraph/scenegraph/DynamicsClass.h"
#include "tracegraph/scenegraph/LightNode.h"
#include "tracegraph/scenegraph/MaterialNode.h"
#include "tracegraph/scenegraph/ShapeNode.h"
#include "tracegraph/scenegraph/TextureNode.h"
#include "tracegraph/scenegraph/TransformNode.h"

namespace tg::sync {

/// Child indices from the root: identifies one occurrence and orders content deterministically.
using Path = std::vector<std::uint32_t>;

/// Transform nodes applied from the root, in order; their product is a world matrix.
using Chain = std::vector<TransformNode*>;

/// Product of a chain's local matrices, folded from the left exactly as traversal folds them.
Affine3d chainMatrix(const Chain& chain);

struct ObjectEntry;
struct Region;

/// One occurrence of a shape inside a frame or the static world.
struct ShapeOcc {
  ShapeNode* shape = nullptr;
  const MaterialNode* material = nullptr;
  const TextureNode* texture = nullptr;
  Affine3d bake;              ///< from the frame (or world) to the shape: baked into vertices
  std::uint64_t version = 0;  ///< shape geometry version when traversed
};

/// One occurrence of an instancing boundary and the shapes it holds.
struct FrameOcc {
  DynamicsClass cls = DynamicsClass::Static;
  ObjectUsage usage = ObjectUsage::Static;
  Chain chain;                       ///< transforms from the root up to the boundary
  std::map<Path, ShapeOcc> shapes;   ///< content, in path order
  Region* owner = nullptr;           ///< region whose traversal created the frame
  ObjectEntry* object = nullptr;     ///< backend object for the content, or null
  InstanceId instance = kInvalidId;  ///< backend instance, or none (empty or singular)
  Affine3d matrix;                   ///< matrix given to the instance
  bool dead = false;                 ///< removed this sync; memory kept until the sync ends
  bool queued = false;               ///< in the list of frames to finalise
  bool matrixQueued = false;         ///< in the list of frames whose matrix to recompute
  /// Entries in the per-transform index of frames (for O(1) removal).
  std::vector<std::pair<const TransformNode*, std::list<FrameOcc*>::iterator>> chainLinks;
};

/// A light or camera occurrence, evaluated on query.
template <typename NodeT>
struct PlacedOcc {
  NodeT* node = nullptr;
  Chain chain;
  Path path;
};

/// Traversal state at a region's start, restored when the region is walked again.
struct EntryState {
  Chain chain;
  Affine3d bake;              ///< static transforms since the current frame began
  FrameOcc* frame = nullptr;  ///< current frame; null: static world
  bool inDynamic = false;     ///< some transform of the chain is dynamic
  const MaterialNode* material = nullptr;
  const TextureNode* texture = nullptr;
  Path path;
};

/// Regions in which a node was visited, per node; list iterators make removal O(1).
using RegionList = std::list<Region*>;

/// One occurrence of a Separator (or the root) and everything its traversal produced.
struct Region {
  Node* node = nullptr;
  Region* parent = nullptr;
  bool isRoot = false;
  EntryState entry;
  /// Every node visited directly here; the references keep chains and maps valid.
  std::vector<ref_ptr<Node>> visited;
  std::vector<std::pair<const Node*, RegionList::iterator>> visitedLinks;
  RegionList::iterator openedLink;  ///< entry in the Separator's list of opened regions
  std::vector<std::pair<FrameOcc*, Path>> frameShapes;  ///< shapes added to frames
  std::vector<Path> staticShapes;                       ///< shapes added to the static world
  std::vector<std::unique_ptr<FrameOcc>> frames;        ///< frames begun here
  std::vector<std::unique_ptr<Region>> children;        ///< nested Separator occurrences
  std::vector<std::unique_ptr<PlacedOcc<LightNode>>> lights;
  std::vector<std::unique_ptr<PlacedOcc<CameraNode>>> cameras;
  std::vector<const Node*> connected;  ///< visited nodes with connected fields
};

}  // namespace tg::sync
