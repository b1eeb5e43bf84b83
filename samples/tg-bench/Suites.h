/// @file Suites.h
/// The benchmark suites tg-bench runs, their options, and what they return.
#pragma once

#include <cstddef>
#include <string>

#include "BenchReport.h"
#include "RayGenerators.h"

namespace tg::bench {

/// Options every suite takes.
struct CommonOptions {
  bool json = false;
  int threads = 1;  ///< worker threads for Tracegraph and Embree alike
  int reps = 0;     ///< timed repetitions; 0: the suite's default
};

/// Default repetitions of the build suites (toplevel, rebuild, build) and of the trace suite.
inline constexpr int kDefaultBuildReps = 11;
inline constexpr int kDefaultTraceReps = 5;

/// `toplevel`: rebuild of the top-level structure over N moving instances.
struct ToplevelOptions {
  std::size_t instances = 661;  ///< the paper's figure
};

/// `rebuild`: from-scratch build over N random triangles, as for a deforming object.
struct RebuildOptions {
  std::size_t triangles = 65536;
};

/// `build`: building every object of a scene.
struct BuildOptions {
  std::string scene;
};

/// `trace`: throughput of primary or shadow rays.
struct TraceOptions {
  std::string scene;
  std::string rays = "primary";  ///< "primary" or "shadow"
  ImageSize size;
};

/// Each suite measures Tracegraph first (the first row of every case is ours), then the Embree
/// peer when it was compiled in (otherwise a note goes to stderr). The caller fills in
/// BenchReport::machine. Errors in the input (a scene that cannot be loaded) throw tg::Error.
BenchReport runToplevelSuite(const CommonOptions& common, const ToplevelOptions& options);
BenchReport runRebuildSuite(const CommonOptions& common, const RebuildOptions& options);
BenchReport runBuildSuite(const CommonOptions& common, const BuildOptions& options);
BenchReport runTraceSuite(const CommonOptions& common, const TraceOptions& options);

}  // namespace tg::bench
