// Object BVH4: build from the mesh, refit after vertex moves, and closest/any-hit queries with
// the watertight triangle test.
#include "BvhAccel.h"

#include "LeafRows.h"
#include "LeafTest.h"
#include "PacketRays.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "Bvh4Refit.h"
#include "Bvh8Walk.h"
#include "BvhBinning.h"
#include "tracegraph/backend/Simd.h"

namespace tg::detail {
namespace {

/// Meshes with fewer triangles are prepared and refitted on the calling thread: below this,
/// scheduling tasks costs more than it saves (the scene already builds objects in parallel).
constexpr std::size_t kParallelTriangles = 8192;
/// Ranges of the SAH build with more triangles bin in parallel and build their subtrees as
/// parallel tasks (BvhBuildOptions::parallelThreshold).
constexpr std::size_t kParallelBuildRange = 2048;
/// Top levels of a large tree whose children refit as parallel tasks: 4^2 subtrees keep two
/// threads busy, however unevenly the triangles are spread.
constexpr int kParallelRefitLevels = 2;
/// Degenerate count and bounds of the non-degenerate triangles: reduced over a mesh with Box3f
/// bounds (TriangleSummary), gathered by the leaves of Morton builds and refits in SSE registers
/// (LeafSummary).
template <class Box>
struct TriangleSummaryOf {
  std::size_t degenerate = 0;
  Box bounds;
  void merge(const TriangleSummaryOf& o) {
    degenerate += o.degenerate;
    bounds.extend(o.bounds);
  }
};
using TriangleSummary = TriangleSummaryOf<Box3f>;
using LeafSummary = TriangleSummaryOf<SseBox>;

/// Reduces perTriangle(i, acc) over the triangles [0, n) into an Acc (which provides merge),
/// on the calling thread below kParallelTriangles, else in blocks of at least `grain`.
template <class Acc, class Fn>
Acc reduceTriangles(std::size_t n, std::size_t grain, Fn&& perTriangle) {
  const auto block = [&](std::size_t begin, std::size_t end, Acc acc) {
    for (std::size_t i = begin; i < end; ++i) perTriangle(i, acc);
    return acc;
  };
  if (n < kParallelTriangles) return block(0, n, Acc{});
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, grain), Acc{},
      [&](const tbb::blocked_range<std::size_t>& r, const Acc& acc) {
        return block(r.begin(), r.end(), acc);
      },
      [](Acc a, const Acc& b) {
        a.merge(b);
        return a;
      });
}

/// fn(begin, end) over blocks of [0, n), in parallel from kParallelTriangles items on.
template <class Fn>
void forEachBlock(std::size_t n, std::size_t grain, Fn&& fn) {
  if (n < kParallelTriangles) {
    fn(std::size_t(0), n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) { fn(r.begin(), r.end()); });
}

/// fn(i) for every i in [0, n), in blocks as forEachBlock makes them.
template <class Fn>
void forEachIndex(std::size_t n, std::size_t grain, Fn&& fn) {
  forEachBlock(n, grain, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i != end; ++i) fn(i);
  });
}

TriangleVertices verticesOf(const TriangleMesh& mesh, std::size_t triangle) {
  const std::uint32_t* idx = mesh.indices.data() + 3 * triangle;
  return {mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]};
}

/// The vertices of `t` in SSE registers, lane 3 repeating z: three loads that stay inside the
/// triangle's nine floats.
inline void loadVertices(const TriangleVertices& t, __m128& a, __m128& b, __m128& c) {
  static_assert(sizeof(TriangleVertices) == 9 * sizeof(float), "vertices must be packed floats");
  const float* f = &t.v0.x;
  const __m128 r0 = _mm_loadu_ps(f), r1 = _mm_loadu_ps(f + 3), r2 = _mm_loadu_ps(f + 5);
  a = _mm_shuffle_ps(r0, r0, _MM_SHUFFLE(2, 2, 1, 0));
  b = _mm_shuffle_ps(r1, r1, _MM_SHUFFLE(2, 2, 1, 0));
  c = _mm_shuffle_ps(r2, r2, _MM_SHUFFLE(3, 3, 2, 1));
}

/// The box of the triangle (a, b, c), as Vec3's min and max take it (MINPS and MAXPS choose
/// between their operands as those do, NaN and signed zeros included).
inline SseBox triangleBox(__m128 a, __m128 b, __m128 c) {
  return {_mm_min_ps(_mm_min_ps(a, b), c), _mm_max_ps(_mm_max_ps(a, b), c)};
}

/// True when one component of the float cross product of the edges b - a and c - a is
/// certainly non-zero in exact arithmetic (the three components side by side). Each edge,
/// product and difference adds one rounding (relative 2^-24), so the float component differs
/// from the exact one by less than 2^-21 times the sum of its products' magnitudes; 2^-20 leaves
/// a margin, and 2^-120 covers products that underflow. Infinite or NaN components never pass.
inline bool certainlyNonDegenerate(__m128 a, __m128 b, __m128 c) {
  const __m128 e1 = _mm_sub_ps(b, a), e2 = _mm_sub_ps(c, a);
  const auto yzx = [](__m128 v) { return _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 0, 2, 1)); };
  const auto zxy = [](__m128 v) { return _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 1, 0, 2)); };
  const __m128 p = _mm_mul_ps(yzx(e1), zxy(e2)), q = _mm_mul_ps(zxy(e1), yzx(e2));
  const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  const __m128 difference = _mm_and_ps(_mm_sub_ps(p, q), absMask);
  const __m128 bound = _mm_add_ps(
      _mm_mul_ps(_mm_set1_ps(0x1p-20f), _mm_add_ps(_mm_and_ps(p, absMask), _mm_and_ps(q, absMask))),
      _mm_set1_ps(0x1p-120f));
  return (_mm_movemask_ps(_mm_cmpgt_ps(difference, bound)) & 7) != 0;
}

/// isDegenerateTriangle for `t`, loaded as (a, b, c), with a float answer for the common case:
/// the exact test in double costs as much as the rest of a refit's work on a triangle.
inline bool degenerate(const TriangleVertices& t, __m128 a, __m128 b, __m128 c) {
  return !certainlyNonDegenerate(a, b, c) && isDegenerateTriangle(t.v0, t.v1, t.v2);
}

