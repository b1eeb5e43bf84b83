// The renderer's index over an instance's material ranges (render/MaterialRangeIndex.h) against
// the binary search it replaces (RenderScene::rangeContaining).
#define BOOST_TEST_MODULE material_range_index
#include <boost/test/unit_test.hpp>

#include <cstdint>
#include <random>
#include <vector>

#include "render/MaterialRangeIndex.h"

using tg::RenderScene;
using tg::detail::MaterialRangeIndex;
using Ranges = std::vector<RenderScene::MaterialRange>;

namespace {

/// Primitives where the two lookups differ, over [0, last + 300) and a few far beyond.
int mismatches(const Ranges& ranges) {
  const MaterialRangeIndex index(ranges);
  int wrong = 0;
  const std::uint32_t end = ranges.back().primBegin + 300;
  const auto check = [&](std::uint32_t p) {
    if (index.find(ranges, p) != RenderScene::rangeContaining(ranges, p)) ++wrong;
  };
  for (std::uint32_t p = 0; p < end; ++p) check(p);
  for (std::uint32_t p : {0x7FFFFFFFu, 0xFFFFFFFEu, 0xFFFFFFFFu}) check(p);
  return wrong;
}

}  // namespace

BOOST_AUTO_TEST_CASE(finds_the_ranges_the_binary_search_finds) {
  // One range, ranges of one primitive, empty ranges (equal starts), a first range that starts
  // after 0, and a range starting at the last representable primitive.
  BOOST_TEST(mismatches({{0, 5}}) == 0);
  BOOST_TEST(mismatches({{0, 1}, {1, 2}, {2, 3}, {3, 4}}) == 0);
  BOOST_TEST(mismatches({{0, 1}, {10, 2}, {10, 3}, {10, 4}, {11, 5}}) == 0);
  BOOST_TEST(mismatches({{7, 1}, {9, 2}, {500, 3}}) == 0);
  const MaterialRangeIndex far({{0, 1}, {0xFFFFFFFFu, 2}});
  const Ranges farRanges{{0, 1}, {0xFFFFFFFFu, 2}};
  BOOST_TEST(far.find(farRanges, 0xFFFFFFFEu) == 0u);
  BOOST_TEST(far.find(farRanges, 0xFFFFFFFFu) == 1u);

  std::mt19937 rng(20261127);
  for (int trial = 0; trial < 200; ++trial) {
    Ranges ranges;
    std::uint32_t start = std::uniform_int_distribution<std::uint32_t>(0, 3)(rng) == 0 ? 5 : 0;
    const int count = std::uniform_int_distribution<int>(1, 80)(rng);
    for (int k = 0; k < count; ++k) {
      ranges.push_back({start, static_cast<std::uint32_t>(k)});
      // Mostly short ranges, some long ones, some empty.
      const int kind = std::uniform_int_distribution<int>(0, 9)(rng);
      start += kind == 0  ? 0
               : kind < 8 ? std::uniform_int_distribution<std::uint32_t>(1, 40)(rng)
                          : std::uniform_int_distribution<std::uint32_t>(100, 3000)(rng);
    }
    BOOST_TEST(mismatches(ranges) == 0, "trial " << trial);
  }
}
