// The packet walk over a BVH4, written once and compiled per instruction set: each kernel
// translation unit includes this file after defining its node test. Everything here has
// internal linkage (see PacketKernel.h for why). Internal header: not installed.
//
// NodeTest(rays) is made once per walk and may keep what of the rays stays fixed during it (all
// but tfar); its test<Rows>(node, rays, lanes, hit, entry), with Rows the walk's WalkConstants,
// tests the four child boxes of `node` against the lanes in `lanes` and writes, per slot, the
// lanes that hit it (hit[s]) and each lane's widened entry distance (entry[s][lane]), with
// exactly the arithmetic of intersectBvh4Node. Its constant kReadsTnearSign says whether the test
// reads Rows::nonNegativeTnear; a test that does not is compiled once per octant only.
// NodeTest also provides the lane operations of ScalarLaneOps (by deriving from it or from a
// wider version with the same answers).
#pragma once

#include "PacketKernel.h"
#include "PacketTriangleTest.h"

namespace tg::detail {
namespace {

/// Index of the lowest set bit of a non-zero mask.
inline unsigned lowestLane(unsigned mask) {
  return static_cast<unsigned>(__builtin_ctz(mask));
}

/// The walk's operations across the lanes of one stack entry, written lane by lane.
struct ScalarLaneOps {
  /// The lanes l of `mask` whose entry[l] lies beyond tfar[l] (false for NaN, as `>` is).
  static unsigned beyond(const float* entry, const float* tfar, unsigned mask) {
    unsigned out = 0;
    for (unsigned m = mask; m != 0; m &= m - 1) {
      const unsigned l = lowestLane(m);
      if (entry[l] > tfar[l]) out |= 1u << l;
    }
    return out;
  }
};

/// What stays fixed during one packet walk, as constants of its code. The Bvh4Node::bounds rows
/// the lanes enter and leave the boxes by, fixed by the octant of their directions: bit a of
/// Signs set when component a is negative (as PacketBoxRays::signs); as constants, the node
/// test addresses its planes directly instead of computing six addresses from row numbers at
/// every node. And whether every lane's tnear is >= 0, when the wider kernels widen each box
/// interval's ends by one product (see Bvh4.h): decided once per walk instead of at each slot.
template <unsigned Signs, bool NonNegativeTnear>
struct WalkConstants {
  static constexpr int nearRow(int a) { return 2 * a + static_cast<int>((Signs >> a) & 1u); }
  static constexpr int farRow(int a) { return 2 * a + 1 - static_cast<int>((Signs >> a) & 1u); }
  static constexpr bool nonNegativeTnear = NonNegativeTnear;
};

/// What the walk over the lanes of one packet takes from them (see walkLanes): its rays, its
/// callbacks (the same for both queries) and how a stack entry keeps the lanes' entries.
template <class NodeTest>
struct OnePacketLanes {
  using Rays = PacketBoxRays&;
  static constexpr unsigned kLanes = kPacketLanes;
  /// A stack entry's entries need no more than a float's alignment: the walk copies them lane
  /// by lane.
  static constexpr std::size_t kEntryAlign = alignof(float);
  template <bool kAnyHit>
  using Leaf = PacketLeafFn;
  template <bool kAnyHit>
  using Single = PacketSingleFn;
  static unsigned beyond(const float* entry, PacketBoxRays& rays, unsigned mask) {
    return NodeTest::beyond(entry, rays.tfar, mask);
  }
  static void copyEntry(const float* from, float* to) {
    for (unsigned l = 0; l < kPacketLanes; ++l) to[l] = from[l];
  }
};

/// The walk, written once for one packet (OnePacketLanes) and for two walked as one
/// (PairLanes in PacketPairWalkImpl.h), and for both queries: everything of the any-hit query
/// (kAnyHit) is under `if constexpr`, so the closest-hit walk, the primary rays' hot loop,
/// compiles to its own code and carries nothing of the other.
///
/// Closest hits: front to back in the order of each subtree's lowest lane (the children hit are
/// visited by that lane's entry distance), with each lane leaving a subtree whose entry lies
/// beyond its own closest hit, as the single-ray walk does. The order decides only how soon the
/// closest hits are found, never which they are (the leaves apply the tie rule). Any hit:
/// children highest slot first (the order of any-hit walks, Bvh4.h), and lanes the leaves
/// occlude leave the walk; returns them (0 for closest hits). Both: a subtree entered by
/// one lane is handed to it alone (`single`). Rows is the WalkConstants of the rays (traversePacket
/// and traversePair choose them).
template <bool kAnyHit, class Lanes, class NodeTest, class Rows>
unsigned walkLanes(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                   typename Lanes::Rays rays, unsigned lanes,
                   typename Lanes::template Leaf<kAnyHit> leaf,
                   typename Lanes::template Single<kAnyHit> single, void* user,
                   std::uint64_t& nodeVisits) {
  struct Entry {
    std::uint32_t child, count;
    unsigned lanes;
    alignas(Lanes::kEntryAlign) float entry[Lanes::kLanes];
  };
  Entry stack[3 * kBvh4MaxDepth + 4];
  int stackSize = 0;
  // Counted in a register: the callbacks are opaque, so a count kept in nodeVisits itself was
  // stored and loaded again around every one of them.
  LocalVisitCount visits(nodeVisits);
  // Per-walk state of the node test: what of the rays stays fixed during the walk (all but tfar).
  const NodeTest nodeTest(rays);
  [[maybe_unused]] unsigned active = lanes, occluded = 0;
  std::uint32_t child = rootChild, count = rootCount;
  unsigned current = lanes;
  for (;;) {
    [[maybe_unused]] unsigned found = 0;
    if (count == 0 && (current & (current - 1)) == 0) {
      // One lane left in this subtree: it walks on alone.
      if constexpr (kAnyHit) {
        if (single(user, child, lowestLane(current), rays) != 0) found = current;
      } else {
        single(user, child, lowestLane(current), rays);
      }
    } else if (count == 0) {
      ++visits.visits;
      const Bvh4Node& node = nodes[child];
      unsigned hit[4];
      alignas(64) float entry[4][Lanes::kLanes];
      nodeTest.template test<Rows>(node, rays, current, hit, entry);
      int slots[4];
      float key[4];
      int n = 0;
      for (int i = 0; i < 4; ++i) {
        // Any hits take the children highest slot first (the order of any-hit walks, Bvh4.h),
        // with no key.
        const int s = kAnyHit ? 3 - i : i;
        if (hit[s] == 0) continue;
        int j = n++;
        if constexpr (!kAnyHit) {
          // Closest hits by one lane's entry, not the smallest over the lanes: the lanes of a
          // coherent packet enter a box close together, and the horizontal minimum per child
          // hit (a chain of three shuffles and minima) cost more than the order it bought.
          // Interleaved runs from the BART cameras: robots 3.5% and kitchen 1.3% less time;
          // from outside, robots 1.6% and the kitchen unchanged.
          const float k = entry[s][lowestLane(hit[s])];
          for (; j > 0 && key[j - 1] > k; --j) {
            key[j] = key[j - 1];
            slots[j] = slots[j - 1];
          }
          key[j] = k;
        }
        slots[j] = s;
      }
      if (n > 0) {
        // Ask for the inner children's nodes now: the walk reaches them after a leaf or two, and
        // the loads of a node's boxes (and the arithmetic waiting on them) were the hottest
        // instructions of the node test in perf profiles.
        for (int j = 0; j < n; ++j) {
          const int s = slots[j];
          if (node.count[s] == 0) {
            const char* line = reinterpret_cast<const char*>(nodes + node.child[s]);
            __builtin_prefetch(line);
            __builtin_prefetch(line + 64);
          }
        }
        for (int j = n - 1; j > 0; --j) {
          const int s = slots[j];
          Entry& e = stack[stackSize++];
          e.child = node.child[s];
          e.count = node.count[s];
          e.lanes = hit[s];
          Lanes::copyEntry(entry[s], e.entry);
        }
        child = node.child[slots[0]];
        count = node.count[slots[0]];
        current = hit[slots[0]];
        continue;
      }
    } else {
      if constexpr (kAnyHit)
        found = leaf(user, child, count, current, rays);
      else
        leaf(user, child, count, current, rays);
    }
    if constexpr (kAnyHit) {
      if (found != 0) {
        occluded |= found;
        active &= ~found;
        if (active == 0) return occluded;
      }
    }
    // Pop the next subtree some lane still needs.
    for (;;) {
      if (stackSize == 0) return occluded;
      const Entry& e = stack[--stackSize];
      const unsigned want = kAnyHit ? e.lanes & active : e.lanes;
      const unsigned need = want & ~Lanes::beyond(e.entry, rays, want);
      if (need != 0) {
        child = e.child;
        count = e.count;
        current = need;
        break;
      }
    }
  }
}

/// The walk of one packet for the query `anyHit` (PacketTraverseFn for one WalkConstants).
template <class NodeTest, class Rows>
unsigned walkPacket(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                    PacketBoxRays& rays, unsigned lanes, bool anyHit, PacketLeafFn leaf,
                    PacketSingleFn single, void* user, std::uint64_t& nodeVisits) {
  if (anyHit)
    return walkLanes<true, OnePacketLanes<NodeTest>, NodeTest, Rows>(
        nodes, rootChild, rootCount, rays, lanes, leaf, single, user, nodeVisits);
  return walkLanes<false, OnePacketLanes<NodeTest>, NodeTest, Rows>(
      nodes, rootChild, rootCount, rays, lanes, leaf, single, user, nodeVisits);
}

/// walkPacket for each WalkConstants, indexed by the octant's sign bits plus 8 when every lane's
/// tnear is >= 0 (the same walks in both halves for a NodeTest that does not read the tnear
/// sign). A plain array in this header's unnamed namespace: a std::array would be instantiated
/// alike in every kernel's translation unit, each compiled with its own instruction set (see
/// PacketKernel.h).
template <class NodeTest, unsigned... Signs>
struct OctantWalks {
  static constexpr PacketTraverseFn walks[2 * sizeof...(Signs)] = {
      &walkPacket<NodeTest, WalkConstants<Signs, false>>...,
      &walkPacket<NodeTest, WalkConstants<Signs, NodeTest::kReadsTnearSign>>...};
};

/// walkPacket for the octant and tnear signs of `rays` (PacketTraverseFn): a copy of the walk
/// per octant and, where the node test reads it, tnear sign, since a packet's lanes share them.
/// Callgrind, primary packets from the BART cameras (AVX2 kernels): kitchen 7.1% and robots 9.1%
/// fewer instructions with the octant's rows as constants than with row numbers read from the
/// packet; with the tnear test out of the node test, 14% and 16% fewer mispredicted branches in
/// Callgrind's model (a test and branch per slot, and the instructions 0.1% and 0.7% fewer).
template <class NodeTest>
unsigned traversePacket(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                        PacketBoxRays& rays, unsigned lanes, bool anyHit, PacketLeafFn leaf,
                        PacketSingleFn single, void* user, std::uint64_t& nodeVisits) {
  using Walks = OctantWalks<NodeTest, 0, 1, 2, 3, 4, 5, 6, 7>;
  // tnear >= 0 in every lane, filled ones included (false for NaN, as the kernels' ordered
  // comparisons give).
  bool nonNegativeTnear = true;
  for (unsigned l = 0; l < kPacketLanes; ++l) nonNegativeTnear &= rays.tnear[l] >= 0.0f;
  return Walks::walks[rays.signs + (nonNegativeTnear ? 8u : 0u)](
      nodes, rootChild, rootCount, rays, lanes, anyHit, leaf, single, user, nodeVisits);
}

/// The kernels of one instruction set: the packet loads, the walk with its node test, the
/// triangle test with its lane type and the one-box test.
template <class NodeTest, class Lanes>
PacketKernels packetKernelsWith(BoxRayLoadFn load, TransformedRowsFn loadTransformedRows,
                                IdentityRowsFn loadIdentityRows, PacketOneBoxFn meetsOneBox) {
  return {load,
          &traversePacket<NodeTest>,
          &testTrianglesWith<Lanes>,
          loadTransformedRows,
          loadIdentityRows,
          meetsOneBox,
          nullptr,
          nullptr,
          nullptr};
}

}  // namespace
}  // namespace tg::detail