/// Box of the leaf triangles [first, first + count) (in leaf order); their degenerate count
/// goes into `degenerateCount` and the boxes of the others into `bounds`: the boxes of a loop with
/// Box3f, in SSE registers. Callgrind, refits of 65,536 triangles: 30% fewer instructions with
/// these and refitBvh4's slots in SSE (69.5M -> 48.8M for four refits); four Morton builds
/// 273.7M -> 248.8M.
inline SseBox leafBoxSse(const TriangleVertices* triangles, std::uint32_t first,
                         std::uint32_t count, std::size_t& degenerateCount, SseBox& bounds) {
  SseBox box;
  for (std::uint32_t k = first; k < first + count; ++k) {
    const TriangleVertices& t = triangles[k];
    __m128 a, b, c;
    loadVertices(t, a, b, c);
    const SseBox triangle = triangleBox(a, b, c);
    box.extend(triangle);
    if (degenerate(t, a, b, c)) {
      ++degenerateCount;
    } else {
      bounds.extend(triangle);
    }
  }
  return box;
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

void BvhAccel::build(const TriangleMesh& mesh) {
  const auto start = std::chrono::steady_clock::now();
  stats_ = {};
  stats_.triangles = mesh.triangleCount();
  // Single rays that walk a whole SAH tree (rigid parts, sole identity instances, objects not
  // opened into the top level) walk an eight-wide copy of it where the CPU runs AVX2: half the
  // node visits at eight boxes per test. One thread, 640x480, alternating processes, against
  // the BVH4: the flattened BART kitchen from its camera 54.3 -> 48.6 ms, the flattened robots
  // 55.0 -> 52.1, the instanced robots (661 rigid parts) 60.9-61.0 -> 59.3-59.6 (with twins
  // opened from the root; the smallest-cost collapse of buildBvh8 took the kitchen's visits
  // per ray from 9.26 to 7.80). Walks entered at a subtree of the first levels (the static
  // chunks' braided into the top level) take it too, from the wide nodes buildBvh8 gives those
  // subtrees (wideEntries_): 8.70 -> 7.50 visits per ray from the kitchen's camera. Refitted
  // (Morton) trees have none: buildSah makes the copy beside the leaf rows.
  wide_.clear();
  wideEntries_.clear();
  if (kind_ == AccelKind::BvhFast) {
    buildMorton(mesh);
  } else {
    buildSah(mesh);
  }
  stats_.buildSahCost = stats_.sahCost;
  finishStats();
  stats_.buildMs = millisecondsSince(start);
}

void BvhAccel::buildSah(const TriangleMesh& mesh) {
  const std::size_t n = mesh.triangleCount();
  // One primitive per non-degenerate triangle: degenerate ones can never be hit and would only
  // cost tests. They are marked by an empty box, then left out.
  // The same pass gathers the bounds of the primitives' centroids, which the builder would
  // otherwise gather in a pass of its own.
  // The bounds in SSE registers, and each primitive written as its two 16-byte halves: Box3f
  // accumulators and BvhPrim::make took a round trip through scalar floats per triangle.
  struct SahSummary : LeafSummary {
    SseBox centroids;
    void merge(const SahSummary& o) {
      LeafSummary::merge(o);
      centroids.extend(o.centroids);
    }
  };
  prims_.resize(n);
  const __m128 xyz = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
  const SahSummary summary =
      reduceTriangles<SahSummary>(n, 1024, [&](std::size_t i, SahSummary& acc) {
        const TriangleVertices t = verticesOf(mesh, i);
        __m128 a, b, c;
        loadVertices(t, a, b, c);
        if (degenerate(t, a, b, c)) {
          prims_[i] = BvhPrim::make(Box3f{}, static_cast<std::uint32_t>(i));
          ++acc.degenerate;
          return;
        }
        const SseBox box = triangleBox(a, b, c);
        // Lane 3: the id in the lower corner, zero in the upper one (BvhPrim's layout).
        const __m128 id = _mm_castsi128_ps(_mm_set_epi32(static_cast<int>(i), 0, 0, 0));
        _mm_store_ps(prims_[i].lower, _mm_or_ps(_mm_and_ps(box.lower, xyz), id));
        _mm_store_ps(prims_[i].upper, _mm_and_ps(box.upper, xyz));
        acc.bounds.extend(box);
        const __m128 centroid = _mm_add_ps(box.lower, box.upper);
        acc.centroids.extend(centroid, centroid);
      });
  if (summary.degenerate != 0) {
    std::erase_if(prims_, [](const BvhPrim& p) { return p.lower[0] > p.upper[0]; });
  }

  BvhBuildOptions options;
  static_assert(BvhBuildOptions{}.maxLeafSize <= kMaxLeafRowsTriangles,
                "a leaf's triangles must fit one four-wide test");
  options.traversalCost = static_cast<float>(kTraversalCost);
  options.intersectionCost = static_cast<float>(kIntersectionCost);
  // Subtrees below 4096 triangles (the default) took up to a millisecond each on one thread,
  // and the last of them kept the other thread idle at the end of the flattened kitchen's
  // build; from 2048 on the two threads finish closer together (the tree does not change).
  options.parallelThreshold = kParallelBuildRange;
  BvhBuildResult result;
  result.nodes.swap(nodes_);  // reuse the node memory of the previous build
  const BvhPrimBounds primBounds{summary.bounds.box(), summary.centroids.box()};
  // Decided here, on the calling thread, not on whichever thread runs the copy.
  const bool makeWide = TG_BVH8_WALK && activeSimdIsa() != SimdIsa::Portable;
  // The eight-wide collapse's programme is solved as the builder finishes each node, on its
  // thread and while the node is in its cache; only its nodes are appended after the build.
  // As a pass of its own after the build, the programme's tasks read nodes that either thread
  // had built: the flattened BART kitchen's took 2.7-3.1 ms on two threads against 3.0-3.1 on
  // one, and its share of the build grew by 1.3 ms instead. Static build from its camera, two
  // threads, four alternating process pairs: 16.3-17.2 -> 16.1-16.2 ms (Embree MEDIUM
  // 13.1-13.7 ms).
  Bvh8CollapsePlan plan;
  if (makeWide) plan.reset(prims_.size());
  buildBvh4(prims_, options, result, &primBounds, makeWide ? &plan : nullptr);
  nodes_.swap(result.nodes);
  // The builder reserves its worst case, one node per primitive; SAH trees with leaves of up to
  // four triangles use about a quarter of it (the BART kitchen flattened: 26.5k nodes for 110k
  // triangles). A static or rigid tree is built once and kept: it gives the rest back, for one
  // copy of the nodes it uses, made in parallel blocks (on one thread, the copy and the first
  // touch of its pages took 0.45 ms of the flattened kitchen's 15 ms two-thread build).
  if (nodes_.capacity() > nodes_.size() + nodes_.size() / 4) {
    Bvh4NodeArray trimmed(nodes_.size());
    forEachBlock(nodes_.size(), 2048, [&](std::size_t begin, std::size_t end) {
      std::copy(nodes_.begin() + static_cast<std::ptrdiff_t>(begin),
                nodes_.begin() + static_cast<std::ptrdiff_t>(end),
                trimmed.begin() + static_cast<std::ptrdiff_t>(begin));
    });
    nodes_.swap(trimmed);
  }

  // The leaf rows and the eight-wide copy only read the tree, so they are made side by side:
  // made after the rows, the twins' serial collapse kept one thread busy while the other
  // waited (the flattened BART kitchen on two threads: 2.1 ms of a 17 ms build, after 1.5 ms
  // of rows; 1.066 instead of 1.097 of Embree MEDIUM's time, medians of six alternating
  // processes). The smallest-cost collapse that replaced them appends its nodes serially here
  // (about 1.6 ms on two threads for that kitchen, beside about 2 ms of rows). The trim
  // stays before them: with the large node array still held, the rows and the copy went to fresh
  // pages, whose first touch cost about 12 us each on the same virtual machine (on one thread, in
  // most processes: 77-115 ms per build instead of 30, with about 4,000 more page faults each).
  const std::size_t refs = prims_.size();
  primIds_.resize(refs);
  tbb::parallel_invoke(
      [&] {
        if (makeWide) buildBvh8(nodes_, plan, wide_, &wideEntries_);
      },
      [&] {
        forEachIndex(refs, 4096, [&](std::size_t k) { primIds_[k] = prims_[k].id; });
        writeLeafRowsOfTree(mesh);
      });
  // A static tree is never refitted: keep neither the topology nor the build scratch.
  std::vector<std::uint32_t>().swap(indices_);
  BvhPrimArray().swap(prims_);
  bounds_ = summary.bounds.box();
  stats_.degenerate = summary.degenerate;
  stats_.leaves = result.leaves;
  stats_.maxDepth = result.maxDepth;
  stats_.primReferences = refs;
  stats_.sahCost = nodes_.empty() ? 0.0 : result.sahCost;
}

void BvhAccel::writeLeafRowsOfTree(const TriangleMesh& mesh) {
  const std::size_t n = primIds_.size();
  decltype(triangles_)().swap(triangles_);
  leafRows_.resize(9 * n + kLeafRowPadding);
  leafLanes_.resize(n);
  // The padding is read (by lanes that are masked off) and must be initialised for that.
  std::fill(leafRows_.end() - static_cast<std::ptrdiff_t>(kLeafRowPadding), leafRows_.end(), 0.0f);
  forEachIndex(nodes_.size(), 1024, [&](std::size_t i) {
    const Bvh4Node& node = nodes_[i];
    for (int s = 0; s < 4; ++s) {
      const std::uint32_t first = node.child[s], count = node.count[s];
      if (count == 0) continue;
      TriangleVertices leaf[kMaxLeafRowsTriangles];
      for (std::uint32_t k = 0; k < count; ++k) {
        leaf[k] = verticesOf(mesh, primIds_[first + k]);
        leafLanes_[first + k] = static_cast<std::uint8_t>(k | count << 4);
      }
      writeLeafRows(leaf, count, &leafRows_[9 * first]);
    }
  });
}

void BvhAccel::buildMorton(const TriangleMesh& mesh) {
  const std::size_t n = mesh.triangleCount();
  // Every triangle takes part, degenerate ones included (see BvhAccel). The builder needs only
  // the box centres (as lower + upper) to sort; boxes come with the nodes.
  centroids_.resize(n);
  const MortonCentroidBounds centroidBounds =
      reduceTriangles<MortonCentroidBounds>(n, 4096, [&](std::size_t i, MortonCentroidBounds& acc) {
        const TriangleVertices t = verticesOf(mesh, i);
        centroids_[i] = min(min(t.v0, t.v1), t.v2) + max(max(t.v0, t.v1), t.v2);
        acc.add(centroids_[i]);
      });
  rank_.resize(n);
  morton_.sort(centroids_, primIds_, &centroidBounds, rank_.data());
  // Triangles go to their leaf positions by a scatter in mesh order rather than a gather in
  // leaf order: the mesh is then read front to back, and the random accesses are stores, which
  // do not wait for memory the way dependent loads (index, then vertices) do. The same pass
  // keeps the indices for the refit check.
  triangles_.resize(n);
  indices_.resize(mesh.indices.size());
  forEachIndex(n, 4096, [&](std::size_t i) {
    const std::uint32_t* idx = mesh.indices.data() + 3 * i;
    indices_[3 * i] = idx[0];
    indices_[3 * i + 1] = idx[1];
    indices_[3 * i + 2] = idx[2];
    triangles_[rank_[i]] = {mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]};
  });
  for (std::size_t k = 3 * n; k < mesh.indices.size(); ++k) indices_[k] = mesh.indices[k];
  BvhMortonOptions options;
  // Two triangles per leaf at most: Morton leaves are looser than SAH leaves, and bigger ones
  // cost more triangle tests than the node tests they save (BART robots and kitchen).
  options.maxLeafSize = 2;
  options.traversalCost = kTraversalCost;
  options.intersectionCost = kIntersectionCost;
  BvhBuildResult result;
  result.nodes.swap(nodes_);  // reuse the node memory of the previous build
  LeafSummary summary;
  morton_.emit(
      options,
      [&](std::uint32_t first, std::uint32_t count, LeafSummary& acc) {
        return leafBoxSse(triangles_.data(), first, count, acc.degenerate, acc.bounds).box();
      },
      result, summary);
  nodes_.swap(result.nodes);
  bounds_ = summary.bounds.box();
  stats_.degenerate = summary.degenerate;
  stats_.sahCost = nodes_.empty() ? 0.0 : result.sahCost;
  stats_.leaves = result.leaves;
  stats_.maxDepth = result.maxDepth;
  stats_.primReferences = n;
}

