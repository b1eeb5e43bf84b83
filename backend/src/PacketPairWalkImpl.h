// The walks of two packets as one (PairTraverseFn for closest hits, PairOccludedFn for any hit),
// written once for a node test of kPairLanes lanes: included by the kernel translation units
// that have one, after defining it. Both are walkLanes (PacketTraversalImpl.h), the packet
// walk, over the lanes of both halves (PairLanes).
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

/// What the walk over the lanes of two packets as one takes from them (see walkLanes): both
/// halves' rays, the pair callbacks of each query, and the node test's own copy and comparison
/// of a stack entry's kPairLanes entries. Leaves get the pair lanes that reach them, which the
/// callback splits into halves.
///
/// Why pairs: neighbouring packets of camera rays enter mostly the same nodes. Counted from the
/// BART cameras (one thread, 640x480), two packets of 8 side by side visit together 0.742
/// (kitchen) and 1.150 (robots) distinct nodes per ray where each alone visits 1.372 and 2.262.
template <class PairNodeTest>
struct PairLanes {
  using Rays = PacketBoxRays* const (&)[2];
  static constexpr unsigned kLanes = kPairLanes;
  /// A stack entry's entries are copied and compared as whole vectors.
  static constexpr std::size_t kEntryAlign = 64;
  template <bool kAnyHit>
  using Leaf = typename PairCallbacks<kAnyHit>::Leaf;
  template <bool kAnyHit>
  using Single = typename PairCallbacks<kAnyHit>::Single;
  static unsigned beyond(const float* entry, Rays rays, unsigned mask) {
    return PairNodeTest::beyond(entry, rays, mask);
  }
  static void copyEntry(const float* from, float* to) { PairNodeTest::copyEntry(from, to); }
};

/// The closest-hit pair walk (PairTraverseFn for one WalkConstants).
template <class PairNodeTest, class Rows>
void walkPair(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
              PacketBoxRays* const (&rays)[2], unsigned lanes, PairLeafFn leaf, PairSingleFn single,
              void* user, std::uint64_t& nodeVisits) {
  walkLanes<false, PairLanes<PairNodeTest>, PairNodeTest, Rows>(
      nodes, rootChild, rootCount, rays, lanes, leaf, single, user, nodeVisits);
}

/// The any-hit pair walk (PairOccludedFn for one WalkConstants).
template <class PairNodeTest, class Rows>
unsigned walkPairOccluded(const Bvh4Node* nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                          PacketBoxRays* const (&rays)[2], unsigned lanes, PairOccludedLeafFn leaf,
                          PairOccludedSingleFn single, void* user, std::uint64_t& nodeVisits) {
  return walkLanes<true, PairLanes<PairNodeTest>, PairNodeTest, Rows>(
      nodes, rootChild, rootCount, rays, lanes, leaf, single, user, nodeVisits);
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
                      PacketBoxRays* const (&rays)[2], unsigned lanes, PairOccludedLeafFn leaf,
                      PairOccludedSingleFn single, void* user, std::uint64_t& nodeVisits) {
  using Walks = OctantPairOccludedWalks<PairNodeTest, 0, 1, 2, 3, 4, 5, 6, 7>;
  return Walks::walks[rays[0]->signs + (pairTnearNonNegative(rays) ? 8u : 0u)](
      nodes, rootChild, rootCount, rays, lanes, leaf, single, user, nodeVisits);
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
