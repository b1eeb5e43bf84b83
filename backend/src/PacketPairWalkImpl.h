// The closest-hit walk of two packets as one (PairTraverseFn), written once for a node test of
// kPairLanes lanes: included by the kernel translation units that have one, after defining it.
// Everything here has internal linkage (see PacketKernel.h for why). Internal header: not
// installed.
//
// PairNodeTest(rays) is made once per walk and keeps what of both halves stays fixed (all but
// tfar); its test<Rows>(node, rays, lanes, hit, entry) tests the four child boxes of `node`
// against the pair lanes `lanes` with exactly the arithmetic of the packet node test, writing
// per slot the lanes that hit it (hit[s]) and each lane's widened entry (entry[s][lane]); its
// beyond(entry, rays, mask) gives the lanes of `mask` whose entry lies beyond their tfar.
#pragma once

#include "PacketTraversalImpl.h"

namespace tg::detail {
namespace {

/// The pair walk: walkPacket's closest-hit walk (children front to back by the entry of the
/// lowest lane entering each, a lane leaving a subtree whose entry lies beyond its closest hit,
/// a subtree entered by one lane handed to it alone) over kPairLanes lanes. Leaves get the pair
/// lanes that reach them, which the callback splits into halves.
///
/// Why: neighbouring packets of camera rays enter mostly the same nodes. Counted from the BART
/// cameras (one thread, 640x480), two packets of 8 side by side visit together 0.742 (kitchen)
/// and 1.150 (robots) distinct nodes per ray where each alone visits 1.372 and 2.262.
template <class PairNodeTest, class Rows>
void walkPair(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
              PacketBoxRays* const (&rays)[2], unsigned lanes, PairLeafFn leaf, PairSingleFn single,
              void* user, std::uint64_t& nodeVisits) {
  struct Entry {
    std::uint32_t child, count;
    unsigned lanes;
    alignas(64) float entry[kPairLanes];
  };
  Entry stack[3 * kBvh4MaxDepth + 4];
  int stackSize = 0;
  const PairNodeTest nodeTest(rays);
  std::uint32_t child = rootChild, count = rootCount;
  unsigned current = lanes;
  for (;;) {
    if (count == 0 && (current & (current - 1)) == 0) {
      single(user, child, lowestLane(current), rays);
    } else if (count == 0) {
      ++nodeVisits;
      const Bvh4Node& node = nodes[child];
      unsigned hit[4];
      alignas(64) float entry[4][kPairLanes];
      nodeTest.template test<Rows>(node, rays, current, hit, entry);
      int order[4];
      float key[4];
      int n = 0;
      for (int s = 0; s < 4; ++s) {
        if (hit[s] == 0) continue;
        // By the lowest lane's entry, as walkPacket orders closest hits.
        const float k = entry[s][lowestLane(hit[s])];
        int j = n++;
        for (; j > 0 && key[j - 1] > k; --j) {
          key[j] = key[j - 1];
          order[j] = order[j - 1];
        }
        key[j] = k;
        order[j] = s;
      }
      if (n > 0) {
        for (int j = 0; j < n; ++j) {
          const int s = order[j];
          if (node.count[s] == 0) {
            const char* line = reinterpret_cast<const char*>(nodes + node.child[s]);
            __builtin_prefetch(line);
            __builtin_prefetch(line + 64);
          }
        }
        for (int j = n - 1; j > 0; --j) {
          const int s = order[j];
          Entry& e = stack[stackSize++];
          e.child = node.child[s];
          e.count = node.count[s];
          e.lanes = hit[s];
          PairNodeTest::copyEntry(entry[s], e.entry);
        }
        child = node.child[order[0]];
        count = node.count[order[0]];
        current = hit[order[0]];
        continue;
      }
    } else {
      leaf(user, child, count, current, rays);
    }
    // Pop the next subtree some lane still needs.
    for (;;) {
      if (stackSize == 0) return;
      const Entry& e = stack[--stackSize];
      const unsigned need = e.lanes & ~PairNodeTest::beyond(e.entry, rays, e.lanes);
      if (need != 0) {
        child = e.child;
        count = e.count;
        current = need;
        break;
      }
    }
  }
}

/// walkPair for each WalkConstants, indexed as OctantWalks indexes walkPacket.
template <class PairNodeTest, unsigned... Signs>
struct OctantPairWalks {
  static constexpr PairTraverseFn walks[2 * sizeof...(Signs)] = {
      &walkPair<PairNodeTest, WalkConstants<Signs, false>>...,
      &walkPair<PairNodeTest, WalkConstants<Signs, true>>...};
};

/// walkPair for the shared octant of both halves and the sign of their tnear (PairTraverseFn).
template <class PairNodeTest>
void traversePair(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                  PacketBoxRays* const (&rays)[2], unsigned lanes, PairLeafFn leaf,
                  PairSingleFn single, void* user, std::uint64_t& nodeVisits) {
  using Walks = OctantPairWalks<PairNodeTest, 0, 1, 2, 3, 4, 5, 6, 7>;
  bool nonNegativeTnear = true;
  for (const PacketBoxRays* half : rays)
    for (unsigned l = 0; l < kPacketLanes; ++l) nonNegativeTnear &= half->tnear[l] >= 0.0f;
  Walks::walks[rays[0]->signs + (nonNegativeTnear ? 8u : 0u)](
      nodes, rootChild, rootCount, rays, lanes, leaf, single, user, nodeVisits);
}

}  // namespace
}  // namespace tg::detail
