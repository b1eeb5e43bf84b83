// The object-level 4-wide BVH behind the ObjectAccel interface (AccelKind::Bvh and
// AccelKind::BvhFast). Internal header: callers create it through createObjectAccel.
#pragma once

#include <vector>

#include "Bvh8Twin.h"
#include "BvhBuilder.h"
#include "BvhMortonBuilder.h"
#include "PacketKernel.h"
#include "tracegraph/backend/KdTree.h"
#include "tracegraph/backend/ObjectAccel.h"
#include "tracegraph/backend/TopLevelAccel.h"

namespace tg::detail {

/// A packet as BvhAccel's packet walk reads it (BvhAccel::loadPacket): the box-test rays of the
/// lanes that share the first lane's direction signs, and the SIMD triangle test's rays of
/// those that also share its axis permutation. A caller that sends the same rays into several
/// objects (identity instances) loads them once.
struct BvhPacketRays {
  /// Box-test rays; the walk lowers tfar of the lanes that find closer hits.
  PacketBoxRays box;
  /// Triangle-test rays of the lanes in `filtered`.
  PacketTriangleRays triangles;
  /// Lanes in `box`: the others need another walk.
  unsigned coherent = 0;
  /// Lanes of `coherent` in `triangles`: the others are tested lane by lane.
  unsigned filtered = 0;
  /// Lanes whose ObjectRay in the packet holds only tfar and the ids (an identity instance's
  /// packet, see mapIdentityPacket, or a transformed one's, see loadTransformedPacket): the
  /// walk completes one, from worldRays, before a test that reads it.
  unsigned unmappedLanes = 0;
  /// The world rays of unmappedLanes.
  const Ray* worldRays = nullptr;
  /// The instance whose mapping (objectRayFor) makes the object rays of worldRays.
  const InstanceRecord* instance = nullptr;
  /// The kernels that walk these rays (those of the instruction set active when loaded): looked
  /// up once per load rather than at every walk entered with them.
  const PacketKernels* kernels = nullptr;
};

/// A part of a BvhAccel's tree that a top-level walk may enter directly, in place of the whole
/// object (partial re-braiding, Benthin et al. 2017): inner node `child` when `count` is 0, else
/// the leaf of `count` triangles at `child`.
struct BvhSubtree {
  Box3f bounds;             ///< the subtree's box (object space)
  std::uint32_t child = 0;  ///< node index (inner) or first triangle (leaf)
  std::uint32_t count = 0;  ///< triangles of a leaf; 0 for an inner node
};

/// A BVH4 over one mesh. Leaves hold up to a few triangles, copied contiguously in leaf order
/// for the same watertight test the kd-trees use, so hits are identical whichever accelerator
/// found them. SAH trees keep each leaf's vertices component by component (leaf rows,
/// LeafRows.h): a single ray tests a leaf's up to four triangles in one SSE step, with the
/// scalar test's bits; Morton trees, rewritten by every refit, keep them packed. SAH trees built
/// on a CPU with AVX2 also keep an eight-wide copy of their nodes (buildBvh8), which single rays
/// walking the whole tree take (intersectWhole, occludedWhole); packets and walks entered at a
/// subtree take the BVH4.
///
/// AccelKind::Bvh: 32-bin SAH over all axes, degenerate triangles left out; no refit.
/// AccelKind::BvhFast: Morton-code build (BvhMortonBuilder), degenerate triangles kept in the
/// tree (the watertight test never hits them) so that a later refit finds every triangle when a
/// degenerate one opens up again (hard case 19); refit() supported.
class BvhAccel final : public ObjectAccel {
 public:
  /// An unbuilt BVH; `kind` is AccelKind::Bvh or AccelKind::BvhFast.
  explicit BvhAccel(AccelKind kind) : kind_(kind) {}

  AccelKind kind() const override { return kind_; }
  void build(const TriangleMesh& mesh) override;
  bool refit(const TriangleMesh& mesh) override;
  Box3f bounds() const override { return bounds_; }
  bool intersect(ObjectRay& ray, Hit& hit, TraversalContext& ctx) const override;
  bool occluded(const ObjectRay& ray, TraversalContext& ctx) const override;
  bool occludedByPrimitive(const ObjectRay& ray, std::uint32_t primitive) const override;
  unsigned intersectPacket(ObjectRayPacket& packet, unsigned lanes, Hit* hits,
                           TraversalContext& ctx) const override;
  unsigned occludedPacket(const ObjectRayPacket& packet, unsigned lanes,
                          TraversalContext& ctx) const override;
  const BuildStats& stats() const override { return stats_; }

