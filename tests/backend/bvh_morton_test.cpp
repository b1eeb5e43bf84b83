// The Morton-code BVH4 builder on its own: tree structure (every primitive in exactly one leaf,
// boxes that enclose, bounded depth), awkward inputs (no primitive, one, all centroids equal,
// empty and point boxes), independence from the thread count, and the bottom-up refit.
#define BOOST_TEST_MODULE bvh_morton
#include <boost/test/unit_test.hpp>

#include <tbb/global_control.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "Bvh4Refit.h"
#include "Bvh4TreeWalk.h"
#include "BvhMortonBuilder.h"
#include "tracegraph/backend/ObjectAccel.h"
#include "tracegraph/backend/TriangleMesh.h"

using namespace tg;
using namespace tg::detail;

namespace {

using TreeCheck = tg::test::Bvh4TreeCheck;

/// The structural walk with the Morton builder's rules (slot boxes enclose their contents).
Box3f walk(const Bvh4NodeArray& nodes, const std::vector<Box3f>& sorted, std::uint32_t maxLeaf,
           std::vector<int>& seen, TreeCheck& c) {
  return tg::test::walkBvh4(nodes, 0, 0, sorted, {maxLeaf, false, tg::test::SlotBoxRule::Enclosing},
                            seen, c);
}

/// Builds over `boxes` and checks the structure; returns the checked result.
BvhBuildResult buildAndCheck(const std::vector<Box3f>& boxes, std::uint32_t maxLeaf,
                             std::vector<std::uint32_t>& order, const std::string& label) {
  BvhMortonOptions options;
  options.maxLeafSize = maxLeaf;
  BvhMortonBuilder builder;
  BvhBuildResult out;
  builder.build(boxes, options, order, out);
  BOOST_TEST_REQUIRE(order.size() == boxes.size(), label);
  // `order` is a permutation of the primitive indices.
  std::vector<int> hit(boxes.size(), 0);
  for (std::uint32_t id : order) {
    BOOST_TEST_REQUIRE(id < boxes.size(), label);
    ++hit[id];
  }
  BOOST_TEST(std::count(hit.begin(), hit.end(), 1) == static_cast<long>(boxes.size()), label);
  if (boxes.empty()) {
    BOOST_TEST(out.nodes.empty(), label);
    BOOST_TEST(out.leaves == 0u, label);
    return out;
  }
  std::vector<Box3f> sorted(boxes.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = boxes[order[k]];
  std::vector<int> seen(boxes.size(), 0);
  TreeCheck c;
  const Box3f root = walk(out.nodes, sorted, maxLeaf, seen, c);
  BOOST_TEST(c.errors == 0u, label << ": " << c.firstError);
  BOOST_TEST(std::count(seen.begin(), seen.end(), 1) == static_cast<long>(boxes.size()),
             label << ": every primitive in exactly one leaf");
  BOOST_TEST(c.nodesVisited == out.nodes.size(), label << ": every node reachable");
  BOOST_TEST(c.leaves == out.leaves, label);
  BOOST_TEST(c.maxDepth == out.maxDepth, label);
  BOOST_TEST(out.maxDepth < static_cast<std::size_t>(kBvh4MaxDepth), label);
  BOOST_TEST((root == out.bounds), label);
  // The cost gathered during the build is the one bvh4SahCost computes (summed in another
  // order, hence the tolerance).
  const double walked = bvh4SahCost(out.nodes, options.traversalCost, options.intersectionCost);
  BOOST_TEST(std::abs(out.sahCost - walked) <= 1e-9 * walked, label);
  return out;
}

std::vector<Box3f> randomBoxes(std::mt19937& rng, std::size_t n, float size) {
  std::uniform_real_distribution<float> pos(-100.0f, 100.0f), ext(0.0f, size);
  std::vector<Box3f> boxes(n);
  for (Box3f& b : boxes) {
    const Vec3f lo{pos(rng), pos(rng), pos(rng)};
    b = {lo, lo + Vec3f{ext(rng), ext(rng), ext(rng)}};
  }
  return boxes;
}

/// Structural equality of two trees walked from their roots (node numbering may differ).
bool sameTree(const Bvh4NodeArray& a, std::uint32_t ia, const Bvh4NodeArray& b, std::uint32_t ib) {
  const Bvh4Node &x = a[ia], &y = b[ib];
  for (int s = 0; s < 4; ++s) {
    if (!(x.slotBounds(s) == y.slotBounds(s)) || x.count[s] != y.count[s]) return false;
    if ((x.child[s] == kInvalidId) != (y.child[s] == kInvalidId)) return false;
    if (x.child[s] == kInvalidId) continue;
    if (x.count[s] != 0) {
      if (x.child[s] != y.child[s]) return false;
    } else if (!sameTree(a, x.child[s], b, y.child[s])) {
      return false;
    }
  }
  return true;
}

}  // namespace

BOOST_AUTO_TEST_CASE(random_boxes_give_valid_trees) {
  std::mt19937 rng(1);
  std::vector<std::uint32_t> order;
  for (std::size_t n : {2u, 3u, 4u, 5u, 17u, 1000u, 50000u}) {
    for (std::uint32_t maxLeaf : {1u, 4u}) {
      const BvhBuildResult r =
          buildAndCheck(randomBoxes(rng, n, 3.0f), maxLeaf, order, "n=" + std::to_string(n));
      // Well spread boxes make a shallow tree: about log4(n) levels, not log2(n).
      BOOST_TEST(r.maxDepth <= 2 * static_cast<std::size_t>(std::log2(double(n)) / 2.0 + 3));
    }
  }
}

BOOST_AUTO_TEST_CASE(no_primitive_and_one_primitive) {
  std::vector<std::uint32_t> order{7, 8, 9};
  buildAndCheck({}, 4, order, "empty");
  const Box3f one{{1, 2, 3}, {4, 5, 6}};
  const BvhBuildResult r = buildAndCheck({one}, 4, order, "single");
  BOOST_TEST_REQUIRE(r.nodes.size() == 1u);
  BOOST_TEST(r.nodes[0].count[0] == 1u);
  BOOST_TEST(r.nodes[0].child[0] == 0u);
  BOOST_TEST((r.nodes[0].slotBounds(0) == one));
  BOOST_TEST(r.leaves == 1u);
  // A builder reused for an empty input forgets the previous tree.
  BvhMortonBuilder builder;
  BvhBuildResult out;
  builder.build(std::vector<Box3f>{one, one}, BvhMortonOptions{}, order, out);
  BOOST_TEST(out.nodes.size() == 1u);
  builder.build(std::vector<Box3f>{}, BvhMortonOptions{}, order, out);
  BOOST_TEST(out.nodes.empty());
  BOOST_TEST(order.empty());
}

BOOST_AUTO_TEST_CASE(identical_centroids_stay_within_the_depth_bound) {
  // 100k equal codes split at the middle: about log4(100000 / 4) levels, far below the bound
  // that sizes the traversal stack.
  std::vector<std::uint32_t> order;
  const std::vector<Box3f> same(100000, Box3f{{1, 1, 1}, {2, 2, 2}});
  const BvhBuildResult r = buildAndCheck(same, 4, order, "identical boxes");
  BOOST_TEST(r.maxDepth <= 10u);
  // Halving never leaves fewer than half of maxLeafSize in a leaf.
  BOOST_TEST(r.leaves <= 50000u);
  // Same centre, different sizes: still one code.
  std::vector<Box3f> nested(100000);
  for (std::size_t i = 0; i < nested.size(); ++i) {
    const float h = 1.0f + static_cast<float>(i % 97);
    nested[i] = {{-h, -h, -h}, {h, h, h}};
  }
  BOOST_TEST(buildAndCheck(nested, 4, order, "nested boxes").maxDepth <= 10u);
}

BOOST_AUTO_TEST_CASE(worst_case_codes_stay_within_the_depth_bound) {
  // Centroids at 2^-k along one axis: every split by code peels off one primitive, the deepest
  // a binary radix tree of 30-bit codes can get, followed by equal codes split at the middle.
  std::vector<Box3f> boxes;
  for (int k = 0; k < 40; ++k) {
    const float x = std::ldexp(1.0f, -k);
    for (int copy = 0; copy < 200; ++copy) boxes.push_back({{x, 0, 0}, {x, 0, 0}});
  }
  std::vector<std::uint32_t> order;
  const BvhBuildResult r = buildAndCheck(boxes, 1, order, "geometric");
  BOOST_TEST(r.maxDepth < static_cast<std::size_t>(kBvh4MaxDepth));
}

BOOST_AUTO_TEST_CASE(empty_point_and_flat_boxes) {
  std::mt19937 rng(2);
  std::vector<Box3f> boxes = randomBoxes(rng, 3000, 2.0f);
  std::uniform_int_distribution<int> kind(0, 4);
  for (Box3f& b : boxes) {
    switch (kind(rng)) {
      case 0:
        b = Box3f{};
        break;  // empty (never widens a node)
      case 1:
        b.upper = b.lower;
        break;  // a point
      case 2:
        b.upper.z = b.lower.z = 5.0f;
        break;  // flat
      default:
        break;
    }
  }
  std::vector<std::uint32_t> order;
  buildAndCheck(boxes, 4, order, "mixed");
  // Only empty boxes: nothing to quantise, still one tree over all of them.
  const BvhBuildResult r = buildAndCheck(std::vector<Box3f>(37, Box3f{}), 4, order, "all empty");
  BOOST_TEST(r.bounds.empty());
  // All in one plane, and all on one line.
  std::vector<Box3f> plane = randomBoxes(rng, 5000, 0.0f), line = plane;
  for (Box3f& b : plane) b.lower.y = b.upper.y = 0.0f;
  for (Box3f& b : line) b.lower.x = b.upper.x = b.lower.y = b.upper.y = 0.0f;
  buildAndCheck(plane, 4, order, "plane");
  buildAndCheck(line, 4, order, "line");
  // Far apart clusters: the codes put each in its own subtree.
  std::vector<Box3f> clusters = randomBoxes(rng, 4000, 1.0f);
  for (std::size_t i = 0; i < clusters.size(); i += 2) {
    clusters[i].lower = clusters[i].lower * 1e-6f + Vec3f{1e6f, 0, 0};
    clusters[i].upper = clusters[i].upper * 1e-6f + Vec3f{1e6f, 0, 0};
  }
  buildAndCheck(clusters, 4, order, "clusters");
}

BOOST_AUTO_TEST_CASE(trees_do_not_depend_on_the_thread_count) {
  std::mt19937 rng(3);
  // Large enough for the parallel sort and parallel subtrees, with duplicates so that equal
  // codes must keep their input order.
  std::vector<Box3f> boxes = randomBoxes(rng, 120000, 1.0f);
  for (std::size_t i = 0; i < boxes.size(); i += 3) boxes[i] = boxes[i / 2];
  BvhBuildResult results[2];
  std::vector<std::uint32_t> orders[2];
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    BvhMortonBuilder builder;
    builder.build(boxes, BvhMortonOptions{}, orders[threads - 1], results[threads - 1]);
  }
  BOOST_TEST((orders[0] == orders[1]));
  BOOST_TEST(results[0].nodes.size() == results[1].nodes.size());
  BOOST_TEST(results[0].leaves == results[1].leaves);
  BOOST_TEST(results[0].maxDepth == results[1].maxDepth);
  BOOST_TEST(results[0].sahCost == results[1].sahCost);
  BOOST_TEST(sameTree(results[0].nodes, 0, results[1].nodes, 0));
  // Jobs are placed in job order, so even the node numbering is the same.
  BOOST_TEST_REQUIRE(results[0].nodes.size() == results[1].nodes.size());
  BOOST_TEST(std::memcmp(results[0].nodes.data(), results[1].nodes.data(),
                         results[0].nodes.size() * sizeof(Bvh4Node)) == 0);
}

