// The top-level BVH4 builder on its own: tree structure (every instance in exactly one leaf,
// exact slot boxes, leaf sizes), awkward inputs, the same tree as buildBvh4 with one binned axis,
// and the same tree whatever the thread count on the parallel paths.
#define BOOST_TEST_MODULE toplevel_bvh_builder
#include <boost/test/unit_test.hpp>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "Bvh4TreeWalk.h"
#include "BvhBuilder.h"
#include "TopLevelBvhBuilder.h"

using namespace tg;
using namespace tg::detail;

namespace {

using TreeCheck = tg::test::Bvh4TreeCheck;
using tg::test::sameBox;

BvhPrimArray makePrims(const std::vector<Box3f>& boxes) {
  BvhPrimArray prims;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    prims.push_back(BvhPrim::make(boxes[i], static_cast<std::uint32_t>(i)));
  return prims;
}

/// Checks a result over `boxes` (the input of the build that reordered `prims`).
TreeCheck check(const std::vector<Box3f>& boxes, const BvhPrimArray& prims,
                const BvhBuildResult& out, std::uint32_t maxLeaf, bool allowBigLeaves) {
  TreeCheck c;
  if (boxes.empty()) {
    if (!out.nodes.empty()) c.fail("nodes for an empty input");
    return c;
  }
  std::vector<int> ids(boxes.size(), 0);
  for (const BvhPrim& p : prims) {
    if (p.id >= boxes.size() || !sameBox(p.box(), boxes[p.id])) c.fail("primitive changed");
    if (p.id < boxes.size()) ++ids[p.id];
  }
  for (const int n : ids)
    if (n != 1) c.fail("primitives are not a permutation of the input");
  std::vector<int> seen(prims.size(), 0);
  std::vector<Box3f> primBoxes;
  for (const BvhPrim& p : prims) primBoxes.push_back(p.box());
  const Box3f all = tg::test::walkBvh4(
      out.nodes, 0, 0, primBoxes, {maxLeaf, allowBigLeaves, tg::test::SlotBoxRule::Exact}, seen, c);
  for (const int n : seen)
    if (n != 1) c.fail("a primitive is not in exactly one leaf");
  if (!sameBox(all, out.bounds)) c.fail("result bounds differ from the root's slots");
  if (c.leaves != out.leaves) c.fail("leaf count differs from the walk");
  return c;
}

TreeCheck buildAndCheck(const std::vector<Box3f>& boxes, const TopLevelBuildOptions& options,
                        bool allowBigLeaves, BvhPrimArray& prims, BvhBuildResult& out) {
  prims = makePrims(boxes);
  TopLevelBvhBuilder builder;
  builder.build(prims, options, out);
  return check(boxes, prims, out, options.maxLeafSize, allowBigLeaves);
}

/// Depth-first description of a tree that does not depend on node numbering or on the order of
/// primitives within a leaf: slot kinds, boxes, and each leaf's sorted ids.
std::vector<double> describe(const Bvh4NodeArray& nodes, const BvhPrimArray& prims) {
  std::vector<double> d;
  if (nodes.empty()) return d;
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const Bvh4Node& node = nodes[stack.back()];
    stack.pop_back();
    for (int s = 0; s < 4; ++s) {
      if (node.child[s] == kInvalidId) {
        d.push_back(-1.0);
        continue;
      }
      const Box3f b = node.slotBounds(s);
      for (int a = 0; a < 3; ++a) {
        d.push_back(b.lower[a]);
        d.push_back(b.upper[a]);
      }
      if (node.count[s] == 0) {
        d.push_back(0.0);
        stack.push_back(node.child[s]);
        continue;
      }
      std::vector<std::uint32_t> ids;
      for (std::uint32_t k = node.child[s]; k < node.child[s] + node.count[s]; ++k)
        ids.push_back(prims[k].id);
      std::sort(ids.begin(), ids.end());
      d.push_back(static_cast<double>(ids.size()));
      for (const std::uint32_t id : ids) d.push_back(id);
    }
  }
  return d;
}

std::vector<Box3f> randomBoxes(std::size_t n, std::uint32_t seed, float side, float size) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(0.0f, side), ext(0.0f, size);
  std::vector<Box3f> boxes;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f lo{pos(rng), pos(rng), pos(rng)};
    boxes.push_back({lo, lo + Vec3f{ext(rng), ext(rng), ext(rng)}});
  }
  return boxes;
}

}  // namespace

BOOST_AUTO_TEST_CASE(random_boxes_give_valid_trees) {
  TopLevelBuildOptions options;
  for (const std::size_t n : {2, 3, 4, 5, 8, 9, 17, 100, 1000, 20000}) {
    BvhPrimArray prims;
    BvhBuildResult out;
    const TreeCheck c =
        buildAndCheck(randomBoxes(n, 7 + static_cast<std::uint32_t>(n), 100.0f, 2.0f), options,
                      false, prims, out);
    BOOST_TEST(c.errors == 0u, "n=" << n << ": " << c.firstError);
    BOOST_TEST(out.maxDepth <= static_cast<std::size_t>(kBvh4MaxDepth));
  }
}