  /// Loads the lanes of `packet` in `lanes` into `out` (see BvhPacketRays).
  static void loadPacket(const ObjectRayPacket& packet, unsigned lanes, BvhPacketRays& out);
  /// loadPacket for the packet of an identity instance (lanes `lanes`, walked with `kernels`),
  /// whose box rays are `world`: the world rays of `lanes`, loaded for the top-level walk (same
  /// direction signs, unused lanes filled from the first), and whose triangle rows
  /// mapIdentityPacket wrote into out.triangles, returning `filtered`. The box part is a copy of
  /// `world` (lane tfar as `world` holds it), equal to what loadPacket computes lane by lane.
  /// out.unmappedLanes, out.worldRays and out.instance are left as they are (the walk owns
  /// them).
  static void loadIdentityPacket(const PacketBoxRays& world, unsigned lanes, unsigned filtered,
                                 const PacketKernels& kernels, BvhPacketRays& out);
  /// Lane `l` of `packet` with its whole object ray: made first, when the lane is in
  /// rays.unmappedLanes (which it then leaves), as objectRayFor(*rays.instance) maps
  /// rays.worldRays[l], keeping the tfar and ids the lane holds.
  static ObjectRay& packetLane(ObjectRayPacket& packet, BvhPacketRays& rays, unsigned l);
  /// intersectPacket for lanes already loaded: `lanes` lie in rays.coherent, and rays.box.tfar
  /// of each equals its packet ray's tfar. Returns the lanes whose hit changed.
  /// `root` limits the walk to one subtree (BvhSubtree); the default is the whole tree.
  unsigned intersectLoadedPacket(ObjectRayPacket& packet, BvhPacketRays& rays, unsigned lanes,
                                 Hit* hits, TraversalContext& ctx,
                                 const BvhSubtree& root = {}) const;
  /// One half of intersectLoadedPair: a packet, its loaded rows, its lanes and its hits.
  struct LoadedHalf {
    ObjectRayPacket* packet = nullptr;
    BvhPacketRays* rays = nullptr;
    unsigned lanes = 0;
    Hit* hits = nullptr;
  };
  /// intersectLoadedPacket for two halves at once, walked as one pair (PairTraverseFn) when the
  /// kernels of half 0 have a pair walk, both halves have lanes and share their direction signs;
  /// else half by half. Writes into changed[h] the lanes of half h whose hit changed.
  void intersectLoadedPair(const LoadedHalf (&halves)[2], TraversalContext& ctx,
                           const BvhSubtree& root, unsigned (&changed)[2]) const;
  /// occludedLoadedPacket for two halves at once (their `hits` unused), walked as one pair
  /// (PairOccludedFn) under the conditions of intersectLoadedPair; else half by half. Writes
  /// into blocked[h] the lanes of half h found occluded.
  void occludedLoadedPair(const LoadedHalf (&halves)[2], TraversalContext& ctx,
                          const BvhSubtree& root, unsigned (&blocked)[2]) const;
  /// occludedPacket for lanes already loaded (see intersectLoadedPacket).
  unsigned occludedLoadedPacket(ObjectRayPacket& packet, BvhPacketRays& rays, unsigned lanes,
                                TraversalContext& ctx, const BvhSubtree& root = {}) const;

  /// The children of subtree `t` into `out`, with their boxes; returns how many (0 for a leaf,
  /// and for a tree without nodes). BvhSubtree{} is the whole tree, whose root is node 0.
  int subtreeChildren(const BvhSubtree& t, BvhSubtree out[4]) const;

  /// Closest-hit test of one ray against the triangles [first, first + count) of a leaf; the
  /// leaf test of both the single-ray and the packet walk, so that both find the same hits.
  bool intersectLeaf(ObjectRay& ray, Hit& hit, std::uint32_t first, std::uint32_t count,
                     TraversalContext& ctx) const;
  /// Any-hit test of one ray against a leaf's triangles.
  bool occludedLeaf(const ObjectRay& ray, std::uint32_t first, std::uint32_t count,
                    TraversalContext& ctx) const;
  /// Closest hit of one ray in the subtree (child, count) (the single-ray walk; see
  /// BvhSubtree for the pair).
  bool intersectSubtree(ObjectRay& ray, Hit& hit, std::uint32_t child, std::uint32_t count,
                        TraversalContext& ctx) const;
  /// Any hit of one ray in the subtree (child, count).
  bool occludedSubtree(const ObjectRay& ray, std::uint32_t child, std::uint32_t count,
                       TraversalContext& ctx) const;
  /// intersectSubtree with the box-test constants of `ray` already made (`boxRay`, equal to
  /// what the ray's own would be: for an identity instance, the world ray's).
  bool intersectSubtree(ObjectRay& ray, const Bvh4Ray& boxRay, Hit& hit, std::uint32_t child,
                        std::uint32_t count, TraversalContext& ctx) const;
  /// Closest hit of one ray in the whole tree (intersectSubtree at the root, through the
  /// eight-wide tree where there is one), with the box-test constants of `ray` already made.
  bool intersectWhole(ObjectRay& ray, const Bvh4Ray& boxRay, Hit& hit, TraversalContext& ctx) const;
  /// Any hit of one ray in the whole tree (see intersectWhole).
  bool occludedWhole(const ObjectRay& ray, const Bvh4Ray& boxRay, TraversalContext& ctx) const;
  /// The node of the eight-wide tree that stands for inner BVH4 node `node` (Bvh8Entry: the
  /// nodes of the first kBvh8EntryDepth levels), or kInvalidId.
  std::uint32_t wideEntryOf(std::uint32_t node) const;
  /// intersectSubtree through the eight-wide tree, from its node `wideNode` (wideEntryOf), with
  /// the same answers. Call it only on a CPU with AVX2 (the tree is made only there).
  bool intersectWideSubtree(ObjectRay& ray, const Bvh4Ray& boxRay, Hit& hit,
                            std::uint32_t wideNode, TraversalContext& ctx) const;
  /// occludedSubtree through the eight-wide tree (see intersectWideSubtree).
  bool occludedWideSubtree(const ObjectRay& ray, const Bvh4Ray& boxRay, std::uint32_t wideNode,
                           TraversalContext& ctx) const;
  /// occludedSubtree with the box-test constants of `ray` already made.
  bool occludedSubtree(const ObjectRay& ray, const Bvh4Ray& boxRay, std::uint32_t child,
                       std::uint32_t count, TraversalContext& ctx) const;
  /// Closest-hit test of one ray against triangle `k` (leaf order), with the same answers as
  /// intersectLeaf's step (which reads the ray's axis permutation as constants): the packet
  /// leaves' test for lanes the SIMD test does not decide.
  bool intersectTriangle(ObjectRay& ray, Hit& hit, std::uint32_t k) const;
  /// Any-hit test of one ray against triangle `k` (leaf order).
  bool occludedTriangle(const ObjectRay& ray, std::uint32_t k) const;
  /// Mesh triangle index of triangle `k` (leaf order).
  std::uint32_t primId(std::uint32_t k) const { return primIds_[k]; }
  /// The vertices of the leaf of `count` triangles at `first` (leaf order), from triangle
  /// `from` on.
  TriangleFloats leafTriangles(std::uint32_t first, std::uint32_t count, std::uint32_t from) const;
  /// The vertices of triangle `k` (leaf order).
  TriangleVertices vertices(std::uint32_t k) const;

