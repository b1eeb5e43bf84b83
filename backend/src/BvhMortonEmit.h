// Emission of a Morton-ordered BVH4 with its boxes: the top-down split of the sorted codes and the
// bottom-up boxes in one recursion, subtrees built as parallel jobs into their own node buffers.
// Internal header: not installed.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "Bvh4Refit.h"
#include "BvhBuilder.h"

namespace tg::detail {

/// A range [begin, end) of sorted Morton codes.
struct MortonRange {
  std::uint32_t begin = 0, end = 0;
  std::uint32_t count() const { return end - begin; }
};

/// Splits `range` into up to four child ranges, in code order, by opening the range that must
/// split (more than `maxLeaf` primitives) and spans the largest cell of the code grid (the
/// highest differing bit; then the most primitives) until there are four. Returns their number.
int openMortonRanges(const std::uint32_t* codes, MortonRange range, std::uint32_t maxLeaf,
                     MortonRange ranges[4]);

/// Leaf slots and deepest node level of a subtree.
struct MortonCounts {
  std::size_t leaves = 0;
  std::size_t maxDepth = 0;
  void merge(const MortonCounts& o) {
    leaves += o.leaves;
    maxDepth = std::max(maxDepth, o.maxDepth);
  }
};

/// Node buffers and job lists of the emission, kept between builds so that per-frame rebuilds
/// do not allocate once the primitive count has stopped growing.
struct MortonEmitScratch {
  /// A subtree built as one job, below a node of the top part (topJobs says which slot).
  struct Job {
    MortonRange range;
    std::size_t depth = 0;  ///< level of the job's root
  };
  std::vector<Job> jobs;
  std::vector<Bvh4NodeArray> buffers;  ///< one node buffer per job
  std::vector<std::uint32_t> offsets;  ///< final index of each job's root
  std::vector<std::int32_t> topJobs;   ///< per top node and slot: job index or -1
  std::vector<Box3f> topBoxes;         ///< union of each top node's slots
  std::vector<Bvh4SahSum> topSums;     ///< SAH sums of each top node's subtree
  /// Bytes held.
  std::size_t bytes() const {
    std::size_t b = jobs.capacity() * sizeof(Job) + offsets.capacity() * sizeof(std::uint32_t) +
                    topJobs.capacity() * sizeof(std::int32_t) +
                    topBoxes.capacity() * sizeof(Box3f) + topSums.capacity() * sizeof(Bvh4SahSum);
    for (const Bvh4NodeArray& nodes : buffers) b += nodes.capacity() * sizeof(Bvh4Node);
    return b;
  }
};

/// Emits the BVH4 over `n` sorted codes into `out` (nodes, bounds, leaves, maxDepth, sahCost).
///
/// `leafBox(first, count, acc)` gives a leaf slot's box (as refitBvh4's), so that boxes are
/// made while the ranges are hot instead of in a second walk. Ranges of more than `jobSize`
/// primitives are split on the calling thread (the top part); the subtrees below them are
/// jobs run in parallel, each into its own buffer, then copied behind the top nodes in job
/// order. Tree, node numbering, sums and `acc` (merged in job order) therefore never depend on
/// the thread count, and the SAH sums are added in the order refitBvh4 adds them, so a refit of
/// unchanged boxes reproduces the build's cost exactly. Children are numbered after their
/// parent.
template <class Acc, class LeafBox>
class MortonEmitter {
 public:
  MortonEmitter(const std::uint32_t* codes, std::uint32_t maxLeaf, double traversalCost,
                double intersectionCost, const LeafBox& leafBox)
      : codes_(codes),
        maxLeaf_(std::max<std::uint32_t>(maxLeaf, 1)),
        traversalCost_(traversalCost),
        intersectionCost_(intersectionCost),
        leafBox_(leafBox) {}