BOOST_AUTO_TEST_CASE(jobs_give_the_tree_of_a_single_recursion) {
  // Far apart clusters of different sizes make top nodes with leaf slots, job slots and top
  // slots side by side; a tiny job size makes many jobs. The tree, its cost and its leaf order
  // must be those of one recursion over the whole range.
  std::mt19937 rng(7);
  std::vector<Box3f> boxes = randomBoxes(rng, 20000, 1.0f);
  for (std::size_t i = 0; i < boxes.size(); i += 7) {
    boxes[i].lower = boxes[i].lower * 1e-3f + Vec3f{500, 0, 0};
    boxes[i].upper = boxes[i].upper * 1e-3f + Vec3f{500, 0, 0};
  }
  boxes[11] = {{-1e4f, -1e4f, -1e4f}, {-1e4f, -1e4f, -1e4f}};  // alone in its corner
  for (std::uint32_t maxLeaf : {1u, 2u, 4u}) {
    BvhMortonOptions single;
    single.maxLeafSize = maxLeaf;
    single.parallelThreshold = boxes.size();
    BvhBuildResult reference;
    std::vector<std::uint32_t> referenceOrder;
    BvhMortonBuilder builder;
    builder.build(boxes, single, referenceOrder, reference);
    for (std::size_t jobSize : {4u, 37u, 1000u}) {
      BvhMortonOptions options = single;
      options.parallelThreshold = jobSize;
      BvhBuildResult out;
      std::vector<std::uint32_t> order;
      builder.build(boxes, options, order, out);
      const std::string label =
          "maxLeaf=" + std::to_string(maxLeaf) + " jobSize=" + std::to_string(jobSize);
      BOOST_TEST((order == referenceOrder), label);
      BOOST_TEST(sameTree(out.nodes, 0, reference.nodes, 0), label);
      BOOST_TEST(out.nodes.size() == reference.nodes.size(), label);
      BOOST_TEST(out.sahCost == reference.sahCost, label);
      BOOST_TEST((out.bounds == reference.bounds), label);
      BOOST_TEST(out.leaves == reference.leaves, label);
      BOOST_TEST(out.maxDepth == reference.maxDepth, label);
      // And the tree is valid on its own: every slot box encloses what lies below it.
      std::vector<Box3f> sorted(boxes.size());
      for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = boxes[order[k]];
      std::vector<int> seen(boxes.size(), 0);
      TreeCheck c;
      walk(out.nodes, sorted, maxLeaf, seen, c);
      BOOST_TEST(c.errors == 0u, label << ": " << c.firstError);
      BOOST_TEST(c.nodesVisited == out.nodes.size(), label);
    }
  }
}