 private:
  /// SAH weights used for the cost figure (and by the builders): a four-box node test costs
  /// one and a half triangle tests. Against 1.0, the flattened kitchen's two-thread build took
  /// 0.944-0.971 of Embree MEDIUM's time instead of 0.954-1.011 (fewer, fuller leaves) and traced
  /// at 0.983-1.012 of its speed instead of 0.960-1.013; primary rays from the BART files'
  /// cameras and from outside within noise. 2.0 traced the kitchen from its camera 5-7% slower.
  static constexpr double kTraversalCost = 1.5;
  static constexpr double kIntersectionCost = 1.0;

  /// AccelKind::Bvh: binned SAH without the degenerate triangles.
  void buildSah(const TriangleMesh& mesh);
  /// AccelKind::BvhFast: Morton build over every triangle.
  void buildMorton(const TriangleMesh& mesh);
  /// Copies the triangles of `mesh` into leaf order and recomputes every box, the bounds, the
  /// degenerate count and the SAH cost over the topology of the last Morton build (a refit).
  void refitFromMesh(const TriangleMesh& mesh);
  void finishStats();
  /// Writes leafRows_ and leafLanes_ for every leaf of nodes_ from `mesh` and primIds_.
  void writeLeafRowsOfTree(const TriangleMesh& mesh);

  /// True when the vertices are leaf rows (SAH trees), false when packed (Morton trees).
  bool hasLeafRows() const { return kind_ != AccelKind::BvhFast; }

  AccelKind kind_;
  Bvh4NodeArray nodes_;
  /// An eight-wide BVH collapsed from nodes_, for single rays that walk the whole tree on CPUs
  /// with AVX2 (SAH trees; see build()). Empty when not made.
  Bvh8NodeArray wide_;
  /// Where subtree entries enter wide_ (buildBvh8's entries), sorted by BVH4 node.
  std::vector<Bvh8Entry> wideEntries_;
  /// Morton trees: the vertices in leaf order, packed; every build writes all of them (see
  /// NoInit). A refit rewrites them in place.
  std::vector<TriangleVertices, UninitializedAllocator<TriangleVertices>> triangles_;
  /// SAH trees: the vertices as leaf rows (LeafRows.h), which single rays test four triangles
  /// at a time: triangle k of a leaf starting at `first` lies in the 9 * count floats from
  /// 9 * first, followed by kLeafRowPadding floats at the end.
  std::vector<float, UninitializedAllocator<float>> leafRows_;
  /// SAH trees: per triangle, its place in its leaf (low four bits) and the leaf's size (high
  /// four), which find its rows from its index alone (vertices()).
  std::vector<std::uint8_t> leafLanes_;
  std::vector<std::uint32_t> primIds_;  ///< mesh triangle index of each triangle (leaf order)
  std::vector<std::uint32_t> indices_;  ///< mesh indices at the last build (refit check)
  BvhPrimArray prims_;                  ///< SAH build scratch
  std::vector<Vec3f> centroids_;        ///< Morton build scratch: lower + upper per box
  std::vector<std::uint32_t> rank_;     ///< leaf position of each mesh triangle (for refits)
  BvhMortonBuilder morton_;             ///< Morton build scratch, kept between builds
  Box3f bounds_;
  BuildStats stats_;
};

}  // namespace tg::detail