  /// Emits the tree over codes [0, n), with jobs of at most `jobSize` primitives.
  void run(std::uint32_t n, std::size_t jobSize, MortonEmitScratch& scratch, BvhBuildResult& out,
           Acc& acc) {
    out.leaves = 0;
    out.maxDepth = 0;
    out.nodes.clear();
    if (n == 0) {
      out.bounds = Box3f{};
      out.sahCost = 0.0;
      return;
    }
    Bvh4SahSum sum;
    MortonCounts counts;
    if (n <= jobSize) {
      // Small trees go straight into the output: no job, no copy.
      out.nodes.resize(1);
      out.bounds = emitNode(out.nodes, 0, {0, n}, 0, sum, counts, acc);
    } else {
      out.bounds = emitLarge(n, jobSize, scratch, out, sum, counts, acc);
    }
    out.leaves = counts.leaves;
    out.maxDepth = counts.maxDepth;
    out.sahCost = sum.finish(out.bounds, traversalCost_);
  }

 private:
  /// The subtree of `range` into nodes[index] and after; returns the union of its slots.
  Box3f emitNode(Bvh4NodeArray& nodes, std::uint32_t index, MortonRange range, std::size_t depth,
                 Bvh4SahSum& sum, MortonCounts& counts, Acc& acc) const {
    MortonRange ranges[4];
    const int n = openMortonRanges(codes_, range, maxLeaf_, ranges);
    counts.maxDepth = std::max(counts.maxDepth, depth);
    std::uint32_t inner = 0;
    for (int c = 0; c < n; ++c) inner += ranges[c].count() > maxLeaf_ ? 1u : 0u;
    // The inner children take consecutive indices right after those already used, so each is
    // numbered after its parent.
    std::uint32_t next = static_cast<std::uint32_t>(nodes.size());
    nodes.resize(next + inner);
    Bvh4Node node = Bvh4Node::makeEmpty();
    Box3f all;
    for (int c = 0; c < n; ++c) {
      const MortonRange r = ranges[c];
      Box3f box;
      if (r.count() <= maxLeaf_) {
        box = leafBox_(r.begin, r.count(), acc);
        node.child[c] = r.begin;
        node.count[c] = r.count();
        ++counts.leaves;
        sum.addSlot(box, intersectionCost_ * r.count());
      } else {
        Bvh4SahSum childSum;
        node.child[c] = next;
        node.count[c] = 0;
        box = emitNode(nodes, next++, r, depth + 1, childSum, counts, acc);
        sum.addSlot(box, traversalCost_);
        sum.add(childSum);
      }
      node.setBounds(c, box);
      all.extend(box);
    }
    nodes[index] = node;
    return all;
  }

  /// Per job: its subtree's box, sums, counts and gathered leaf data.
  struct JobResult {
    Box3f box;
    Bvh4SahSum sum;
    MortonCounts counts;
    Acc acc;
  };

