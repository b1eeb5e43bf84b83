// Eight-wide twins of BVH4 nodes (see Bvh8Twin.h).
#include "Bvh8Twin.h"

#include <tbb/parallel_for.h>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define TG_COLLAPSE_AVX2 1
#else
#define TG_COLLAPSE_AVX2 0
#endif

#include <bit>
#include <limits>
#include <vector>

namespace tg::detail {
namespace {

/// True when slot `s` of `node` holds a child (inner or leaf).
bool used(const Bvh4Node& node, int s) {
  return node.child[s] != kInvalidId || node.count[s] != 0;
}

/// One slot of a twin under construction.
struct Slot {
  Box3f box;
  std::uint32_t child, count;
};

/// The slots of node `i`'s twin: its own, with the widest inner slot whose children fit opened
/// into its children, until none does (a ray that enters a wide box is the likeliest to enter
/// its children too). Returns how many (at most eight).
int twinSlots(const Bvh4NodeArray& nodes, std::size_t i, Slot slots[8]) {
  int n = 0;
  for (int s = 0; s < 4; ++s)
    if (used(nodes[i], s))
      slots[n++] = Slot{nodes[i].slotBounds(s), nodes[i].child[s], nodes[i].count[s]};
  for (;;) {
    int best = -1;
    float bestArea = -1.0f;
    for (int k = 0; k < n; ++k) {
      if (slots[k].count != 0) continue;
      const Bvh4Node& c = nodes[slots[k].child];
      int children = 0;
      for (int s = 0; s < 4; ++s) children += used(c, s) ? 1 : 0;
      if (children == 0 || n - 1 + children > 8) continue;
      const float area = slots[k].box.area();
      if (area > bestArea) {
        best = k;
        bestArea = area;
      }
    }
    if (best < 0) return n;
    const Bvh4Node& c = nodes[slots[best].child];
    bool first = true;
    for (int s = 0; s < 4; ++s) {
      if (!used(c, s)) continue;
      const Slot slot{c.slotBounds(s), c.child[s], c.count[s]};
      if (first) {
        slots[best] = slot;
        first = false;
      } else {
        slots[n++] = slot;
      }
    }
  }
}

/// Writes the `n` slots into `out`, the rest unused.
void writeSlots(const Slot slots[8], int n, Bvh8Node& out) {
  for (int s = 0; s < 8; ++s) {
    const bool live = s < n;
    for (int a = 0; a < 3; ++a) {
      out.bounds[2 * a][s] = live ? slots[s].box.lower[a] : std::numeric_limits<float>::infinity();
      out.bounds[2 * a + 1][s] =
          live ? slots[s].box.upper[a] : -std::numeric_limits<float>::infinity();
    }
    out.child[s] = live ? slots[s].child : kInvalidId;
    out.count[s] = live ? slots[s].count : 0;
  }
}

/// Appends the twin of BVH4 node `i` to `wide` and then, depth first, those of the nodes its
/// inner slots hold, whose indices in `wide` replace theirs; returns its index.
std::uint32_t appendWideNode(const Bvh4NodeArray& nodes, std::uint32_t i, Bvh8NodeArray& wide) {
  Slot slots[8];
  const int n = twinSlots(nodes, i, slots);
  const auto index = static_cast<std::uint32_t>(wide.size());
  wide.emplace_back();
  for (int k = 0; k < n; ++k)
    if (slots[k].count == 0) slots[k].child = appendWideNode(nodes, slots[k].child, wide);
  writeSlots(slots, n, wide[index]);
  return index;
}

/// Part of a BVH4 node that a wide node holds as one child: the slots of `node` in `mask`.
/// Every part the collapse makes is a node's used slots or a group of them that lowHalf made,
/// so parts form a binary tree over the BVH4's slots.
struct Part {
  std::uint32_t node;
  unsigned mask;
  /// One slot holding a leaf.
  bool leaf = false;
};

/// True when `mask` holds at most one slot (std::popcount is a library call on x86-64's
/// baseline).
bool atMostOneSlot(unsigned mask) {
  return (mask & (mask - 1)) == 0;
}

/// The used slots of `node` as a mask.
unsigned usedMask(const Bvh4Node& node) {
  unsigned mask = 0;
  for (int s = 0; s < 4; ++s)
    if (used(node, s)) mask |= 1u << s;
  return mask;
}

/// A part of one slot that holds an inner node stands for that node's used slots; a part of one
/// leaf slot is marked as a leaf.
Part normalised(const Bvh4NodeArray& nodes, Part p) {
  while (atMostOneSlot(p.mask)) {
    const Bvh4Node& n = nodes[p.node];
    const int s = std::countr_zero(p.mask);
    if (!n.isInner(s)) return Part{p.node, p.mask, true};
    p = Part{n.child[s], usedMask(nodes[n.child[s]])};
  }
  return p;
}

/// Union of the slot boxes of `p`.
Box3f partBox(const Bvh4NodeArray& nodes, const Part& p) {
  Box3f box;
  for (unsigned m = p.mask; m != 0; m &= m - 1)
    box.extend(nodes[p.node].slotBounds(std::countr_zero(m)));
  return box;
}

/// Union of the boxes in `box` of the slots in `mask`.
Box3f unionOf(const Box3f (&box)[4], unsigned mask) {
  Box3f b;
  for (; mask != 0; mask &= mask - 1) b.extend(box[std::countr_zero(mask)]);
  return b;
}

/// How the collapse splits the slots in `mask` (two to four of a node whose slot boxes are `box`):
/// the slots of the half that holds the lowest one. Two slots go one each; three the pair of
/// the smallest box and the third; four the pairing whose two boxes have the smallest summed
/// area (the binned SAH made the node by splitting its range in two, then the wider halves
/// again; the node does not record which slots came from which half, and the tightest pairing
/// stands for it).
unsigned lowHalf(const Box3f (&box)[4], unsigned mask) {
  int slots[4];
  int k = 0;
  for (unsigned m = mask; m != 0; m &= m - 1) slots[k++] = std::countr_zero(m);
  const auto pairArea = [&](int a, int b) {
    Box3f u = box[a];
    u.extend(box[b]);
    return u.area();
  };
  if (k == 2) return 1u << slots[0];
  if (k == 3) {
    const float a01 = pairArea(slots[0], slots[1]), a02 = pairArea(slots[0], slots[2]),
                a12 = pairArea(slots[1], slots[2]);
    if (a01 <= a02 && a01 <= a12) return (1u << slots[0]) | (1u << slots[1]);
    if (a02 <= a12) return (1u << slots[0]) | (1u << slots[2]);
    return 1u << slots[0];
  }
  const float c01 = pairArea(slots[0], slots[1]) + pairArea(slots[2], slots[3]);
  const float c02 = pairArea(slots[0], slots[2]) + pairArea(slots[1], slots[3]);
  const float c03 = pairArea(slots[0], slots[3]) + pairArea(slots[1], slots[2]);
  const int partner = c01 <= c02 && c01 <= c03 ? 1 : (c02 <= c03 ? 2 : 3);
  return (1u << slots[0]) | (1u << slots[partner]);
}

constexpr int kWidth = 8;

/// Half `h` of a solved part.
Part halfOf(const Bvh8PartChoice& c, int h) {
  return Part{c.halfNode[h], c.halfMask[h] & 15u, (c.halfMask[h] & 16u) != 0};
}

/// Stores the halves of a part in its choice record.
void setHalves(Bvh8PartChoice& c, const Part& first, const Part& second) {
  c.halfNode[0] = first.node;
  c.halfNode[1] = second.node;
  c.halfMask[0] = static_cast<std::uint8_t>(first.mask | (first.leaf ? 16u : 0u));
  c.halfMask[1] = static_cast<std::uint8_t>(second.mask | (second.leaf ? 16u : 0u));
}

/// Which of its node's three parts part `p` (of two or more slots, normalised) is.
int partOf(const Bvh8PartChoice* nodeParts, const Part& p) {
  if (nodeParts[0].mask == p.mask) return 0;
  return nodeParts[1].mask == p.mask ? 1 : 2;
}

/// The record of part `p` (of two or more slots, normalised) of a solved plan.
const Bvh8PartChoice& choiceOf(const Bvh8CollapsePlan& plan, const Part& p) {
  const Bvh8PartChoice* nodeParts = plan.choicesOf(p.node);
  return nodeParts[partOf(nodeParts, p)];
}

/// The costs of part `p` (of two or more slots, normalised) of a solved plan.
const Bvh8PartCosts& costsOf(const Bvh8CollapsePlan& plan, const Part& p) {
  return plan.costsOf(p.node)[partOf(plan.choicesOf(p.node), p)];
}

#if TG_COLLAPSE_AVX2
/// PlanSolver::solve with the budgets in the eight lanes of AVX registers (lane j - 1 for
/// budget j): part `c` of box area `area` from its first half's costs a[1..8] for 1 to 8 roots
/// and its second half's in b[8..15]; b[0..7] hold +inf, so that the load from b + 8 - k gives
/// lane j the cost of j - k roots, and +inf where j - k < 1, where the sum never wins. Each lane
/// adds and compares the same floats as the scalar loops and keeps the first of equal sums, so
/// the answers are the same bits (Callgrind, the programme in a one-thread `tg-bench static` run
/// of the BART kitchen: 128.6M -> 104.9M instructions). Compiled for AVX2: call it only where
/// the CPU runs AVX2.
[[gnu::target("avx2")]] void solveAvx2(const float* a, const float* b, float area,
                                       Bvh8PartChoice& c, Bvh8PartCosts& costs) {
  // The cheapest spread of j roots over the two halves, and the roots the first one takes.
  __m256 spread = _mm256_add_ps(_mm256_set1_ps(a[1]), _mm256_loadu_ps(b + 8 - 1));
  __m256i first = _mm256_set1_epi32(1);
  for (int k = 2; k < kWidth; ++k) {
    const __m256 sum = _mm256_add_ps(_mm256_set1_ps(a[k]), _mm256_loadu_ps(b + 8 - k));
    const __m256 better = _mm256_cmp_ps(sum, spread, _CMP_LT_OQ);
    spread = _mm256_blendv_ps(spread, sum, better);
    first = _mm256_blendv_epi8(first, _mm256_set1_epi32(k), _mm256_castps_si256(better));
  }
  // A node of its own takes its box and the spread over all eight of its slots; budget 1 has
  // no other choice (lane 0).
  alignas(32) float spreadOut[8];
  _mm256_store_ps(spreadOut, spread);
  const float own = area + spreadOut[kWidth - 1];
  const __m256 ownV = _mm256_set1_ps(own);
  const __m256 isOwn =
      _mm256_or_ps(_mm256_cmp_ps(ownV, spread, _CMP_LE_OQ),
                   _mm256_castsi256_ps(_mm256_setr_epi32(-1, 0, 0, 0, 0, 0, 0, 0)));
  _mm256_storeu_ps(costs.cost, _mm256_blendv_ps(spread, ownV, isOwn));
  // Three bits per budget of 2 to 8 (0 where a node of its own is cheaper), then the first
  // half's roots in a node of its own.
  const __m256i spreadRoots = _mm256_andnot_si256(_mm256_castps_si256(isOwn), first);
  alignas(32) std::uint32_t bits[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(bits),
                     _mm256_sllv_epi32(spreadRoots, _mm256_setr_epi32(0, 0, 3, 6, 9, 12, 15, 18)));
  alignas(32) std::int32_t firstOut[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(firstOut), first);
  c.choices = (bits[1] | bits[2] | bits[3] | bits[4] | bits[5] | bits[6] | bits[7]) |
              static_cast<std::uint32_t>(firstOut[kWidth - 1]) << 21;
}
#endif

/// True when this CPU runs solveAvx2.
bool cpuRunsSolveAvx2() {
#if TG_COLLAPSE_AVX2
  // Also called from static initialisers (plans made before main): detect the CPU first.
  static const bool runs = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return runs;
#else
  return false;
#endif
}

/// The dynamic programme of Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal on
/// GPUs Through Compressed Wide BVHs" (2017), over the binary tree of parts: for every part and
/// every budget i of 1 to 8, the cheapest way to stand for its subtree with at most i children
/// of the enclosing wide node, either as one wide node of its own or spread over the roots of
/// its two halves. The cost of a tree is the summed surface area of its wide nodes (the leaves
/// are the BVH4's in every collapse).
class PlanSolver {
 public:
  PlanSolver(const Bvh4NodeArray& nodes, const Bvh8CollapsePlan& plan)
      : nodes_(nodes), plan_(plan) {}