namespace {

/// Counts the primitives the leaf callback saw, as an Acc merged across jobs.
struct LeafCount {
  std::size_t primitives = 0;
  std::size_t leaves = 0;
  void merge(const LeafCount& o) {
    primitives += o.primitives;
    leaves += o.leaves;
  }
};

}  // namespace

BOOST_AUTO_TEST_CASE(emit_calls_the_leaf_callback_once_per_leaf) {
  std::mt19937 rng(8);
  const std::vector<Box3f> boxes = randomBoxes(rng, 30000, 1.0f);
  std::vector<Vec3f> centroids(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) centroids[i] = boxes[i].lower + boxes[i].upper;
  BvhMortonBuilder builder;
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> rank(boxes.size());
  builder.sort(centroids, order, nullptr, rank.data());
  for (std::size_t k = 0; k < order.size(); ++k) BOOST_TEST_REQUIRE(rank[order[k]] == k);
  std::vector<std::atomic<int>> visits(boxes.size());
  BvhMortonOptions options;
  options.parallelThreshold = 500;
  BvhBuildResult out;
  LeafCount count;
  builder.emit(
      options,
      [&](std::uint32_t first, std::uint32_t n, LeafCount& acc) {
        ++acc.leaves;
        acc.primitives += n;
        Box3f box;
        for (std::uint32_t k = first; k < first + n; ++k) {
          visits[k].fetch_add(1, std::memory_order_relaxed);
          box.extend(boxes[order[k]]);
        }
        return box;
      },
      out, count);
  BOOST_TEST(count.primitives == boxes.size());
  BOOST_TEST(count.leaves == out.leaves);
  std::size_t once = 0;
  for (const std::atomic<int>& v : visits) once += v.load() == 1 ? 1 : 0;
  BOOST_TEST(once == boxes.size());
  // The same tree as build() over the boxes.
  BvhBuildResult viaBuild;
  std::vector<std::uint32_t> buildOrder;
  BvhMortonBuilder().build(boxes, options, buildOrder, viaBuild);
  BOOST_TEST((buildOrder == order));
  BOOST_TEST(sameTree(out.nodes, 0, viaBuild.nodes, 0));
}