  Box3f emitLarge(std::uint32_t n, std::size_t jobSize, MortonEmitScratch& scratch,
                  BvhBuildResult& out, Bvh4SahSum& sum, MortonCounts& counts, Acc& acc) const {
    // The top part, on this thread: ranges above jobSize become top nodes, in the order the
    // recursion meets them, the inner ranges below it jobs.
    scratch.jobs.clear();
    scratch.topJobs.clear();
    out.nodes.resize(1);
    splitTop(out.nodes, 0, {0, n}, 0, jobSize, scratch, counts);
    const std::size_t top = out.nodes.size(), jobs = scratch.jobs.size();
    if (scratch.buffers.size() < jobs) scratch.buffers.resize(jobs);
    std::vector<JobResult> results(jobs);
    tbb::parallel_for(std::size_t{0}, jobs, [&](std::size_t j) {
      const MortonEmitScratch::Job& job = scratch.jobs[j];
      Bvh4NodeArray& nodes = scratch.buffers[j];
      nodes.resize(1);
      JobResult& r = results[j];
      r.box = emitNode(nodes, 0, job.range, job.depth, r.sum, r.counts, r.acc);
    });
    // Jobs follow the top nodes in job order.
    scratch.offsets.resize(jobs);
    std::size_t total = top;
    for (std::size_t j = 0; j < jobs; ++j) {
      scratch.offsets[j] = static_cast<std::uint32_t>(total);
      total += scratch.buffers[j].size();
    }
    out.nodes.resize(total);
    tbb::parallel_for(std::size_t{0}, jobs, [&](std::size_t j) {
      const Bvh4NodeArray& nodes = scratch.buffers[j];
      const std::uint32_t base = scratch.offsets[j];
      Bvh4Node* dst = out.nodes.data() + base;
      for (std::size_t k = 0; k < nodes.size(); ++k) {
        Bvh4Node node = nodes[k];
        for (int s = 0; s < 4; ++s)
          if (node.isInner(s)) node.child[s] += base;
        dst[k] = node;
      }
    });
    for (std::size_t j = 0; j < jobs; ++j) {
      counts.merge(results[j].counts);
      acc.merge(results[j].acc);
    }
    // Boxes of the top nodes, children (numbered after their parents) first.
    scratch.topBoxes.resize(top);
    scratch.topSums.assign(top, Bvh4SahSum{});
    for (std::size_t t = top; t-- > 0;) {
      Bvh4Node& node = out.nodes[t];
      Bvh4SahSum& nodeSum = scratch.topSums[t];
      Box3f all;
      for (int s = 0; s < 4; ++s) {
        if (node.child[s] == kInvalidId) continue;
        const std::int32_t job = scratch.topJobs[4 * t + static_cast<std::size_t>(s)];
        Box3f box;
        if (node.count[s] != 0) {
          box = leafBox_(node.child[s], node.count[s], acc);
          nodeSum.addSlot(box, intersectionCost_ * node.count[s]);
        } else if (job >= 0) {
          const JobResult& r = results[static_cast<std::size_t>(job)];
          node.child[s] = scratch.offsets[static_cast<std::size_t>(job)];
          box = r.box;
          nodeSum.addSlot(box, traversalCost_);
          nodeSum.add(r.sum);
        } else {
          box = scratch.topBoxes[node.child[s]];
          nodeSum.addSlot(box, traversalCost_);
          nodeSum.add(scratch.topSums[node.child[s]]);
        }
        node.setBounds(s, box);
        all.extend(box);
      }
      scratch.topBoxes[t] = all;
    }
    sum = scratch.topSums[0];
    return scratch.topBoxes[0];
  }

  /// Splits `range` into top node `index` (boxes left for later) and records its jobs.
  void splitTop(Bvh4NodeArray& nodes, std::uint32_t index, MortonRange range, std::size_t depth,
                std::size_t jobSize, MortonEmitScratch& scratch, MortonCounts& counts) const {
    MortonRange ranges[4];
    const int n = openMortonRanges(codes_, range, maxLeaf_, ranges);
    counts.maxDepth = std::max(counts.maxDepth, depth);
    std::uint32_t next = static_cast<std::uint32_t>(nodes.size());
    std::uint32_t topChildren = 0;
    for (int c = 0; c < n; ++c) topChildren += ranges[c].count() > jobSize ? 1u : 0u;
    nodes.resize(next + topChildren);
    scratch.topJobs.resize(nodes.size() * 4, -1);
    Bvh4Node node = Bvh4Node::makeEmpty();
    for (int c = 0; c < n; ++c) {
      const MortonRange r = ranges[c];
      if (r.count() <= maxLeaf_) {
        node.child[c] = r.begin;
        node.count[c] = r.count();
        ++counts.leaves;
      } else if (r.count() <= jobSize) {
        node.child[c] = 0;  // the job's root index, known once the jobs are done
        node.count[c] = 0;
        scratch.topJobs[4 * std::size_t{index} + static_cast<std::size_t>(c)] =
            static_cast<std::int32_t>(scratch.jobs.size());
        scratch.jobs.push_back({r, depth + 1});
      } else {
        node.child[c] = next;
        node.count[c] = 0;
        nodes[index] = node;  // the recursion may reallocate: store what is known so far
        splitTop(nodes, next++, r, depth + 1, jobSize, scratch, counts);
      }
    }
    nodes[index] = node;
  }

  const std::uint32_t* codes_;
  const std::uint32_t maxLeaf_;
  const double traversalCost_;
  const double intersectionCost_;
  const LeafBox& leafBox_;
};

}  // namespace tg::detail
