/// @file HitComparison.h
/// Per-ray outcomes of a trace and a cheap accuracy check between two implementations.
#pragma once

#include <cstdint>
#include <span>

#include "tracegraph/backend/Ray.h"

namespace tg::bench {

/// What a closest-hit query reported for one ray: the instance and triangle hit, or kInvalidId
/// for a miss. Instance ids are indices into BenchScene::instances for every implementation.
struct RayOutcome {
  std::uint32_t instance = kInvalidId;
  std::uint32_t prim = kInvalidId;
  bool hit() const { return prim != kInvalidId; }
};

/// Disagreements between two traces of the same rays.
struct MismatchCounts {
  std::size_t hitMiss = 0;  ///< one reports a hit, the other a miss
  std::size_t prim = 0;     ///< both hit, but different (instance, triangle)
};

/// Compares closest-hit outcomes ray by ray (spans of equal length).
MismatchCounts compareOutcomes(std::span<const RayOutcome> a, std::span<const RayOutcome> b);

/// Compares occlusion answers (non-zero = occluded) ray by ray; only MismatchCounts::hitMiss
/// is used.
MismatchCounts compareOcclusion(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b);

}  // namespace tg::bench
