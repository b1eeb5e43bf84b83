/// @file Variants.h
/// The implementation choices the accuracy suite and the report compare, each in one small
/// table so that a new engine (a BVH, a packet path) is one line here, not a change in every
/// suite.
#pragma once

#include <string>
#include <vector>

#include "tracegraph/backend/Scene.h"

namespace tg::bench {

/// One object-accelerator configuration of Tracegraph.
struct AccelVariant {
  std::string name;  ///< row suffix, e.g. "sah-kd"
  SceneOptions options;
};

/// Every object accelerator the backend offers, the high-quality one first, each under the top
/// level of its own engine. Both the static and the deforming slot get the same kind, so a
/// scene is traced by that kind alone.
inline std::vector<AccelVariant> accelVariants() {
  const auto only = [](AccelKind kind, Engine engine) {
    SceneOptions o = sceneOptionsFor(engine);
    o.staticAccel = kind;
    o.deformingAccel = kind;
    return o;
  };
  return {
      {"sah-kd", only(AccelKind::SahKdTree, Engine::KdTree)},
      {"fast-kd", only(AccelKind::FastKdTree, Engine::KdTree)},
      {"bvh", only(AccelKind::Bvh, Engine::Bvh)},
      {"bvh-fast", only(AccelKind::BvhFast, Engine::Bvh)},
  };
}

/// How a secondary ray's origin is moved off the surface it leaves.
enum class OffsetKind {
  Scaled,   ///< refineHitPoint + spawnRay: scales with the hit point's magnitude
  Epsilon,  ///< o + t d, then a fixed 1e-4 along the normal (the classic epsilon)
  None,     ///< o + t d as computed: what happens without any care
};

struct OffsetVariant {
  std::string name;
  OffsetKind kind;
};

/// The fixed epsilon of OffsetKind::Epsilon, in world units.
inline constexpr float kFixedEpsilon = 1e-4f;

inline std::vector<OffsetVariant> offsetVariants() {
  return {{"scaled-offset", OffsetKind::Scaled},
          {"epsilon-1e-4", OffsetKind::Epsilon},
          {"no-offset", OffsetKind::None}};
}

}  // namespace tg::bench