bool BvhAccel::refit(const TriangleMesh& mesh) {
  if (kind_ != AccelKind::BvhFast || mesh.indices != indices_) return false;
  const auto start = std::chrono::steady_clock::now();
  refitFromMesh(mesh);
  stats_.refitted = true;
  stats_.buildMs = millisecondsSince(start);
  return true;
}

void BvhAccel::refitFromMesh(const TriangleMesh& mesh) {
  // The vertices go to their leaf positions as in a build (a scatter in mesh order, see
  // buildMorton), then one pass down the tree and back: each leaf returns the box of its
  // triangles, each node its children's union on the way up.
  const std::size_t n = primIds_.size();
  forEachIndex(n, 4096, [&](std::size_t i) { triangles_[rank_[i]] = verticesOf(mesh, i); });
  const auto leaf = [&](std::uint32_t first, std::uint32_t count, LeafSummary& acc) {
    return leafBoxSse(triangles_.data(), first, count, acc.degenerate, acc.bounds);
  };
  LeafSummary summary;
  Bvh4SahSum sum;
  const Box3f root =
      nodes_.empty() ? Box3f{}
                     : refitBvh4(nodes_, 0, leaf, kTraversalCost, kIntersectionCost,
                                 n < kParallelTriangles ? 0 : kParallelRefitLevels, sum, summary)
                           .box();
  stats_.sahCost = nodes_.empty() ? 0.0 : sum.finish(root, kTraversalCost);
  bounds_ = summary.bounds.box();
  stats_.degenerate = summary.degenerate;
}

