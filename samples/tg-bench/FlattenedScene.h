/// @file FlattenedScene.h
/// A BenchScene with every instance moved into world space in one mesh: what a renderer without
/// a two-level structure traces, and the baseline the two-level overhead is measured against.
#pragma once

#include <vector>

#include "BenchScene.h"
#include "HitComparison.h"

namespace tg::bench {

/// Every instance of a scene pre-transformed into one world-space mesh (float positions), and
/// for every flattened triangle the (instance, triangle) it came from.
struct Flattened {
  BenchScene scene;                ///< one mesh under one identity instance
  std::vector<RayOutcome> origin;  ///< per flattened triangle: its instance and triangle
};

/// Flattens `bench`; the scene is named after it with " flattened" appended.
Flattened flatten(const BenchScene& bench);

/// Maps outcomes traced in a flattened scene back to the instanced scene's ids.
void unflatten(const Flattened& flat, std::vector<RayOutcome>& outcomes);

}  // namespace tg::bench
