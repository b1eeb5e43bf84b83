// The 4-wide BVH shared by the object BVH and the top-level BVH: node layout, the 4-box slab
// test (SSE on x86-64, where SSE2 is baseline, scalar elsewhere) and ordered front-to-back
// traversal. Internal header: not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#define TG_BVH4_SSE 1
#else
#define TG_BVH4_SSE 0
#endif

#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/Ray.h"

namespace tg::detail {

/// Deepest BVH4 level a builder produces; bounds the traversal stack (3 pushes per level).
inline constexpr int kBvh4MaxDepth = 64;

/// A node with four child slots, boxes stored per axis and side so that one SSE load gives
/// the same plane of all four children (two cache lines per node).
///
/// Slot i is an inner child when count[i] == 0 (child[i]: node index, always greater than this
/// node's), a leaf when count[i] > 0 (child[i]: first primitive, count[i] primitives stored
/// contiguously), unused when count[i] == 0 and child[i] == kInvalidId; an unused slot has an
/// empty box (lower +inf, upper -inf) that no ray can hit, so traversal need not test for it.
struct alignas(64) Bvh4Node {
  /// bounds[2 * axis] lower, bounds[2 * axis + 1] upper coordinates of the four children.
  float bounds[6][4];
  /// Node index (inner) or first primitive (leaf) per slot.
  std::uint32_t child[4];
  /// Primitive count per slot; 0 for inner and unused slots.
  std::uint32_t count[4];