void BvhAccel::finishStats() {
  stats_.refitted = false;
  stats_.nodes = nodes_.size() + stats_.leaves;
  stats_.wideNodes = wide_.size();
  stats_.bytes = nodes_.capacity() * sizeof(Bvh4Node) + wide_.capacity() * sizeof(Bvh8Node) +
                 wideEntries_.capacity() * sizeof(Bvh8Entry) +
                 triangles_.capacity() * sizeof(TriangleVertices) +
                 leafRows_.capacity() * sizeof(float) + leafLanes_.capacity() +
                 primIds_.capacity() * sizeof(std::uint32_t) +
                 indices_.capacity() * sizeof(std::uint32_t) + prims_.capacity() * sizeof(BvhPrim) +
                 centroids_.capacity() * sizeof(Vec3f) + rank_.capacity() * sizeof(std::uint32_t) +
                 morton_.scratchBytes();
}

TriangleVertices BvhAccel::vertices(std::uint32_t k) const {
  if (!hasLeafRows()) return triangles_[k];
  const std::uint32_t lane = leafLanes_[k] & 15u, count = leafLanes_[k] >> 4u;
  return readLeafRows(&leafRows_[9 * (k - lane)], count, lane);
}

TriangleFloats BvhAccel::leafTriangles(std::uint32_t first, std::uint32_t count,
                                       std::uint32_t from) const {
  static_assert(sizeof(TriangleVertices) == 9 * sizeof(float), "vertices must be packed floats");
  if (!hasLeafRows()) return {&triangles_[from].v0.x, 1, 9};
  return {&leafRows_[9 * first + (from - first)], count, 1};
}

bool BvhAccel::intersectTriangle(ObjectRay& ray, Hit& hit, std::uint32_t k) const {
  return recordTriangleHit(ray, vertices(k), primIds_[k], hit);
}

bool BvhAccel::occludedTriangle(const ObjectRay& ray, std::uint32_t k) const {
  return hitsTriangleWith(ray, RayAxes(ray.wt), vertices(k));
}

bool BvhAccel::occludedByPrimitive(const ObjectRay& ray, std::uint32_t primitive) const {
  return primitive < primIds_.size() && occludedTriangle(ray, primitive);
}

bool BvhAccel::intersectLeaf(ObjectRay& ray, Hit& hit, std::uint32_t first, std::uint32_t count,
                             TraversalContext& ctx) const {
  ctx.triangleTests += count;
#if TG_BVH4_SSE
  if (hasLeafRows()) {
    return withFixedAxes(ray.wt, [&](const auto& axes) {
      bool found = false;
      forEachLeafRowsHit(ray.wt, axes, &leafRows_[9 * first], count, ray.tfar,
                         [&](unsigned lane, const TriangleHit& th) {
                           found |= recordHit(ray, th, primIds_[first + lane], hit);
                           return false;
                         });
      return found;
    });
  }
#endif
  // One loop per axis permutation: the vertex components the test needs are then read
  // directly rather than selected at run time (4-6% faster single rays, BART kitchen and
  // robots, both cameras, primary and shadow).
  return withFixedAxes(ray.wt, [&](const auto& axes) {
    bool found = false;
    for (std::uint32_t k = first; k < first + count; ++k)
      found |= recordTriangleHitWith(ray, axes, vertices(k), primIds_[k], hit);
    return found;
  });
}

bool BvhAccel::occludedLeaf(const ObjectRay& ray, std::uint32_t first, std::uint32_t count,
                            TraversalContext& ctx) const {
#if TG_BVH4_SSE
  if (hasLeafRows()) {
    return withFixedAxes(ray.wt, [&](const auto& axes) {
      const int lane = forEachLeafRowsHit(ray.wt, axes, &leafRows_[9 * first], count, ray.tfar,
                                          [](unsigned, const TriangleHit&) { return true; });
      if (lane >= 0) {
        // Counted as the scalar loop counts: the triangles up to the blocking one.
        ctx.triangleTests += static_cast<std::uint32_t>(lane) + 1;
        ctx.occludingPrimitive = first + static_cast<std::uint32_t>(lane);
        return true;
      }
      ctx.triangleTests += count;
      return false;
    });
  }
#endif
  return withFixedAxes(ray.wt, [&](const auto& axes) {
    for (std::uint32_t k = first; k < first + count; ++k) {
      ++ctx.triangleTests;
      if (hitsTriangleWith(ray, axes, vertices(k))) {
        ctx.occludingPrimitive = k;
        return true;
      }
    }
    return false;
  });
}

namespace {

/// The box-test constants of an object ray, from its reciprocal direction.
Bvh4Ray boxRayOf(const ObjectRay& ray) {
  return {ray.wt.origin, ray.wt.direction, ray.inverseDirection, ray.wt.tnear};
}

}  // namespace

bool BvhAccel::intersectSubtree(ObjectRay& ray, Hit& hit, std::uint32_t child,
                                std::uint32_t leafCount, TraversalContext& ctx) const {
  return intersectSubtree(ray, boxRayOf(ray), hit, child, leafCount, ctx);
}

bool BvhAccel::occludedSubtree(const ObjectRay& ray, std::uint32_t child, std::uint32_t leafCount,
                               TraversalContext& ctx) const {
  return occludedSubtree(ray, boxRayOf(ray), child, leafCount, ctx);
}

bool BvhAccel::intersectSubtree(ObjectRay& ray, const Bvh4Ray& boxRay, Hit& hit,
                                std::uint32_t child, std::uint32_t leafCount,
                                TraversalContext& ctx) const {
  return traverseBvh4From<false>(nodes_, child, leafCount, boxRay, ray.tfar, ctx.nodeVisits,
                                 [&](std::uint32_t first, std::uint32_t count) {
                                   return intersectLeaf(ray, hit, first, count, ctx);
                                 });
}