  /// Solves the parts of node `node`, whose children are solved: the node's slots split in two
  /// (lowHalf), and each half of two slots split again; the halves keep slot order (the one
  /// holding the lowest slot comes first). The slot boxes are read once, for every split and
  /// area.
  void solveNode(std::uint32_t node) const {
    const std::size_t i = node;
    const Bvh4Node& n = nodes_[i];
    Box3f box[4];
    unsigned mask = 0;
    for (int s = 0; s < 4; ++s) {
      if (!used(n, s)) continue;
      mask |= 1u << s;
      box[s] = n.slotBounds(s);
    }
    Bvh8PartChoice* const parts = plan_.choicesOf(node);
    Bvh8PartCosts* const costs = plan_.costsOf(node);
    Bvh8PartChoice& full = parts[0];
    full.mask = static_cast<std::uint8_t>(mask);
    parts[1].mask = 0;  // written below when this node has pairs
    parts[2].mask = 0;
    if (atMostOneSlot(mask)) return;  // a root of one slot: see WideCollapse::append()
    const unsigned low = lowHalf(box, mask);
    const Part first = normalised(nodes_, Part{node, low});
    const Part second = normalised(nodes_, Part{node, mask & ~low});
    // The halves that are pairs of this node's slots, then the node.
    for (int h = 0; h < 2; ++h) {
      const unsigned half = h == 0 ? low : mask & ~low;
      if (atMostOneSlot(half)) continue;
      Bvh8PartChoice& pair = parts[1 + h];
      pair.mask = static_cast<std::uint8_t>(half);
      const unsigned lowest = half & (0u - half);
      setHalves(pair, normalised(nodes_, Part{node, lowest}),
                normalised(nodes_, Part{node, half & ~lowest}));
      solve(pair, costs[1 + h], unionOf(box, half).area(), halfOf(pair, 0), halfOf(pair, 1));
    }
    setHalves(full, first, second);
    solve(full, costs[0], unionOf(box, mask).area(), first, second);
  }