  /// A node whose four slots are unused.
  static Bvh4Node makeEmpty() {
    Bvh4Node n;
    for (int s = 0; s < 4; ++s) {
      for (int a = 0; a < 3; ++a) {
        n.bounds[2 * a][s] = std::numeric_limits<float>::infinity();
        n.bounds[2 * a + 1][s] = -std::numeric_limits<float>::infinity();
      }
      n.child[s] = kInvalidId;
      n.count[s] = 0;
    }
    return n;
  }
  /// Sets the box of slot `s`.
  void setBounds(int s, const Box3f& b) {
    for (int a = 0; a < 3; ++a) {
      bounds[2 * a][s] = b.lower[a];
      bounds[2 * a + 1][s] = b.upper[a];
    }
  }
  /// The box of slot `s`.
  Box3f slotBounds(int s) const {
    return {{bounds[0][s], bounds[2][s], bounds[4][s]}, {bounds[1][s], bounds[3][s], bounds[5][s]}};
  }
  /// Union of the four slot boxes.
  Box3f unionBounds() const {
    Box3f b;
    for (int s = 0; s < 4; ++s)
      if (child[s] != kInvalidId) b.extend(slotBounds(s));
    return b;
  }
  /// True when slot `s` holds an inner child.
  bool isInner(int s) const { return count[s] == 0 && child[s] != kInvalidId; }
};

/// A std::allocator whose value-less construct (what vector::resize calls for new elements)
/// is `Init::make(p)` instead of value-initialisation; constructions with arguments are as
/// usual. For arrays a build sizes and then writes in full.
template <class T, class Init>
struct ResizeInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = ResizeInitAllocator<U, Init>;
  };
  ResizeInitAllocator() = default;
  template <class U>
  explicit ResizeInitAllocator(const ResizeInitAllocator<U, Init>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    Init::make(p);
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// Default-initialisation: growing a vector of nodes that are about to be overwritten then
/// costs no pass over memory (per-frame top-level rebuilds).
struct DefaultInit {
  template <class U>
  static void make(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
};

/// No initialisation at all, for trivially copyable, trivially destructible elements that are
/// written before they are read (such objects begin their lifetime implicitly in allocated
/// storage). Unlike DefaultInit it also skips default member initialisers: the leaf triangles
/// of a BVH (Vec3f zeroes its members) were zeroed on one thread before the parallel pass that
/// writes them.
struct NoInit {
  template <class U>
  static void make(U*) noexcept {
    static_assert(std::is_trivially_copyable_v<U> && std::is_trivially_destructible_v<U>,
                  "only elements without construction or destruction may be left unwritten");
  }
};

/// Vectors grown without zero-filling (see DefaultInit).
template <class T>
using DefaultInitAllocator = ResizeInitAllocator<T, DefaultInit>;
/// Vectors grown without any initialisation (see NoInit).
template <class T>
using UninitializedAllocator = ResizeInitAllocator<T, NoInit>;

/// The node array of a BVH4, root first.
using Bvh4NodeArray = std::vector<Bvh4Node, DefaultInitAllocator<Bvh4Node>>;

/// Relative widening of box intervals: the slab distance (b - o) * (1/d) is rounded three
/// times (difference, reciprocal, product); one more ulp of margin keeps rays that graze a box
/// holding a triangle whose edge lies on the box face.
inline constexpr float kBvhIntervalSlack = 4.0f * 0x1p-24f;

/// 1 - kBvhIntervalSlack (row 0) and 1 + kBvhIntervalSlack (row 1) in each of eight lanes: the
/// factors that widen box intervals whose ends are >= 0. Defined in Bvh4.cpp, out of sight of
/// the walks, so that the products take them as operands in memory: a constant the compiler
/// sees, it made again at every node (a broadcast per factor).
alignas(32) extern const float kBvhWidenFactors[2][8];

/// Per-ray constants of the 4-box test.
///
/// A zero direction component (+0 or -0) gets +inf as its reciprocal, whatever its sign: the
/// slab distances on that axis are then -inf/+inf when the origin lies strictly inside the slab,
/// +inf/-inf-signed values that empty the interval when it lies outside, and NaN (0 * inf) when
/// it lies exactly on a face. The interval update below is written so that a NaN leaves the
/// interval unchanged, which is the right answer for an origin on a face: a ray lying in a box
/// face touches the box (hard case 3). 0 * inf therefore never decides a slab test.
struct Bvh4Ray {
#if TG_BVH4_SSE
  __m128 origin[3];      ///< origin, broadcast per axis
  __m128 reciprocal[3];  ///< 1/direction, broadcast (+inf for +-0)
#else
  float origin[3];
  float reciprocal[3];
#endif
#if TG_BVH4_SSE
  /// Byte offsets in a Bvh4Node's bounds (16 bytes a row) of the row of the plane entered first
  /// per axis (nearOffset) and of the plane left last (farOffset), pointer-sized: a box test
  /// adds them to the bounds' address as they are (doubled by the load's addressing for the
  /// 32-byte rows of Bvh8Node), where a row number took a sign extension and a shift per plane
  /// and node.
  std::ptrdiff_t nearOffset[3], farOffset[3];
  __m128 tnearV;  ///< tnear, broadcast
#else
  int nearRow[3];  ///< Bvh4Node::bounds row of the plane entered first per axis
  int farRow[3];   ///< and of the plane left last
#endif
  bool nonNegativeTnear;  ///< tnear >= 0: intervals are widened by one product per end
  float tnear;            ///< smallest t that counts

  Bvh4Ray(const Vec3f& org, const Vec3f& dir, float tnear_)
      : Bvh4Ray(org, dir, reciprocals(dir), tnear_) {}

  /// From a ray whose reciprocal direction is already known (1/dir per component, +-inf for
  /// +-0, as ObjectRay::inverseDirection holds it): the same constants without three divisions.
  Bvh4Ray(const Vec3f& org, const Vec3f& dir, const Vec3f& inverseDir, float tnear_)
      : nonNegativeTnear(tnear_ >= 0.0f), tnear(tnear_) {
#if TG_BVH4_SSE
    // All three axes at once: the per-axis zero tests were branches, and the set-up was a tenth
    // of a walk's time for rays that leave after a node or two (most rays from outside a scene).
    const __m128 d = _mm_setr_ps(dir.x, dir.y, dir.z, 1.0f);
    const __m128 zero = _mm_cmpeq_ps(d, _mm_setzero_ps());
    const __m128 r =
        _mm_or_ps(_mm_and_ps(zero, _mm_set1_ps(std::numeric_limits<float>::infinity())),
                  _mm_andnot_ps(zero, _mm_setr_ps(inverseDir.x, inverseDir.y, inverseDir.z, 1.0f)));
    const __m128 o = _mm_setr_ps(org.x, org.y, org.z, 0.0f);
    origin[0] = _mm_shuffle_ps(o, o, 0x00);
    origin[1] = _mm_shuffle_ps(o, o, 0x55);
    origin[2] = _mm_shuffle_ps(o, o, 0xAA);
    reciprocal[0] = _mm_shuffle_ps(r, r, 0x00);
    reciprocal[1] = _mm_shuffle_ps(r, r, 0x55);
    reciprocal[2] = _mm_shuffle_ps(r, r, 0xAA);
    // -0 counts as positive (its reciprocal was made +inf), as does NaN.
    const int negative = _mm_movemask_ps(_mm_cmplt_ps(d, _mm_setzero_ps()));
    constexpr auto kRowBytes = static_cast<std::ptrdiff_t>(sizeof(Bvh4Node::bounds[0]));
    for (int a = 0; a < 3; ++a) {
      const std::ptrdiff_t n = (negative >> a) & 1;
      nearOffset[a] = kRowBytes * (2 * a + n);
      farOffset[a] = kRowBytes * (2 * a + 1 - n);
    }
    tnearV = _mm_set1_ps(tnear_);
#else
    for (int a = 0; a < 3; ++a) {
      origin[a] = org[a];
      reciprocal[a] = dir[a] == 0.0f ? std::numeric_limits<float>::infinity() : inverseDir[a];
      // -0 counts as positive: its reciprocal was made +inf above.
      const bool negative = dir[a] < 0.0f;
      nearRow[a] = 2 * a + (negative ? 1 : 0);
      farRow[a] = 2 * a + (negative ? 0 : 1);
    }
#endif
  }
};

/// Tests the four child boxes of `node` against [ray.tnear, tfar]. Returns a 4-bit mask of the
/// slots hit and writes each hit slot's (widened) entry distance into `entry`.
inline unsigned intersectBvh4Node(const Bvh4Node& node, const Bvh4Ray& ray, float tfar,
                                  float entry[4]) {
#if TG_BVH4_SSE
  __m128 tmin = ray.tnearV, tmax = _mm_set1_ps(tfar);
  const char* const rows = reinterpret_cast<const char*>(node.bounds);
  const auto row = [&](std::ptrdiff_t offset) {
    return _mm_load_ps(reinterpret_cast<const float*>(rows + offset));
  };
  for (int a = 0; a < 3; ++a) {
    const __m128 n =
        _mm_mul_ps(_mm_sub_ps(row(ray.nearOffset[a]), ray.origin[a]), ray.reciprocal[a]);
    const __m128 f =
        _mm_mul_ps(_mm_sub_ps(row(ray.farOffset[a]), ray.origin[a]), ray.reciprocal[a]);
    // MAXPS/MINPS return the second operand when either is NaN: a NaN slab distance (origin on
    // a face of a slab the ray is parallel to) keeps the interval as it is.
    tmin = _mm_max_ps(n, tmin);
    tmax = _mm_min_ps(f, tmax);
  }
  if (ray.nonNegativeTnear) {
    // Then tmin >= tnear >= 0 (a NaN slab distance keeps tmin), and widening an end by its own
    // magnitude is one product: t - t s and t (1 - s) round the same exact value (t s is exact,
    // s being a power of two). A negative tmax rejects the box either way. Only where both ends
    // are +inf (a ray parallel to an axis outside the box's slab while every other slab
    // distance overflows) is a box kept that the general form rejects: a wasted visit, never a
    // lost hit. Two to three percent of the BART walks from the files' cameras.
    tmin = _mm_mul_ps(tmin, _mm_load_ps(kBvhWidenFactors[0]));
    tmax = _mm_mul_ps(tmax, _mm_load_ps(kBvhWidenFactors[1]));
  } else {
    // Widen both ends by their own magnitude. An infinite end stays infinite on the side that
    // keeps the box, and turns into NaN (inf - inf) only on the side that already rejects it.
    const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
    const __m128 slack = _mm_set1_ps(kBvhIntervalSlack);
    tmin = _mm_sub_ps(tmin, _mm_mul_ps(_mm_and_ps(tmin, absMask), slack));
    tmax = _mm_add_ps(tmax, _mm_mul_ps(_mm_and_ps(tmax, absMask), slack));
  }
  _mm_storeu_ps(entry, tmin);
  return static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(tmin, tmax)));
#else
  unsigned mask = 0;
  for (int s = 0; s < 4; ++s) {
    float tmin = ray.tnear, tmax = tfar;
    for (int a = 0; a < 3; ++a) {
      const float n = (node.bounds[ray.nearRow[a]][s] - ray.origin[a]) * ray.reciprocal[a];
      const float f = (node.bounds[ray.farRow[a]][s] - ray.origin[a]) * ray.reciprocal[a];
      // Written so that NaN keeps the interval, like the SSE path.
      tmin = n > tmin ? n : tmin;
      tmax = f < tmax ? f : tmax;
    }
    tmin -= (tmin < 0.0f ? -tmin : tmin) * kBvhIntervalSlack;
    tmax += (tmax < 0.0f ? -tmax : tmax) * kBvhIntervalSlack;
    entry[s] = tmin;
    if (tmin <= tmax) mask |= 1u << s;
  }
  return mask;
#endif
}

