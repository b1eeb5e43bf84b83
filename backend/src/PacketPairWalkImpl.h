// The walks of two packets as one (PairTraverseFn for closest hits, PairOccludedFn for any hit),
// written once for a node test of kPairLanes lanes: included by the kernel translation units
// that have one, after defining it. Both are one template on the query (walkPairFor), each
// compiled on its own rather than one walk testing an any-hit flag at run time as walkPacket
// does: the closest-hit walk is the primary rays' hot loop and carries nothing of the other.
// Everything here has internal linkage (see PacketKernel.h for why). Internal header: not
// installed.
//
// PairNodeTest(rays) is made once per walk and keeps what of both halves stays fixed (all but
// tfar); its test<Rows>(node, rays, lanes, hit, entry) tests the four child boxes of `node`
// against the pair lanes `lanes` with exactly the arithmetic of the packet node test, writing
// per slot the lanes that hit it (hit[s]) and each lane's widened entry (entry[s][lane]); its
// beyond(entry, rays, mask) gives the lanes of `mask` whose entry lies beyond their tfar and
// copyEntry(from, to) copies a slot's kPairLanes entries into a stack entry.
#pragma once

#include "PacketTraversalImpl.h"

namespace tg::detail {
namespace {

/// The callbacks of a pair walk for closest hits (kAnyHit false) or any hit (true).
template <bool kAnyHit>
struct PairCallbacks {
  using Leaf = PairLeafFn;
  using Single = PairSingleFn;
};
template <>
struct PairCallbacks<true> {
  using Leaf = PairOccludedLeafFn;
  using Single = PairOccludedSingleFn;
};

/// The pair walk, walkPacket's walk over kPairLanes lanes, written once for both queries as
/// walkPacket is. Closest hits (kAnyHit false): children front to back by the entry of the
/// lowest lane entering each, a lane leaving a subtree whose entry lies beyond its closest hit.
/// Any hit (true): children in `order`, farthest first by the entry of each one's lowest lane
/// or in slot order, and occluded lanes leave the walk; returns them. Both: a subtree entered by
/// one lane is handed to it alone, and leaves get the pair lanes that reach them, which the
/// callback splits into halves. The closest-hit query is the primary rays' hot loop: everything
/// of the other query is under `if constexpr`, so it compiles to its own walk.
///
/// Why pairs: neighbouring packets of camera rays enter mostly the same nodes. Counted from the
/// BART cameras (one thread, 640x480), two packets of 8 side by side visit together 0.742
/// (kitchen) and 1.150 (robots) distinct nodes per ray where each alone visits 1.372 and 2.262.
template <bool kAnyHit, class PairNodeTest, class Rows>
unsigned walkPairFor(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                     PacketBoxRays* const (&rays)[2], unsigned lanes, AnyHitOrder order,
                     typename PairCallbacks<kAnyHit>::Leaf leaf,
                     typename PairCallbacks<kAnyHit>::Single single, void* user,
                     std::uint64_t& nodeVisits) {
  struct Entry {
    std::uint32_t child, count;
    unsigned lanes;
    alignas(64) float entry[kPairLanes];
  };
  Entry stack[3 * kBvh4MaxDepth + 4];
  int stackSize = 0;
  // Counted in a register: the callbacks are opaque, so a count kept in nodeVisits itself was
  // stored and loaded again around every one of them.
  LocalVisitCount visits(nodeVisits);
  const PairNodeTest nodeTest(rays);
  // Closest hits: no sorting key is negated and every lane stays active.
  const bool ordered = !kAnyHit || order == AnyHitOrder::FarthestFirst;
  [[maybe_unused]] unsigned active = lanes, occluded = 0;
  std::uint32_t child = rootChild, count = rootCount;
  unsigned current = lanes;
  for (;;) {
    [[maybe_unused]] unsigned found = 0;
    if (count == 0 && (current & (current - 1)) == 0) {
      if constexpr (kAnyHit) {
        if (single(user, child, lowestLane(current), rays) != 0) found = current;
      } else {
        single(user, child, lowestLane(current), rays);
      }
    } else if (count == 0) {
      ++visits.visits;
      const Bvh4Node& node = nodes[child];
      unsigned hit[4];
      alignas(64) float entry[4][kPairLanes];
      nodeTest.template test<Rows>(node, rays, current, hit, entry);
      int slots[4];
      float key[4];
      int n = 0;
      for (int s = 0; s < 4; ++s) {
        if (hit[s] == 0) continue;
        int j = n++;
        if (ordered) {
          // By the lowest lane's entry: nearest first for closest hits, farthest first (negated
          // keys in ascending order) for any hit.
          const float e = entry[s][lowestLane(hit[s])];
          const float k = kAnyHit ? -e : e;
          for (; j > 0 && key[j - 1] > k; --j) {
            key[j] = key[j - 1];
            slots[j] = slots[j - 1];
          }
          key[j] = k;
        }
        slots[j] = s;
      }
      if (n > 0) {
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
          PairNodeTest::copyEntry(entry[s], e.entry);
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
      const unsigned need = want & ~PairNodeTest::beyond(e.entry, rays, want);
      if (need != 0) {
        child = e.child;
        count = e.count;
        current = need;
        break;
      }
    }
  }
}

/// The closest-hit pair walk (PairTraverseFn for one WalkConstants).
template <class PairNodeTest, class Rows>
void walkPair(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
              PacketBoxRays* const (&rays)[2], unsigned lanes, PairLeafFn leaf, PairSingleFn single,
              void* user, std::uint64_t& nodeVisits) {
  walkPairFor<false, PairNodeTest, Rows>(nodes, rootChild, rootCount, rays, lanes,
                                         AnyHitOrder::Slots, leaf, single, user, nodeVisits);
}

/// The any-hit pair walk (PairOccludedFn for one WalkConstants).
template <class PairNodeTest, class Rows>
unsigned walkPairOccluded(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                          PacketBoxRays* const (&rays)[2], unsigned lanes, AnyHitOrder order,
                          PairOccludedLeafFn leaf, PairOccludedSingleFn single, void* user,
                          std::uint64_t& nodeVisits) {
  return walkPairFor<true, PairNodeTest, Rows>(nodes, rootChild, rootCount, rays, lanes, order,
                                               leaf, single, user, nodeVisits);
}

/// walkPair for each WalkConstants, indexed as OctantWalks indexes walkPacket.
template <class PairNodeTest, unsigned... Signs>
struct OctantPairWalks {
  static constexpr PairTraverseFn walks[2 * sizeof...(Signs)] = {
      &walkPair<PairNodeTest, WalkConstants<Signs, false>>...,
      &walkPair<PairNodeTest, WalkConstants<Signs, true>>...};
};

/// walkPairOccluded for each WalkConstants, indexed as OctantWalks indexes walkPacket.
template <class PairNodeTest, unsigned... Signs>
struct OctantPairOccludedWalks {
  static constexpr PairOccludedFn walks[2 * sizeof...(Signs)] = {
      &walkPairOccluded<PairNodeTest, WalkConstants<Signs, false>>...,
      &walkPairOccluded<PairNodeTest, WalkConstants<Signs, true>>...};
};

/// Whether every lane of both halves has tnear >= 0 (false for NaN).
inline bool pairTnearNonNegative(PacketBoxRays* const (&rays)[2]) {
  bool nonNegative = true;
  for (const PacketBoxRays* half : rays)
    for (unsigned l = 0; l < kPacketLanes; ++l) nonNegative &= half->tnear[l] >= 0.0f;
  return nonNegative;
}

/// walkPairOccluded for the shared octant of both halves and the sign of their tnear
/// (PairOccludedFn).
template <class PairNodeTest>
unsigned occludedPair(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                      PacketBoxRays* const (&rays)[2], unsigned lanes, AnyHitOrder order,
                      PairOccludedLeafFn leaf, PairOccludedSingleFn single, void* user,
                      std::uint64_t& nodeVisits) {
  using Walks = OctantPairOccludedWalks<PairNodeTest, 0, 1, 2, 3, 4, 5, 6, 7>;
  return Walks::walks[rays[0]->signs + (pairTnearNonNegative(rays) ? 8u : 0u)](
      nodes, rootChild, rootCount, rays, lanes, order, leaf, single, user, nodeVisits);
}

/// walkPair for the shared octant of both halves and the sign of their tnear (PairTraverseFn).
template <class PairNodeTest>
void traversePair(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                  PacketBoxRays* const (&rays)[2], unsigned lanes, PairLeafFn leaf,
                  PairSingleFn single, void* user, std::uint64_t& nodeVisits) {
  using Walks = OctantPairWalks<PairNodeTest, 0, 1, 2, 3, 4, 5, 6, 7>;
  Walks::walks[rays[0]->signs + (pairTnearNonNegative(rays) ? 8u : 0u)](
      nodes, rootChild, rootCount, rays, lanes, leaf, single, user, nodeVisits);
}

}  // namespace
}  // namespace tg::detail