BOOST_AUTO_TEST_CASE(same_tree_as_the_general_builder_on_one_axis) {
  // The top-level builder takes buildBvh4's splits with one binned axis, so traversal costs
  // the same through either tree.
  for (const std::size_t n : {3, 7, 50, 661, 5000, 30000}) {
    const std::vector<Box3f> boxes = randomBoxes(n, 19 + static_cast<std::uint32_t>(n),
                                                 2.0f * std::cbrt(static_cast<float>(n)), 1.0f);
    for (const std::size_t threshold : {std::size_t(8192), std::size_t(256)}) {
      TopLevelBuildOptions options;
      options.parallelThreshold = threshold;
      BvhBuildOptions general;
      general.bins = options.bins;
      general.allAxes = false;
      general.maxLeafSize = options.maxLeafSize;
      general.traversalCost = options.traversalCost;
      general.intersectionCost = options.intersectionCost;
      general.parallelThreshold = threshold;
      BvhPrimArray prims;
      BvhBuildResult out;
      const TreeCheck c = buildAndCheck(boxes, options, false, prims, out);
      BOOST_TEST(c.errors == 0u, c.firstError);
      BvhPrimArray generalPrims = makePrims(boxes);
      BvhBuildResult generalOut;
      buildBvh4(generalPrims, general, generalOut);
      BOOST_TEST((describe(out.nodes, prims) == describe(generalOut.nodes, generalPrims)),
                 "n=" << n << " threshold=" << threshold);
    }
  }
}

BOOST_AUTO_TEST_CASE(awkward_inputs) {
  TopLevelBuildOptions options;
  BvhPrimArray prims;
  BvhBuildResult out;

  TreeCheck c = buildAndCheck({}, options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);
  BOOST_TEST(out.leaves == 0u);

  const Box3f one{{1, 2, 3}, {4, 5, 6}};
  c = buildAndCheck({one}, options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);
  BOOST_TEST(out.leaves == 1u);
  BOOST_TEST(out.nodes.size() == 1u);

  // All boxes equal (instances at one place): median splits bound the leaves, in parallel
  // ranges too.
  c = buildAndCheck(std::vector<Box3f>(100, one), options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);
  c = buildAndCheck(std::vector<Box3f>(20000, one), options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);

  // Point boxes along a line (zero area everywhere).
  std::vector<Box3f> line;
  for (int i = 0; i < 300; ++i) {
    const Vec3f p{static_cast<float>(i), 0.0f, 0.0f};
    line.push_back({p, p});
  }
  c = buildAndCheck(line, options, false, prims, out);
  BOOST_TEST(c.errors == 0u, c.firstError);

  // Infinite and NaN coordinates must not crash the build or lose an instance.
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Box3f> wild = randomBoxes(40, 5, 10.0f, 1.0f);
  wild.push_back({{-inf, 0, 0}, {inf, 1, 1}});
  wild.push_back({{0, -inf, 0}, {1, 2, inf}});
  wild.push_back({{nan, 0, 0}, {nan, 1, 1}});
  wild.push_back({{-inf, -inf, -inf}, {inf, inf, inf}});
  prims = makePrims(wild);
  TopLevelBvhBuilder builder;
  builder.build(prims, options, out);
  std::vector<int> ids(wild.size(), 0);
  for (const BvhPrim& p : prims) ++ids[p.id];
  BOOST_TEST((std::count(ids.begin(), ids.end(), 1) == static_cast<long>(wild.size())));
}

BOOST_AUTO_TEST_CASE(trees_do_not_depend_on_the_thread_count) {
  const std::vector<Box3f> boxes = randomBoxes(60000, 11, 200.0f, 3.0f);
  TopLevelBuildOptions options;
  options.parallelThreshold = 512;  // the parallel binning, partition and subtree tasks run
  BvhPrimArray prims[2];
  BvhBuildResult out[2];
  TreeCheck c[2];
  tbb::task_arena(1).execute(
      [&] { c[0] = buildAndCheck(boxes, options, false, prims[0], out[0]); });
  tbb::task_arena(2).execute(
      [&] { c[1] = buildAndCheck(boxes, options, false, prims[1], out[1]); });
  BOOST_TEST(c[0].errors == 0u, c[0].firstError);
  BOOST_TEST(c[1].errors == 0u, c[1].firstError);
  BOOST_TEST((c[0].shape == c[1].shape));
  bool sameOrder = prims[0].size() == prims[1].size();
  for (std::size_t k = 0; sameOrder && k < prims[0].size(); ++k)
    sameOrder = prims[0][k].id == prims[1][k].id;
  BOOST_TEST(sameOrder);
}

BOOST_AUTO_TEST_CASE(rebuilding_with_one_builder_reuses_its_scratch) {
  // A per-frame rebuild: the same builder over moving boxes gives the tree a fresh builder gives.
  TopLevelBvhBuilder kept;
  TopLevelBuildOptions options;
  options.parallelThreshold = 1000;
  for (std::uint32_t frame = 0; frame < 3; ++frame) {
    const std::vector<Box3f> boxes = randomBoxes(9000 - 2000 * frame, 30 + frame, 50.0f, 2.0f);
    BvhPrimArray a = makePrims(boxes), b = makePrims(boxes);
    BvhBuildResult outA, outB;
    kept.build(a, options, outA);
    TopLevelBvhBuilder().build(b, options, outB);
    BOOST_TEST(check(boxes, a, outA, options.maxLeafSize, false).errors == 0u);
    BOOST_TEST((describe(outA.nodes, a) == describe(outB.nodes, b)));
  }
}