bool BvhAccel::occludedSubtree(const ObjectRay& ray, const Bvh4Ray& boxRay, std::uint32_t child,
                               std::uint32_t leafCount, TraversalContext& ctx) const {
  return traverseBvh4From<true>(nodes_, child, leafCount, boxRay, ray.tfar, ctx.nodeVisits,
                                [&](std::uint32_t first, std::uint32_t count) {
                                  return occludedLeaf(ray, first, count, ctx);
                                });
}

bool BvhAccel::intersectWhole(ObjectRay& ray, const Bvh4Ray& boxRay, Hit& hit,
                              TraversalContext& ctx) const {
#if TG_BVH8_WALK
  if (!wide_.empty())
    return traverseWideBvh8<false>(wide_, boxRay, ray.tfar, ctx.nodeVisits,
                                   [&](std::uint32_t first, std::uint32_t count) {
                                     return intersectLeaf(ray, hit, first, count, ctx);
                                   });
#endif
  return intersectSubtree(ray, boxRay, hit, 0, 0, ctx);
}

std::uint32_t BvhAccel::wideEntryOf(std::uint32_t node) const {
  const auto it =
      std::lower_bound(wideEntries_.begin(), wideEntries_.end(), node,
                       [](const Bvh8Entry& e, std::uint32_t n) { return e.bvh4Node < n; });
  return it != wideEntries_.end() && it->bvh4Node == node ? it->wideNode : kInvalidId;
}

bool BvhAccel::intersectWideSubtree(ObjectRay& ray, const Bvh4Ray& boxRay, Hit& hit,
                                    std::uint32_t wideNode, TraversalContext& ctx) const {
#if TG_BVH8_WALK
  return traverseWideBvh8<false>(
      wide_, boxRay, ray.tfar, ctx.nodeVisits,
      [&](std::uint32_t first, std::uint32_t count) {
        return intersectLeaf(ray, hit, first, count, ctx);
      },
      wideNode);
#else
  (void)ray, (void)boxRay, (void)hit, (void)wideNode, (void)ctx;
  throw std::logic_error("BvhAccel::intersectWideSubtree: no eight-wide walk in this build");
#endif
}

bool BvhAccel::occludedWideSubtree(const ObjectRay& ray, const Bvh4Ray& boxRay,
                                   std::uint32_t wideNode, TraversalContext& ctx) const {
#if TG_BVH8_WALK
  return traverseWideBvh8<true>(
      wide_, boxRay, ray.tfar, ctx.nodeVisits,
      [&](std::uint32_t first, std::uint32_t count) {
        return occludedLeaf(ray, first, count, ctx);
      },
      wideNode);
#else
  (void)ray, (void)boxRay, (void)wideNode, (void)ctx;
  throw std::logic_error("BvhAccel::occludedWideSubtree: no eight-wide walk in this build");
#endif
}

bool BvhAccel::occludedWhole(const ObjectRay& ray, const Bvh4Ray& boxRay,
                             TraversalContext& ctx) const {
#if TG_BVH8_WALK
  if (!wide_.empty())
    return traverseWideBvh8<true>(wide_, boxRay, ray.tfar, ctx.nodeVisits,
                                  [&](std::uint32_t first, std::uint32_t count) {
                                    return occludedLeaf(ray, first, count, ctx);
                                  });
#endif
  return occludedSubtree(ray, boxRay, 0, 0, ctx);
}

bool BvhAccel::intersect(ObjectRay& ray, Hit& hit, TraversalContext& ctx) const {
  return intersectWhole(ray, boxRayOf(ray), hit, ctx);
}

bool BvhAccel::occluded(const ObjectRay& ray, TraversalContext& ctx) const {
  return occludedWhole(ray, boxRayOf(ray), ctx);
}

int BvhAccel::subtreeChildren(const BvhSubtree& t, BvhSubtree out[4]) const {
  if (t.count != 0 || t.child >= nodes_.size()) return 0;
  const Bvh4Node& node = nodes_[t.child];
  int n = 0;
  for (int s = 0; s < 4; ++s)
    if (node.child[s] != kInvalidId) out[n++] = {node.slotBounds(s), node.child[s], node.count[s]};
  return n;
}

namespace {

/// What the packet leaf callbacks of both queries need; passed through the kernel as `user`.
/// Lanes in `rays->filtered` go through the SIMD triangle test (`rays->triangles`); the others
/// are tested lane by lane.
struct PacketLeafContext {
  const BvhAccel* accel;
  TraversalContext* ctx;
  BvhPacketRays* rays;
  /// The kernels of the walk, looked up once rather than per leaf.
  const PacketKernels* kernels;
  /// The packet's rays; the closest-hit callbacks lower the lanes' tfar in it.
  ObjectRayPacket* packet;

  /// Lane `l`'s whole object ray (BvhAccel::packetLane).
  ObjectRay& lane(unsigned l) const { return BvhAccel::packetLane(*packet, *rays, l); }
};

/// The closest-hit callbacks' context.
struct ClosestLeafContext : PacketLeafContext {
  Hit* hits;
  unsigned changed = 0;
};

/// The any-hit callbacks' context.
using OccludedLeafContext = PacketLeafContext;

/// Tests the leaf's triangles against the lanes in `lanes`, in triangle order per lane as the
/// single-ray leaf test meets them: the SIMD test gives found(lane, k, hit) its hits, and the
/// lanes it cannot decide (an edge function exactly zero) and those outside the SIMD layout go
/// through scalar(lane, k). Both return true to retire the lane from the rest of the leaf
/// (any-hit). `tfar` holds the lanes' current tfar, which found() and scalar() keep up to date.
template <class Found, class Scalar>
void forEachTriangle(const PacketLeafContext& c, std::uint32_t first, std::uint32_t count,
                     unsigned lanes, const float* tfar, bool anyHit, const Found& found,
                     const Scalar& scalar) {
  const unsigned simd = lanes & c.rays->filtered;
  if (simd != 0) {
    c.ctx->triangleTests += static_cast<std::uint64_t>(laneCount(simd)) * count;
    unsigned live = simd;
    PacketTriangleHits out;
    for (std::uint32_t base = first; base < first + count && live != 0;) {
      const std::uint32_t n = std::min(kTriangleBatch, first + count - base);
      const std::uint32_t done =
          c.kernels->testTriangles(c.accel->leafTriangles(first, count, base), n, c.rays->triangles,
                                   tfar, live, anyHit, out);
      for (std::uint32_t i = 0; i < done; ++i) {
        for (unsigned m = out.hit[i] & live; m != 0; m &= m - 1) {
          const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
          const TriangleHit th{out.t[i][l], out.u[i][l], out.v[i][l],
                               Vec3d(out.normal[i][0], out.normal[i][1], out.normal[i][2])};
          if (found(l, base + i, th)) live &= ~(1u << l);
        }
        for (unsigned m = out.exact[i] & live; m != 0; m &= m - 1) {
          const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
          if (scalar(l, base + i)) live &= ~(1u << l);
        }
      }
      base += done;
    }
  }
  for (unsigned rest = lanes & ~simd; rest != 0; rest &= rest - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(rest));
    c.ctx->triangleTests += count;
    for (std::uint32_t k = first; k < first + count; ++k)
      if (scalar(l, k)) break;
  }
}