 private:
  /// The costs of part `p` (normalised) for 1 to 8 roots in costs[1..8]: a leaf costs nothing.
  void costsInto(const Part& p, float* costs) const {
    if (p.leaf) {
      for (int i = 1; i <= kWidth; ++i) costs[i] = 0.0f;
      return;
    }
    const Bvh8PartCosts& c = costsOf(plan_, p);
    for (int i = 1; i <= kWidth; ++i) costs[i] = c.cost[i - 1];
  }

  /// The cheapest split of j roots between halves `firstHalf` and `secondHalf`, for j of 2 to
  /// 8, and the roots the first half takes in each.
  void spreadOf(const Part& firstHalf, const Part& secondHalf, float (&spread)[kWidth + 1],
                std::uint8_t (&first)[kWidth + 1]) const {
    float a[kWidth + 1], b[kWidth + 1];
    costsInto(firstHalf, a);
    costsInto(secondHalf, b);
    for (int j = 2; j <= kWidth; ++j) {
      // Without branches: which k wins is data the branch predictor cannot learn.
      float best = a[1] + b[j - 1];
      int bestK = 1;
      for (int k = 2; k < j; ++k) {
        const float sum = a[k] + b[j - k];
        const bool better = sum < best;
        bestK = better ? k : bestK;
        best = better ? sum : best;
      }
      spread[j] = best;
      first[j] = static_cast<std::uint8_t>(bestK);
    }
  }

