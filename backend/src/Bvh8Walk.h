// The single-ray walks (closest and any hit) over eight-wide BVHs collapsed from a BVH4
// (Bvh8Twin.h), eight boxes per AVX instruction. Internal header: not installed; include it only
// where the walk is instantiated (it brings in the AVX intrinsics).
#pragma once

#include "Bvh4.h"
#include "Bvh8Twin.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#include "SlabWidening8.h"
/// 1 when this compiler can build the walk (it is entered only on CPUs with AVX2, see
/// activeSimdIsa).
#define TG_BVH8_WALK 1
#else
#define TG_BVH8_WALK 0
#endif

namespace tg::detail {

#if TG_BVH8_WALK
/// A subtree waiting on an eight-wide walk's stack: node `child` of the eight-wide array when
/// `count` is 0, else the leaf of `count` primitives at `child`; `key` orders the children of a
/// node: the entry distance for closest hits, which visit smaller keys first and skip those
/// beyond the closest hit; for any hits only traverseBvh8's sort of the root's children reads
/// it (minus the slot, so the highest slot comes first).
struct Bvh8WalkEntry {
  std::uint32_t child, count;
  float key;
};

/// Entries an eight-wide walk's stack holds at most: seven per level. A twin spans one or two
/// BVH4 levels; a node of the smallest-cost collapse (buildBvh8) at least half of one, since its
/// children are halves of BVH4 nodes or smaller parts.
inline constexpr int kBvh8StackSize = 14 * kBvh4MaxDepth + 8;

/// The loop the eight-wide walks share, from `current` with `stackSize` entries on `stack`:
/// eight boxes per test with the 4-box test's arithmetic box by box (see intersectBvh4Node for
/// the NaN and widening rules). Closest hits (AnyHit false) visit the children hit nearest
/// entry first; any hits highest slot first (the order of any-hit walks, Bvh4.h).
template <bool AnyHit, class LeafFn>
[[gnu::always_inline, gnu::target("avx2")]] inline bool walkBvh8(
    const Bvh8Node* nodeData, Bvh8WalkEntry* stack, int stackSize, Bvh8WalkEntry current,
    const Bvh4Ray& ray, const float& tfar, LocalVisitCount& count, LeafFn& leaf) {
  using Entry = Bvh8WalkEntry;
  const __m256 origin[3] = {_mm256_set_m128(ray.origin[0], ray.origin[0]),
                            _mm256_set_m128(ray.origin[1], ray.origin[1]),
                            _mm256_set_m128(ray.origin[2], ray.origin[2])};
  const __m256 reciprocal[3] = {_mm256_set_m128(ray.reciprocal[0], ray.reciprocal[0]),
                                _mm256_set_m128(ray.reciprocal[1], ray.reciprocal[1]),
                                _mm256_set_m128(ray.reciprocal[2], ray.reciprocal[2])};
  const __m256 tnear = _mm256_set1_ps(ray.tnear);
  const bool nonNegativeTnear = ray.nonNegativeTnear;
  bool found = false;
  // The subtree being walked, as two scalars rather than an Entry: its key is read only when
  // it comes off the stack, and an Entry kept whole was kept in memory, with the key of every
  // child entered stored into it.
  std::uint32_t child = current.child, leafCount = current.count;
  for (;;) {
    if (leafCount == 0) {
      ++count.visits;
      const Bvh8Node& node = nodeData[child];
      __m256 tmin = tnear, tmax = _mm256_set1_ps(tfar);
      // Rows of 32 bytes: twice Bvh4Ray's offsets, a scale the loads' addressing applies. (No
      // lambda here: it would not inherit this function's AVX2 target.)
      static_assert(sizeof(Bvh8Node::bounds[0]) == 2 * sizeof(Bvh4Node::bounds[0]));
      const char* const rows = reinterpret_cast<const char*>(node.bounds);
      for (int a = 0; a < 3; ++a) {
        const __m256 nearPlanes =
            _mm256_load_ps(reinterpret_cast<const float*>(rows + 2 * ray.nearOffset[a]));
        const __m256 farPlanes =
            _mm256_load_ps(reinterpret_cast<const float*>(rows + 2 * ray.farOffset[a]));
        const __m256 n = _mm256_mul_ps(_mm256_sub_ps(nearPlanes, origin[a]), reciprocal[a]);
        const __m256 f = _mm256_mul_ps(_mm256_sub_ps(farPlanes, origin[a]), reciprocal[a]);
        tmin = _mm256_max_ps(n, tmin);
        tmax = _mm256_min_ps(f, tmax);
      }
      widenSlabInterval8(tmin, tmax, nonNegativeTnear);
      unsigned mask =
          static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(tmin, tmax, _CMP_LE_OQ)));
      if (mask != 0) {
        if constexpr (AnyHit) {
          // The highest slot now, the others on the stack lowest first (the next highest on
          // top). Any-hit walks read no keys but the root's (traverseBvh8 sorts by them).
          const unsigned highest = 31u - static_cast<unsigned>(__builtin_clz(mask));
          for (mask &= ~(1u << highest); mask != 0; mask &= mask - 1) {
            const auto s = static_cast<unsigned>(__builtin_ctz(mask));
            stack[stackSize++] = Entry{node.child[s], node.count[s], 0.0f};
          }
          child = node.child[highest];
          leafCount = node.count[highest];
          continue;
        }
        // One child hit (most nodes): straight into it, no key needed.
        const auto s0 = static_cast<unsigned>(__builtin_ctz(mask));
        mask &= mask - 1;
        if (mask == 0) {
          child = node.child[s0];
          leafCount = node.count[s0];
          continue;
        }
        alignas(32) float key[8];
        _mm256_store_ps(key, tmin);
        const auto slot = [&](unsigned s) { return Entry{node.child[s], node.count[s], key[s]}; };
        const Entry e0 = slot(s0);
        const Entry e1 = slot(static_cast<unsigned>(__builtin_ctz(mask)));
        mask &= mask - 1;
        if (mask == 0) {
          // Two: the smaller key first, slot order on ties.
          const bool second = e1.key < e0.key;
          stack[stackSize++] = second ? e0 : e1;
          const Entry& next = second ? e1 : e0;
          child = next.child;
          leafCount = next.count;
          continue;
        }
        // Three or more: push them all and sort the run smallest key on top (slot order kept
        // among equal entries), then take the top.
        const int base = stackSize;
        stack[stackSize++] = e0;
        stack[stackSize++] = e1;
        do {
          stack[stackSize++] = slot(static_cast<unsigned>(__builtin_ctz(mask)));
          mask &= mask - 1;
        } while (mask != 0);
        for (int i = base + 1; i < stackSize; ++i) {
          const Entry e = stack[i];
          int j = i;
          for (; j > base && stack[j - 1].key <= e.key; --j) stack[j] = stack[j - 1];
          stack[j] = e;
        }
        const Entry& next = stack[--stackSize];
        child = next.child;
        leafCount = next.count;
        continue;
      }
    } else if (leaf(child, leafCount)) {
      if constexpr (AnyHit) return true;
      found = true;
    }
    if constexpr (AnyHit) {
      // tfar never changes: every entry on the stack is still to be walked.
      if (stackSize == 0) return false;
      const Entry& next = stack[--stackSize];
      child = next.child;
      leafCount = next.count;
    } else {
      // Pop the next subtree whose entry still lies before the closest hit.
      for (;;) {
        if (stackSize == 0) return found;
        const Entry& next = stack[--stackSize];
        if (!(next.key > tfar)) {
          child = next.child;
          leafCount = next.count;
          break;
        }
      }
    }
  }
}