unsigned intersectPacketLeaf(void* user, std::uint32_t first, std::uint32_t count, unsigned lanes,
                             PacketBoxRays& rays) {
  auto& c = *static_cast<ClosestLeafContext*>(user);
  // A recorded hit lowers the lane's tfar for the walk too. Closest-hit lanes never retire.
  const auto recorded = [&](unsigned l) {
    rays.tfar[l] = c.packet->rays[l].tfar;
    c.changed |= 1u << l;
  };
  forEachTriangle(
      c, first, count, lanes, rays.tfar, false,
      [&](unsigned l, std::uint32_t k, const TriangleHit& th) {
        if (recordHit(c.packet->rays[l], th, c.accel->primId(k), c.hits[l])) recorded(l);
        return false;
      },
      [&](unsigned l, std::uint32_t k) {
        if (c.accel->intersectTriangle(c.lane(l), c.hits[l], k)) recorded(l);
        return false;
      });
  return 0;
}

unsigned occludedPacketLeaf(void* user, std::uint32_t first, std::uint32_t count, unsigned lanes,
                            PacketBoxRays& rays) {
  const auto& c = *static_cast<const OccludedLeafContext*>(user);
  unsigned blocked = 0;
  forEachTriangle(
      c, first, count, lanes, rays.tfar, true,
      [&](unsigned l, std::uint32_t k, const TriangleHit&) {
        blocked |= 1u << l;
        c.ctx->occludingPrimitive = k;
        return true;
      },
      [&](unsigned l, std::uint32_t k) {
        if (!c.accel->occludedTriangle(c.lane(l), k)) return false;
        blocked |= 1u << l;
        c.ctx->occludingPrimitive = k;
        return true;
      });
  return blocked;
}

unsigned intersectSingleLane(void* user, std::uint32_t child, unsigned lane, PacketBoxRays& rays) {
  auto& c = *static_cast<ClosestLeafContext*>(user);
  if (c.accel->intersectSubtree(c.lane(lane), c.hits[lane], child, 0, *c.ctx)) {
    rays.tfar[lane] = c.packet->rays[lane].tfar;
    c.changed |= 1u << lane;
  }
  return 0;
}

unsigned occludedSingleLane(void* user, std::uint32_t child, unsigned lane, PacketBoxRays&) {
  const auto& c = *static_cast<const OccludedLeafContext*>(user);
  return c.accel->occludedSubtree(c.lane(lane), child, 0, *c.ctx) ? 1u : 0u;
}

}  // namespace

namespace {

/// Lane `l` of the SIMD triangle test's rays.
void setTriangleLane(PacketTriangleRays& tri, unsigned l, const WatertightRay& r) {
  for (int a = 0; a < 3; ++a) {
    tri.origin[a][l] = r.origin[a];
    tri.originD[a][l] = r.originD[a];
    tri.directionD[a][l] = r.directionD[a];
  }
  tri.sx[l] = r.sx;
  tri.sy[l] = r.sy;
  tri.tnear[l] = r.tnear;
}

/// The triangle-test part of BvhAccel::loadPacket for its lanes `coherent` (first lane included):
/// the ones with the first lane's axis permutation share the SIMD triangle test's layout.
void loadPacketTriangles(const ObjectRayPacket& packet, unsigned coherent, BvhPacketRays& out) {
  const WatertightRay& lead = packet.rays[__builtin_ctz(coherent)].wt;
  PacketTriangleRays& tri = out.triangles;
  unsigned filtered = 0;
  tri.kx = lead.kx;
  tri.ky = lead.ky;
  tri.kz = lead.kz;
  for (unsigned m = coherent; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    const WatertightRay& r = packet.rays[l].wt;
    if (r.kx == lead.kx && r.ky == lead.ky && r.kz == lead.kz) {
      setTriangleLane(tri, l, r);
      filtered |= 1u << l;
    }
  }
  // Lanes outside the SIMD test still go through its full-width arithmetic: give them numbers.
  for (unsigned l = 0; l < kPacketLanes; ++l)
    if ((filtered & (1u << l)) == 0) setTriangleLane(tri, l, lead);
  out.coherent = coherent;
  out.filtered = filtered;
}

}  // namespace

void BvhAccel::loadPacket(const ObjectRayPacket& packet, unsigned lanes, BvhPacketRays& out) {
  // Only the lanes whose direction signs match the first lane's share the box rows.
  const unsigned first = static_cast<unsigned>(__builtin_ctz(lanes));
  const unsigned signs = directionSigns(packet.rays[first].wt.direction);
  PacketBoxRays& box = out.box;
  unsigned coherent = 0;
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    const ObjectRay& r = packet.rays[l];
    if (directionSigns(r.wt.direction) != signs) continue;
    setPacketLaneWithReciprocal(box, l, r.wt.origin, r.wt.direction, r.inverseDirection, r.wt.tnear,
                                r.tfar);
    coherent |= 1u << l;
  }
  box.signs = signs;
  fillUnusedLanes(box, coherent, first);
  loadPacketTriangles(packet, coherent, out);
  out.kernels = &activePacketKernels();
  out.unmappedLanes = 0;
}

void BvhAccel::loadIdentityPacket(const PacketBoxRays& world, unsigned lanes, unsigned filtered,
                                  const PacketKernels& kernels, BvhPacketRays& out) {
  // An identity instance's object rays are the world rays (origin, tnear, and reciprocals that
  // are correctly rounded quotients either way, +inf for zeros in the box rows), so every lane
  // has the world signs and the box rows are the world's.
  out.box = world;
  out.coherent = lanes;
  out.filtered = filtered;
  out.kernels = &kernels;
}

ObjectRay& BvhAccel::packetLane(ObjectRayPacket& packet, BvhPacketRays& rays, unsigned l) {
  if (rays.unmappedLanes & (1u << l)) {
    ObjectRay& lane = packet.rays[l];
    // The ids are the instance's being entered: identity instances share one mapped packet.
    const std::uint32_t instanceId = lane.instanceId, objectId = lane.objectId;
    lane = objectRayFor(*rays.instance, rays.worldRays[l], lane.tfar);
    lane.instanceId = instanceId;
    lane.objectId = objectId;
    rays.unmappedLanes &= ~(1u << l);
  }
  return packet.rays[l];
}