  /// Solves a part of box area `area` from the costs of its halves.
  void solve(Bvh8PartChoice& c, Bvh8PartCosts& costs, float area, const Part& firstHalf,
             const Part& secondHalf) const {
#if TG_COLLAPSE_AVX2
    if (plan_.vectorSolve()) {
      float a[kWidth + 1];
      float b[2 * kWidth];  // +inf, then the second half's costs for 1 to 8 roots
      costsInto(firstHalf, a);
      for (int i = 0; i < kWidth; ++i) b[i] = std::numeric_limits<float>::infinity();
      costsInto(secondHalf, b + kWidth - 1);
      solveAvx2(a, b, area, c, costs);
      return;
    }
#endif
    float spread[kWidth + 1];
    std::uint8_t first[kWidth + 1];
    if (firstHalf.leaf && secondHalf.leaf) {
      // Two leaves (most pairs): one root each whatever the budget.
      for (int j = 2; j <= kWidth; ++j) {
        spread[j] = 0.0f;
        first[j] = 1;
      }
    } else {
      spreadOf(firstHalf, secondHalf, spread, first);
    }
    const float own = area + spread[kWidth];
    costs.cost[0] = own;
    std::uint32_t choices = std::uint32_t{first[kWidth]} << 21;
    for (int i = 2; i <= kWidth; ++i) {
      const bool isOwn = own <= spread[i];
      costs.cost[i - 1] = isOwn ? own : spread[i];
      choices |= (isOwn ? 0u : std::uint32_t{first[i]}) << (3 * (i - 2));
    }
    c.choices = choices;
  }