BOOST_AUTO_TEST_CASE(object_build_and_refit_of_the_same_mesh_agree) {
  // The build makes boxes, bounds, degenerate count and cost on its own pass; a refit of the
  // unchanged mesh recomputes them through the refit pass and must find the same figures.
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> pos(-50.0f, 50.0f), off(-0.5f, 0.5f);
  TriangleMesh mesh;
  for (std::uint32_t t = 0; t < 12000; ++t) {
    const Vec3f c{pos(rng), pos(rng), pos(rng)};
    for (int k = 0; k < 3; ++k) {
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
      // Every tenth triangle collapses to a point: degenerate, kept in the tree.
      mesh.positions.push_back(t % 10 == 0 ? c : c + Vec3f{off(rng), off(rng), off(rng)});
    }
  }
  const std::unique_ptr<ObjectAccel> accel = createObjectAccel(AccelKind::BvhFast);
  accel->build(mesh);
  const BuildStats built = accel->stats();
  const Box3f builtBounds = accel->bounds();
  BOOST_TEST(built.degenerate == 1200u);
  BOOST_TEST(built.primReferences == 12000u);
  BOOST_TEST(accel->refit(mesh));
  const BuildStats& refitted = accel->stats();
  BOOST_TEST(refitted.refitted);
  BOOST_TEST(refitted.degenerate == built.degenerate);
  BOOST_TEST(refitted.sahCost == built.sahCost);
  BOOST_TEST((accel->bounds() == builtBounds));
  // A second build over the reused buffers gives the same figures again.
  accel->build(mesh);
  BOOST_TEST(accel->stats().sahCost == built.sahCost);
  BOOST_TEST(accel->stats().nodes == built.nodes);
  BOOST_TEST((accel->bounds() == builtBounds));
}