unsigned BvhAccel::intersectLoadedPacket(ObjectRayPacket& packet, BvhPacketRays& rays,
                                         unsigned lanes, Hit* hits, TraversalContext& ctx,
                                         const BvhSubtree& root) const {
  if (lanes == 0 || nodes_.empty()) return 0;
  ClosestLeafContext c{{this, &ctx, &rays, rays.kernels, &packet}, hits};
  if (laneCount(lanes) < kMinPacketLanes) {
    unsigned changed = 0;
    for (unsigned m = lanes; m != 0; m &= m - 1) {
      const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
      if (intersectSubtree(c.lane(l), hits[l], root.child, root.count, ctx)) changed |= 1u << l;
    }
    return changed;
  }
  c.kernels->traverse(nodes_.data(), root.child, root.count, rays.box, lanes, false,
                      &intersectPacketLeaf, &intersectSingleLane, &c, ctx.nodeVisits);
  return c.changed;
}

namespace {

/// The halves' closest-hit contexts of a pair walk, passed through the kernel as `user`.
struct ClosestPairContext {
  ClosestLeafContext half[2];
  /// Whether the halves' triangle rows share their axis permutation, so that leaves both test
  /// with SIMD go through the pair triangle test.
  bool sharedPermutation = false;
  /// Whether `rows` holds both halves' triangle rows (made at the first leaf that needs them).
  bool rowsReady = false;
  PairTriangleRays rows;
};

/// Both halves' triangle rows as one pair's (half h in lanes 8h to 8h + 7).
void loadPairRows(const PacketTriangleRays& low, const PacketTriangleRays& high,
                  PairTriangleRays& out) {
  const auto both = [](const auto& a, const auto& b, auto& to) {
    std::memcpy(to, a, sizeof(a));
    std::memcpy(to + kPacketLanes, b, sizeof(b));
  };
  for (int a = 0; a < 3; ++a) {
    both(low.origin[a], high.origin[a], out.origin[a]);
    both(low.originD[a], high.originD[a], out.originD[a]);
    both(low.directionD[a], high.directionD[a], out.directionD[a]);
  }
  both(low.sx, high.sx, out.sx);
  both(low.sy, high.sy, out.sy);
  both(low.tnear, high.tnear, out.tnear);
  out.kx = low.kx;
  out.ky = low.ky;
  out.kz = low.kz;
}

/// Records a hit of pair lane `lane` on triangle k (from the SIMD test when `th` is given, else
/// by the scalar test), lowering its half's tfar, as intersectPacketLeaf records hits.
void recordPairLane(ClosestPairContext& c, PacketBoxRays* const (&rays)[2], unsigned lane,
                    std::uint32_t k, const TriangleHit* th) {
  const unsigned h = lane / kPacketLanes, l = lane % kPacketLanes;
  ClosestLeafContext& half = c.half[h];
  const bool found = th != nullptr
                         ? recordHit(half.packet->rays[l], *th, half.accel->primId(k), half.hits[l])
                         : half.accel->intersectTriangle(half.lane(l), half.hits[l], k);
  if (found) {
    rays[h]->tfar[l] = half.packet->rays[l].tfar;
    half.changed |= 1u << l;
  }
}

void intersectPairLeaf(void* user, std::uint32_t first, std::uint32_t count, unsigned lanes,
                       PacketBoxRays* const (&rays)[2]) {
  auto& c = *static_cast<ClosestPairContext*>(user);
  const unsigned halfLanes[2] = {lanes & kAllLanes, lanes >> kPacketLanes};
  const unsigned simd[2] = {halfLanes[0] & c.half[0].rays->filtered,
                            halfLanes[1] & c.half[1].rays->filtered};
  if (simd[0] == 0 || simd[1] == 0 || !c.sharedPermutation) {
    for (unsigned h = 0; h < 2; ++h)
      if (halfLanes[h] != 0) intersectPacketLeaf(&c.half[h], first, count, halfLanes[h], *rays[h]);
    return;
  }
  // Both halves test the leaf with SIMD: one test of sixteen lanes, the triangle's plane made
  // once, instead of one per half.
  if (!c.rowsReady) {
    loadPairRows(c.half[0].rays->triangles, c.half[1].rays->triangles, c.rows);
    c.rowsReady = true;
  }
  const BvhAccel& accel = *c.half[0].accel;
  c.half[0].ctx->triangleTests +=
      static_cast<std::uint64_t>(laneCount(simd[0]) + laneCount(simd[1])) * count;
  const unsigned live = simd[0] | (simd[1] << kPacketLanes);
  PairTriangleHits out;
  for (std::uint32_t base = first; base < first + count;) {
    const std::uint32_t n = std::min(kTriangleBatch, first + count - base);
    alignas(64) float tfar[kPairLanes];
    std::memcpy(tfar, rays[0]->tfar, sizeof(rays[0]->tfar));
    std::memcpy(tfar + kPacketLanes, rays[1]->tfar, sizeof(rays[1]->tfar));
    const std::uint32_t done = c.half[0].kernels->testTrianglesPair(
        accel.leafTriangles(first, count, base), n, c.rows, tfar, live, out);
    for (std::uint32_t i = 0; i < done; ++i) {
      for (unsigned m = out.hit[i]; m != 0; m &= m - 1) {
        const unsigned lane = static_cast<unsigned>(__builtin_ctz(m));
        const TriangleHit th{out.t[i][lane], out.u[i][lane], out.v[i][lane],
                             Vec3d(out.normal[i][0], out.normal[i][1], out.normal[i][2])};
        recordPairLane(c, rays, lane, base + i, &th);
      }
      for (unsigned m = out.exact[i]; m != 0; m &= m - 1)
        recordPairLane(c, rays, static_cast<unsigned>(__builtin_ctz(m)), base + i, nullptr);
    }
    base += done;
  }
  // Lanes outside the SIMD layout, lane by lane.
  for (unsigned h = 0; h < 2; ++h)
    for (unsigned rest = halfLanes[h] & ~simd[h]; rest != 0; rest &= rest - 1) {
      const unsigned lane = kPacketLanes * h + static_cast<unsigned>(__builtin_ctz(rest));
      c.half[0].ctx->triangleTests += count;
      for (std::uint32_t k = first; k < first + count; ++k)
        recordPairLane(c, rays, lane, k, nullptr);
    }
}

void intersectPairSingleLane(void* user, std::uint32_t child, unsigned lane,
                             PacketBoxRays* const (&rays)[2]) {
  auto& c = *static_cast<ClosestPairContext*>(user);
  const unsigned h = lane / kPacketLanes;
  intersectSingleLane(&c.half[h], child, lane % kPacketLanes, *rays[h]);
}

}  // namespace