/// A walk's node visits counted in a local and added to `total` when the walk returns. An
/// increment of the counter in memory at every node is a load and a store that the compiler
/// must also assume may change the node array's address (both are reached through references),
/// so it read that address again at every node.
class LocalVisitCount {
 public:
  explicit LocalVisitCount(std::uint64_t& total) : total_(total) {}
  ~LocalVisitCount() { total_ += visits; }
  LocalVisitCount(const LocalVisitCount&) = delete;
  LocalVisitCount& operator=(const LocalVisitCount&) = delete;
  std::uint64_t visits = 0;  ///< visits so far

 private:
  std::uint64_t& total_;
};

// The order of any-hit walks. Every any-hit walk (single rays and packets, top levels and
// objects, four- and eight-wide) visits the children a ray hits highest slot first, then down
// to the lowest, as Embree's any-hit walks do; the answer is the same in any order, only how
// soon a blocker is found differs. The builders put the lower side of each split in the lower
// slots, so the walk takes the upper side of a node first, whatever the ray: in the BART
// scenes, lit from lamps under their ceilings, the blockers of shadow rays (shades, fittings,
// ceilings) lie on that side. Unhinted shadow rays from the files' cameras, against the lowest
// slot first in objects and the farthest middle of the ray's stretch first in top levels (the
// orders before): node visits per ray 3.52 -> 2.01 (kitchen), 2.67 -> 2.00 (robots),
// 3.67 -> 3.30 (museum), 5.65 -> 2.01 for the kitchen flattened into one object; Callgrind
// counted 18% (kitchen) and 9% (robots) fewer instructions; speed as a share of Embree MEDIUM's
// rtcOccluded1 in alternating processes, 0.61-0.66 -> 0.86-1.02 (kitchen) and 0.80-0.84 ->
// 0.94-1.00 (robots). From cameras framing the bounds, node visits per ray: 1.57 -> 1.40
// (kitchen), 1.93 -> 2.10 (robots), 2.60 -> 1.66 (museum), and 7.38 -> 7.36 for the built-in
// sphereflake. A scene lit from below would walk longer; no fixed order suits every scene, and the
// occluder hint (TraversalContext::occluder) finds coherent blockers in any order.