  const Bvh4NodeArray& nodes_;
  const Bvh8CollapsePlan& plan_;
};

/// The emission of the eight-wide tree that a solved plan describes.
class WideCollapse {
 public:
  WideCollapse(const Bvh4NodeArray& nodes, const Bvh8CollapsePlan& plan)
      : nodes_(nodes), plan_(plan), emitted_(3 * nodes.size(), kInvalidId) {}

  /// Appends the wide tree to `wide`, root first, and then, into `entries` (when given), the
  /// wide nodes of the BVH4 nodes of the first kBvh8EntryDepth levels below the root, sorted by
  /// BVH4 node. A node whose part the tree already holds as a wide node enters it there; the
  /// others get wide nodes of their own, above the wide nodes of the tree they share.
  void append(Bvh8NodeArray& wide, std::vector<Bvh8Entry>* entries) {
    if (nodes_.empty()) return;
    const Part root = normalised(nodes_, Part{0, usedMask(nodes_[0])});
    if (root.leaf) {
      // A tree of one leaf: a node of one slot.
      wide.emplace_back();
      const Bvh4Node& n = nodes_[root.node];
      const int s = std::countr_zero(root.mask);
      const Slot slot{n.slotBounds(s), n.child[s], n.count[s]};
      writeSlots(&slot, 1, wide[0]);
      return;
    }
    appendNode(root, wide);
    if (entries == nullptr) return;
    // Children are numbered after their parents, so a walk forwards meets parents first, and
    // the entries come out sorted.
    std::vector<std::uint8_t> depth(nodes_.size(), 255);  // 255: not within the entry levels
    depth[0] = 0;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (depth[i] > kBvh8EntryDepth) continue;
      const unsigned mask = usedMask(nodes_[i]);
      const auto node = static_cast<std::uint32_t>(i);
      if (!atMostOneSlot(mask))
        entries->push_back(Bvh8Entry{node, appendNode(Part{node, mask}, wide)});
      for (int s = 0; s < 4; ++s)
        if (nodes_[i].isInner(s))
          depth[nodes_[i].child[s]] = static_cast<std::uint8_t>(depth[i] + 1);
    }
  }

 private:
  /// The roots that stand for part `p` with at most `i` of them, in slot order.
  void roots(const Part& p, int i, Part* out, int& n) const {
    if (p.leaf) {
      out[n++] = p;
      return;
    }
    const Bvh8PartChoice& c = choiceOf(plan_, p);
    const int k = c.firstRoots(i);
    if (k == 0) {
      out[n++] = p;
      return;
    }
    roots(halfOf(c, 0), k, out, n);
    roots(halfOf(c, 1), i - k, out, n);
  }

  /// Appends the wide node of part `p` (not a leaf) and then, depth first, those of its inner
  /// children; returns its index. A part appended before is not appended again: its wide node
  /// is shared. The flattened BART kitchen's nodes take 1.7-1.8 ms to append on one thread, most
  /// of it waiting on the first loads of BVH4 nodes and choices (see Bvh8PartChoice).
  std::uint32_t appendNode(const Part& p, Bvh8NodeArray& wide) {
    const Bvh8PartChoice* const nodeParts = plan_.choicesOf(p.node);
    const int part = partOf(nodeParts, p);
    const std::size_t at = 3 * std::size_t{p.node} + static_cast<std::size_t>(part);
    if (emitted_[at] != kInvalidId) return emitted_[at];
    Part children[kWidth];
    int n = 0;
    // A wide node of its own spreads its halves over its eight slots.
    const Bvh8PartChoice& c = nodeParts[part];
    const int k = c.ownFirst();
    roots(halfOf(c, 0), k, children, n);
    roots(halfOf(c, 1), kWidth - k, children, n);
    Slot slots[kWidth];
    bool inner[kWidth];
    for (int s = 0; s < n; ++s) {
      const Bvh4Node& owner = nodes_[children[s].node];
      inner[s] = !children[s].leaf;
      if (!inner[s]) {
        const int slot = std::countr_zero(children[s].mask);
        slots[s] = Slot{owner.slotBounds(slot), owner.child[slot], owner.count[slot]};
      } else {
        slots[s] = Slot{partBox(nodes_, children[s]), kInvalidId, 0};
      }
    }
    const auto index = static_cast<std::uint32_t>(wide.size());
    wide.emplace_back();
    emitted_[at] = index;
    for (int s = 0; s < n; ++s)
      if (inner[s]) slots[s].child = appendNode(children[s], wide);
    writeSlots(slots, n, wide[index]);
    return index;
  }