/// traverseBvh4From's walk from a BVH4's root, whose four children are tested with the 4-box
/// test, then over their twins: `root` and `twins` as buildBvh8BelowRoot writes them (the root's
/// inner slots index `twins`). A twin tests a subset
/// of the boxes above each leaf that the BVH4 walk tests, so it reaches every leaf that walk
/// reaches: the closest-hit walk (AnyHit false, nearest entry first) gives the same closest hit
/// whatever the order, since the leaves apply the tie rule, and the any-hit walk (AnyHit true,
/// highest slot first) the same answer.
///
/// Compiled for AVX2 (the function attribute; the rest of the library stays at the baseline):
/// call it only when the CPU runs AVX2. The root's own test stays four-wide: its twin would
/// test the grandchildren for every ray that enters the scene's box. From the BART robots'
/// camera the closest-hit walk took 1.13-1.14 of Embree MEDIUM's time so, 1.17 through the
/// root's twin.
template <bool AnyHit, class LeafFn>
[[gnu::target("avx2")]] bool traverseBvh8(const Bvh4Node& root, const Bvh8NodeArray& twins,
                                          const Bvh4Ray& ray, const float& tfar,
                                          std::uint64_t& nodeVisits, LeafFn&& leaf) {
  LocalVisitCount count(nodeVisits);
  using Entry = Bvh8WalkEntry;
  Entry stack[kBvh8StackSize];
  int stackSize = 0;
  ++count.visits;
  float entry[4];
  const unsigned mask = intersectBvh4Node(root, ray, tfar, entry);
  if (mask == 0) return false;
  Entry hits[4];
  int n = 0;
  for (int s = 0; s < 4; ++s) {
    if (!(mask & (1u << s))) continue;
    // Any hits order the root's children highest slot first too, by a key that falls with the
    // slot.
    const Entry e{root.child[s], root.count[s], AnyHit ? -static_cast<float>(s) : entry[s]};
    int k = n++;
    for (; k > 0 && hits[k - 1].key > e.key; --k) hits[k] = hits[k - 1];
    hits[k] = e;
  }
  for (int k = n - 1; k > 0; --k) stack[stackSize++] = hits[k];
  return walkBvh8<AnyHit>(twins.data(), stack, stackSize, hits[0], ray, tfar, count, leaf);
}

/// traverseBvh4From's walk over an eight-wide BVH (buildBvh8) from node `start` (0: the root):
/// closest hits nearest entry first, any hits highest slot first. Compiled for AVX2 (call it
/// only when the CPU runs AVX2).
template <bool AnyHit, class LeafFn>
[[gnu::target("avx2")]] bool traverseWideBvh8(const Bvh8NodeArray& wide, const Bvh4Ray& ray,
                                              const float& tfar, std::uint64_t& nodeVisits,
                                              LeafFn&& leaf, std::uint32_t start = 0) {
  if (wide.empty()) return false;
  LocalVisitCount count(nodeVisits);
  Bvh8WalkEntry stack[kBvh8StackSize];
  return walkBvh8<AnyHit>(wide.data(), stack, 0, Bvh8WalkEntry{start, 0, ray.tnear}, ray, tfar,
                          count, leaf);
}
#endif

}  // namespace tg::detail