/// Walks a BVH4. Closest-hit walks go front to back: at each node the children hit are visited
/// nearest entry first, the others pushed with their entry distance and skipped when popped
/// beyond the closest hit. Any-hit walks visit the children hit highest slot first (see the
/// order of any-hit walks above) and return at the first hit. `leaf(first, count)` tests primitives
/// [first, first + count) and returns true when it found a hit; closest-hit leaf functions lower
/// `tfar` themselves. An entry exactly at tfar is still visited, so the tie rule sees every
/// candidate at an equal t.
///
/// The walk starts at the subtree (rootChild, rootCount): node rootChild when rootCount is 0,
/// else the leaf of rootCount primitives at rootChild (traverseBvh4 starts at the root node).
template <bool AnyHit, class LeafFn>
bool traverseBvh4From(const Bvh4NodeArray& nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                      const Bvh4Ray& ray, const float& tfar, std::uint64_t& nodeVisits,
                      LeafFn&& leaf) {
  if (nodes.empty()) return false;
  struct Entry {
    std::uint32_t child, count;
    float tmin;
  };
  const float tnear = ray.tnear;
  const Bvh4Node* const nodeData = nodes.data();
  LocalVisitCount count(nodeVisits);
  Entry stack[3 * kBvh4MaxDepth + 4];
  int stackSize = 0;
  Entry current{rootChild, rootCount, tnear};
  bool found = false;
  for (;;) {
    if (current.count == 0) {
      ++count.visits;
      const Bvh4Node& node = nodeData[current.child];
      float entry[4];
      if constexpr (AnyHit) {
        const unsigned mask = intersectBvh4Node(node, ray, tfar, entry);
        // Highest slot first (the order of any-hit walks, above): the lower slots wait on the
        // stack, the next highest on top.
        if (mask != 0) {
          int next = -1;
          for (int s = 0; s < 4; ++s) {
            if (!(mask & (1u << s))) continue;
            if (next >= 0)
              stack[stackSize++] = Entry{node.child[next], node.count[next], entry[next]};
            next = s;
          }
          current = Entry{node.child[next], node.count[next], entry[next]};
          continue;
        }
      } else if (const unsigned mask = intersectBvh4Node(node, ray, tfar, entry); mask != 0) {
        // Gather the children hit and order them by entry distance (slot order on ties, so the
        // walk never depends on anything but the tree and the ray).
        Entry hits[4];
        int n = 0;
        for (int s = 0; s < 4; ++s) {
          if (!(mask & (1u << s))) continue;
          Entry e{node.child[s], node.count[s], entry[s]};
          int k = n++;
          for (; k > 0 && hits[k - 1].tmin > e.tmin; --k) hits[k] = hits[k - 1];
          hits[k] = e;
        }
        // Farther children wait on the stack; the nearest is visited now.
        for (int k = n - 1; k > 0; --k) stack[stackSize++] = hits[k];
        current = hits[0];
        continue;
      }
    } else {
      if (leaf(current.child, current.count)) {
        if constexpr (AnyHit) return true;
        found = true;
      }
    }
    // Pop the next subtree whose entry still lies before the closest hit.
    for (;;) {
      if (stackSize == 0) return found;
      current = stack[--stackSize];
      if (!(current.tmin > tfar)) break;
    }
  }
}

/// traverseBvh4From for the ray (origin, direction, tnear).
template <bool AnyHit, class LeafFn>
bool traverseBvh4From(const Bvh4NodeArray& nodes, std::uint32_t rootChild, std::uint32_t rootCount,
                      const Vec3f& origin, const Vec3f& direction, float tnear, const float& tfar,
                      std::uint64_t& nodeVisits, LeafFn&& leaf) {
  return traverseBvh4From<AnyHit>(nodes, rootChild, rootCount, Bvh4Ray(origin, direction, tnear),
                                  tfar, nodeVisits, static_cast<LeafFn&&>(leaf));
}

/// traverseBvh4From at the root node.
template <bool AnyHit, class LeafFn>
bool traverseBvh4(const Bvh4NodeArray& nodes, const Vec3f& origin, const Vec3f& direction,
                  float tnear, const float& tfar, std::uint64_t& nodeVisits, LeafFn&& leaf) {
  return traverseBvh4From<AnyHit>(nodes, 0, 0, origin, direction, tnear, tfar, nodeVisits,
                                  static_cast<LeafFn&&>(leaf));
}

}  // namespace tg::detail