BOOST_AUTO_TEST_CASE(rebuilds_reuse_the_builder) {
  // A builder that built a larger input first must give the same tree as a fresh one.
  std::mt19937 rng(4);
  const std::vector<Box3f> large = randomBoxes(rng, 40000, 1.0f);
  const std::vector<Box3f> small = randomBoxes(rng, 9000, 1.0f);
  BvhMortonBuilder reused, fresh;
  std::vector<std::uint32_t> orderA, orderB;
  BvhBuildResult a, b;
  reused.build(large, BvhMortonOptions{}, orderA, a);
  reused.build(small, BvhMortonOptions{}, orderA, a);
  fresh.build(small, BvhMortonOptions{}, orderB, b);
  BOOST_TEST((orderA == orderB));
  BOOST_TEST(a.nodes.size() == b.nodes.size());
  BOOST_TEST(sameTree(a.nodes, 0, b.nodes, 0));
}

BOOST_AUTO_TEST_CASE(refit_recomputes_boxes_bottom_up) {
  std::mt19937 rng(5);
  std::vector<Box3f> boxes = randomBoxes(rng, 30000, 2.0f);
  std::vector<std::uint32_t> order;
  BvhMortonOptions options;
  BvhMortonBuilder builder;
  BvhBuildResult built;
  builder.build(boxes, options, order, built);
  const auto leafBox = [&](std::uint32_t first, std::uint32_t count, NoLeafData&) {
    Box3f b;
    for (std::uint32_t k = first; k < first + count; ++k) b.extend(boxes[order[k]]);
    return SseBox::of(b);
  };
  // Unchanged boxes: the refit reproduces the build's boxes and cost exactly, serial or not.
  for (int levels : {0, 2}) {
    Bvh4NodeArray nodes = built.nodes;
    Bvh4SahSum sum;
    NoLeafData none;
    const Box3f root = refitBvh4(nodes, 0, leafBox, options.traversalCost, options.intersectionCost,
                                 levels, sum, none)
                           .box();
    BOOST_TEST((root == built.bounds));
    BOOST_TEST(sum.finish(root, options.traversalCost) == built.sahCost);
    BOOST_TEST(sameTree(nodes, 0, built.nodes, 0));
  }
  // Moved boxes: the refitted tree encloses every primitive again.
  std::uniform_real_distribution<float> move(-5.0f, 5.0f);
  for (Box3f& b : boxes) {
    const Vec3f d{move(rng), move(rng), move(rng)};
    b = {b.lower + d, b.upper + d};
  }
  Bvh4NodeArray nodes = built.nodes;
  Bvh4SahSum sum;
  NoLeafData none;
  const Box3f root = refitBvh4(nodes, 0, leafBox, 1.0, 1.0, 2, sum, none).box();
  std::vector<Box3f> sorted(boxes.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = boxes[order[k]];
  std::vector<int> seen(boxes.size(), 0);
  TreeCheck c;
  BOOST_TEST((walk(nodes, sorted, options.maxLeafSize, seen, c) == root));
  BOOST_TEST(c.errors == 0u, c.firstError);
  const double walked = bvh4SahCost(nodes, 1.0, 1.0);
  BOOST_TEST(std::abs(sum.finish(root, 1.0) - walked) <= 1e-9 * walked);
}

BOOST_AUTO_TEST_CASE(prim_interface_matches_the_box_interface) {
  std::mt19937 rng(6);
  const std::vector<Box3f> boxes = randomBoxes(rng, 5000, 1.0f);
  BvhPrimArray prims;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    prims.push_back(BvhPrim::make(boxes[i], static_cast<std::uint32_t>(i)));
  BvhBuildOptions options;
  options.maxLeafSize = 2;
  BvhBuildResult viaPrims, viaBoxes;
  buildBvh4Morton(prims, options, viaPrims);
  BvhMortonOptions mortonOptions;
  mortonOptions.maxLeafSize = 2;
  std::vector<std::uint32_t> order;
  BvhMortonBuilder().build(boxes, mortonOptions, order, viaBoxes);
  BOOST_TEST_REQUIRE(prims.size() == order.size());
  for (std::size_t k = 0; k < order.size(); ++k) BOOST_TEST_REQUIRE(prims[k].id == order[k]);
  BOOST_TEST(sameTree(viaPrims.nodes, 0, viaBoxes.nodes, 0));
}

namespace {

/// The Morton code of one centroid as documented (1024 cells per axis within the centroid
/// bounds, x in the highest of each three bits), written plainly.
std::uint32_t referenceCode(const Vec3f& c, const MortonCentroidBounds& b) {
  std::uint32_t code = 0;
  for (int a = 0; a < 3; ++a) {
    const float extent = b.upper[a] - b.lower[a];
    const float scale =
        extent > 0.0f && extent < MortonCentroidBounds::kInf ? 1024.0f / extent : 0.0f;
    float f = (c[a] - b.lower[a]) * scale;
    f = f > 0.0f ? f : 0.0f;
    f = f < 1023.0f ? f : 1023.0f;
    const std::uint32_t cell = static_cast<std::uint32_t>(f);
    for (int bit = 0; bit < 10; ++bit) code |= ((cell >> bit) & 1u) << (3 * bit + (2 - a));
  }
  return code;
}

}  // namespace

BOOST_AUTO_TEST_CASE(sort_orders_by_the_documented_codes) {
  // Sizes that leave a remainder after groups of four, small and large (parallel blocks), with
  // duplicates, NaN centroids and centroids on the bounds.
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> pos(-3.0f, 7.0f);
  for (std::size_t n : {1u, 3u, 5u, 1023u, 50001u}) {
    std::vector<Vec3f> centroids(n);
    for (Vec3f& c : centroids) c = {pos(rng), pos(rng), pos(rng)};
    for (std::size_t i = 0; i < n; i += 5) centroids[i] = centroids[i / 3];
    if (n > 3) centroids[2].y = std::numeric_limits<float>::quiet_NaN();
    MortonCentroidBounds bounds;
    for (const Vec3f& c : centroids) bounds.add(c);
    std::vector<std::uint32_t> expected(n);
    for (std::uint32_t i = 0; i < n; ++i) expected[i] = i;
    std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t x, std::uint32_t y) {
      return referenceCode(centroids[x], bounds) < referenceCode(centroids[y], bounds);
    });
    BvhMortonBuilder builder;
    std::vector<std::uint32_t> order;
    builder.sort(centroids, order);
    BOOST_TEST((order == expected), "n=" << n);
    // Given bounds give the same order.
    std::vector<std::uint32_t> withBounds;
    builder.sort(centroids, withBounds, &bounds);
    BOOST_TEST((withBounds == expected), "n=" << n);
  }
}