namespace {

/// The halves' any-hit contexts of a pair walk, passed through the kernel as `user`.
struct OccludedPairContext {
  OccludedLeafContext half[2];
};

unsigned occludedPairLeaf(void* user, std::uint32_t first, std::uint32_t count, unsigned lanes,
                          PacketBoxRays* const (&rays)[2]) {
  auto& c = *static_cast<OccludedPairContext*>(user);
  unsigned blocked = 0;
  for (unsigned h = 0; h < 2; ++h) {
    const unsigned half = (lanes >> (kPacketLanes * h)) & kAllLanes;
    if (half != 0)
      blocked |= occludedPacketLeaf(&c.half[h], first, count, half, *rays[h]) << (kPacketLanes * h);
  }
  return blocked;
}

unsigned occludedPairSingleLane(void* user, std::uint32_t child, unsigned lane,
                                PacketBoxRays* const (&rays)[2]) {
  auto& c = *static_cast<OccludedPairContext*>(user);
  const unsigned h = lane / kPacketLanes;
  return occludedSingleLane(&c.half[h], child, lane % kPacketLanes, *rays[h]);
}

/// Whether two halves walk as one pair: the kernels have a pair walk, both halves have lanes,
/// enough of them for the shared walk to pay, and the same direction signs.
bool pairable(const BvhAccel::LoadedHalf (&halves)[2], bool anyHit) {
  const PacketKernels& kernels = *halves[0].rays->kernels;
  return (anyHit ? kernels.occludedPair != nullptr : kernels.traversePair != nullptr) &&
         halves[0].lanes != 0 && halves[1].lanes != 0 &&
         laneCount(halves[0].lanes) + laneCount(halves[1].lanes) >=
             static_cast<int>(kPacketLanes) &&
         halves[0].rays->box.signs == halves[1].rays->box.signs;
}

}  // namespace

void BvhAccel::intersectLoadedPair(const LoadedHalf (&halves)[2], TraversalContext& ctx,
                                   const BvhSubtree& root, unsigned (&changed)[2]) const {
  const PacketKernels* kernels = halves[0].rays->kernels;
  const bool paired = !nodes_.empty() && pairable(halves, false);
  if (!paired) {
    for (unsigned h = 0; h < 2; ++h)
      changed[h] = intersectLoadedPacket(*halves[h].packet, *halves[h].rays, halves[h].lanes,
                                         halves[h].hits, ctx, root);
    return;
  }
  ClosestPairContext c;
  for (unsigned h = 0; h < 2; ++h)
    c.half[h] =
        ClosestLeafContext{{this, &ctx, halves[h].rays, kernels, halves[h].packet}, halves[h].hits};
  const PacketTriangleRays& low = halves[0].rays->triangles;
  const PacketTriangleRays& high = halves[1].rays->triangles;
  c.sharedPermutation = kernels->testTrianglesPair != nullptr && low.kx == high.kx &&
                        low.ky == high.ky && low.kz == high.kz;
  PacketBoxRays* const box[2] = {&halves[0].rays->box, &halves[1].rays->box};
  kernels->traversePair(nodes_.data(), root.child, root.count, box,
                        halves[0].lanes | (halves[1].lanes << kPacketLanes), &intersectPairLeaf,
                        &intersectPairSingleLane, &c, ctx.nodeVisits);
  changed[0] = c.half[0].changed;
  changed[1] = c.half[1].changed;
}

void BvhAccel::occludedLoadedPair(const LoadedHalf (&halves)[2], TraversalContext& ctx,
                                  const BvhSubtree& root, unsigned (&blocked)[2]) const {
  if (nodes_.empty() || !pairable(halves, true)) {
    for (unsigned h = 0; h < 2; ++h)
      blocked[h] =
          occludedLoadedPacket(*halves[h].packet, *halves[h].rays, halves[h].lanes, ctx, root);
    return;
  }
  const PacketKernels* kernels = halves[0].rays->kernels;
  OccludedPairContext c;
  for (unsigned h = 0; h < 2; ++h)
    c.half[h] = OccludedLeafContext{this, &ctx, halves[h].rays, kernels, halves[h].packet};
  PacketBoxRays* const box[2] = {&halves[0].rays->box, &halves[1].rays->box};
  const unsigned found =
      kernels->occludedPair(nodes_.data(), root.child, root.count, box,
                            halves[0].lanes | (halves[1].lanes << kPacketLanes), &occludedPairLeaf,
                            &occludedPairSingleLane, &c, ctx.nodeVisits);
  blocked[0] = found & kAllLanes;
  blocked[1] = found >> kPacketLanes;
}

unsigned BvhAccel::occludedLoadedPacket(ObjectRayPacket& packet, BvhPacketRays& rays,
                                        unsigned lanes, TraversalContext& ctx,
                                        const BvhSubtree& root) const {
  if (lanes == 0 || nodes_.empty()) return 0;
  OccludedLeafContext c{this, &ctx, &rays, rays.kernels, &packet};
  if (laneCount(lanes) < kMinPacketLanes) {
    unsigned blocked = 0;
    for (unsigned m = lanes; m != 0; m &= m - 1) {
      const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
      if (occludedSubtree(c.lane(l), root.child, root.count, ctx)) blocked |= 1u << l;
    }
    return blocked;
  }
  return c.kernels->traverse(nodes_.data(), root.child, root.count, rays.box, lanes, true,
                             &occludedPacketLeaf, &occludedSingleLane, &c, ctx.nodeVisits);
}

unsigned BvhAccel::intersectPacket(ObjectRayPacket& packet, unsigned lanes, Hit* hits,
                                   TraversalContext& ctx) const {
  if (lanes == 0 || nodes_.empty()) return 0;
  BvhPacketRays rays;
  loadPacket(packet, lanes, rays);
  return intersectLoadedPacket(packet, rays, rays.coherent, hits, ctx) |
         ObjectAccel::intersectPacket(packet, lanes & ~rays.coherent, hits, ctx);
}

unsigned BvhAccel::occludedPacket(const ObjectRayPacket& packet, unsigned lanes,
                                  TraversalContext& ctx) const {
  if (lanes == 0 || nodes_.empty()) return 0;
  BvhPacketRays rays;
  loadPacket(packet, lanes, rays);
  // loadPacket leaves no lane unmapped, so the walk never writes the packet.
  return occludedLoadedPacket(const_cast<ObjectRayPacket&>(packet), rays, rays.coherent, ctx) |
         ObjectAccel::occludedPacket(packet, lanes & ~rays.coherent, ctx);
}

}  // namespace tg::detail