  const Bvh4NodeArray& nodes_;
  const Bvh8CollapsePlan& plan_;
  /// Per part, three per BVH4 node in the plan's order: the index of its wide node once
  /// appended, else kInvalidId.
  std::vector<std::uint32_t> emitted_;
};

/// BVH4 levels whose subtrees Bvh8CollapsePlan::solveTree solves as parallel tasks.
constexpr int kParallelLevels = 3;

}  // namespace

Bvh8CollapsePlan::Bvh8CollapsePlan() : vectorSolve_(cpuRunsSolveAvx2()) {}

void Bvh8CollapsePlan::setVectorSolve(bool on) {
  vectorSolve_ = on && cpuRunsSolveAvx2();
}

Bvh8CollapsePlan::~Bvh8CollapsePlan() {
  release();
}

void Bvh8CollapsePlan::release() {
  for (std::size_t b = 0; b < blockCount_; ++b) delete blocks_[b].load(std::memory_order_relaxed);
  blocks_.reset();
  blockCount_ = 0;
}

void Bvh8CollapsePlan::reset(std::size_t maxNodes) {
  release();
  blockCount_ = (maxNodes + kNodesPerBlock - 1) / kNodesPerBlock;
  blocks_ = std::make_unique<std::atomic<Block*>[]>(blockCount_);
  for (std::size_t b = 0; b < blockCount_; ++b)
    blocks_[b].store(nullptr, std::memory_order_relaxed);
}

void Bvh8CollapsePlan::nodeBuilt(const Bvh4NodeArray& nodes, std::uint32_t index) {
  std::atomic<Block*>& block = blocks_[index / kNodesPerBlock];
  if (block.load(std::memory_order_acquire) == nullptr) {
    // Two threads may solve the first nodes of one block at once: one allocation wins.
    auto* fresh = new Block;
    Block* expected = nullptr;
    if (!block.compare_exchange_strong(expected, fresh, std::memory_order_acq_rel)) delete fresh;
  }
  PlanSolver(nodes, *this).solveNode(index);
}

void Bvh8CollapsePlan::solveTree(const Bvh4NodeArray& nodes) {
  reset(nodes.size());
  if (!nodes.empty()) solveSubtree(nodes, 0, 0);
}

void Bvh8CollapsePlan::solveSubtree(const Bvh4NodeArray& nodes, std::uint32_t index, int depth) {
  const Bvh4Node& n = nodes[index];
  std::uint32_t inner[4];
  int count = 0;
  for (int s = 0; s < 4; ++s)
    if (n.isInner(s)) inner[count++] = n.child[s];
  // The subtrees of the first levels share no parts: they are solved side by side.
  if (depth < kParallelLevels && count > 1) {
    tbb::parallel_for(0, count, [&](int k) { solveSubtree(nodes, inner[k], depth + 1); });
  } else {
    for (int k = 0; k < count; ++k) solveSubtree(nodes, inner[k], depth + 1);
  }
  nodeBuilt(nodes, index);
}

void buildBvh8(const Bvh4NodeArray& nodes, const Bvh8CollapsePlan& plan, Bvh8NodeArray& wide,
               std::vector<Bvh8Entry>* entries) {
  wide.clear();
  if (entries != nullptr) entries->clear();
  if (nodes.empty()) return;
  wide.reserve(nodes.size());
  WideCollapse(nodes, plan).append(wide, entries);
  // A static tree is kept for many frames: hold what it uses.
  wide.shrink_to_fit();
}

void buildBvh8(const Bvh4NodeArray& nodes, Bvh8NodeArray& wide, std::vector<Bvh8Entry>* entries) {
  Bvh8CollapsePlan plan;
  plan.solveTree(nodes);
  buildBvh8(nodes, plan, wide, entries);
}

void buildBvh8BelowRoot(const Bvh4NodeArray& nodes, Bvh4Node& root, Bvh8NodeArray& wide) {
  wide.clear();
  if (nodes.empty()) return;
  root = nodes[0];
  wide.reserve(nodes.size());
  for (int s = 0; s < 4; ++s)
    if (root.isInner(s)) root.child[s] = appendWideNode(nodes, root.child[s], wide);
}

}  // namespace tg::detail
