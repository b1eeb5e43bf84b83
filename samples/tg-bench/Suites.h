/// @file Suites.h
/// The benchmark suites tg-bench runs, their options, and what they return.
#pragma once

#include <algorithm>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "BenchReport.h"
#include "RayGenerators.h"

namespace tg::bench {

/// Options every suite takes.
struct CommonOptions {
  bool json = false;
  int threads = 1;  ///< worker threads for Tracegraph and Embree alike
  int reps = 0;     ///< timed repetitions; 0: the suite's default
  /// Appended to Embree's device configuration (rtcNewDevice), e.g. "tri_accel=bvh4.triangle4"
  /// to trace with its 4-wide BVH, or "isa=avx2": to see where the peer's speed comes from.
  std::string embreeConfig;
  /// Implementations (row names such as tracegraph-bvh-unhinted) to time; empty: all. Suites
  /// that time several rows as one group (trace, static, overhead, scaling) leave out the
  /// others, and with them the ratio fields that need them: for profiling one path without
  /// the rest of the group in the profile.
  std::vector<std::string> rows;

  /// Whether the row of implementation `impl` is to be timed (see rows).
  bool timesRow(const std::string& impl) const {
    return rows.empty() || std::find(rows.begin(), rows.end(), impl) != rows.end();
  }
};

/// Default repetitions of the build suites (toplevel, rebuild, build), of the trace suite and
/// of the load suite.
inline constexpr int kDefaultBuildReps = 11;
inline constexpr int kDefaultTraceReps = 5;
inline constexpr int kDefaultLoadReps = 5;

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
  /// "bounds": a camera outside the scene framing its bounds; "scene": the scene file's own
  /// camera (its first frame), the view a renderer of the file traces.
  std::string view = "bounds";
  /// Trace the scene's triangles flattened into one object without a transform (as `overhead`
  /// compares), the file's camera kept: the walks of one object alone, with no top level.
  bool flatten = false;
};

/// Default repetitions of the sync suite: an edit's sync and a frame step are short, so more
/// samples fit in the time of one build sample.
inline constexpr int kDefaultSyncReps = 31;
/// Default passes of the frame suite over its frames (every frame is one sample).
inline constexpr int kDefaultFramePasses = 1;

/// `sync`: one field edit in synthetic graphs of each size, then frame steps of a scene
/// against a flat Embree LOW rebuild per frame.
struct SyncSuiteOptions {
  std::vector<std::size_t> nodes = {1000, 10000, 100000};  ///< graph sizes, in nodes
  std::optional<std::string> scene;  ///< scene file for loadSceneSource; none: the demo
};

/// `frame`: whole frames (sync + render) per second and rays per second by kind.
struct FrameSuiteOptions {
  std::optional<std::string> scene;  ///< scene file for loadSceneSource; none: the demo
  ImageSize size{640, 480};
  std::vector<std::string> modes = {"opengl", "whitted"};  ///< render modes, one row each
  std::vector<std::string> engines = {"bvh", "kd"};        ///< engines, one row each per mode
  int depth = 3;   ///< Whitted bounces after the primary hit
  int frames = 5;  ///< frames spread evenly over the animation, first and last included
  /// How textures are sampled; rows of other filters than bilinear name it after the mode.
  std::string textureFilter = "bilinear";
};

/// `load`: parsing an .aff/.nff file, converting it to a node graph, and the first sync.
struct LoadOptions {
  std::string scene;
};

/// Each suite measures Tracegraph first (the first row of every case is ours), then the Embree
/// peer when it was compiled in (otherwise a note goes to stderr). The caller fills in
/// BenchReport::machine. Errors in the input (a scene that cannot be loaded) throw tg::Error.
BenchReport runToplevelSuite(const CommonOptions& common, const ToplevelOptions& options);
BenchReport runRebuildSuite(const CommonOptions& common, const RebuildOptions& options);
BenchReport runBuildSuite(const CommonOptions& common, const BuildOptions& options);
BenchReport runTraceSuite(const CommonOptions& common, const TraceOptions& options);
/// Rows tracegraph-aff-parse (parseAffFile), tracegraph-aff-load (loadAff: parse and node
/// graph) and tracegraph-aff-sync (the first SceneGraph::sync at frame 0); no peer rows.
BenchReport runLoadSuite(const CommonOptions& common, const LoadOptions& options);
BenchReport runSyncSuite(const CommonOptions& common, const SyncSuiteOptions& options);
BenchReport runFrameSuite(const CommonOptions& common, const FrameSuiteOptions& options);

/// The scene suites that measure one issue row each against Embree on a scene's primary rays:
/// `static`, `overhead`, `scaling` and `memory` (see their functions).
struct PeerSceneOptions {
  std::string scene;          ///< as for the build and trace suites
  ImageSize size{640, 480};   ///< primary-ray image (not used by `memory`)
  std::size_t judged = 1024;  ///< rays judged by the reference, and pixels of its FLIP grid
  /// "bounds": a camera framing the scene's bounds; "scene": the file's own camera (see
  /// TraceOptions::view). `memory` traces no rays and ignores it.
  std::string view = "bounds";
};

/// `static`: the scene flattened into one static mesh, built from scratch by our static
/// builders (bvh, sah-kd) and Embree (low, medium, high). Each row times the build (median_ms)
/// and carries the trace speed of the structure it built (mrays_per_s: primary rays, median of
/// the trace repetitions; trace_ms) with its error. Our rows add build_vs_embree_medium (build
/// time ratio, target <= 1) and trace_vs_embree_medium (Mrays/s ratio, target >= 1).
BenchReport runStaticBuildSuite(const CommonOptions& common, const PeerSceneOptions& options);

/// `overhead`: primary-ray throughput of the two-level scene (instances as the scene graph
/// produces them) and of the same triangles flattened into one object, per engine and for
/// Embree. Instanced rows add instanced_over_flattened (time ratio, target <= 1.10); ours add
/// time_vs_embree (against Embree's row of the same layout).
BenchReport runOverheadSuite(const CommonOptions& common, const PeerSceneOptions& options);

/// `scaling`: primary-ray throughput with 1 thread and with --threads threads, per engine and
/// for Embree; rows with more than one thread add speedup (1-thread time / this time, target
/// >= 1.9 on 2 threads) and ours speedup_vs_embree.
BenchReport runScalingSuite(const CommonOptions& common, const PeerSceneOptions& options);

/// `memory`: bytes per triangle of every accelerator (BuildStats::bytes) plus the mesh, on the
/// scene flattened into one mesh, beside Embree's low, medium, high and refit builds as its
/// memory monitor counts them. Fields accel_bytes, mesh_bytes, bytes_per_triangle; ours add
/// bytes_vs_embree_medium. median_ms is the build time.
BenchReport runMemorySuite(const CommonOptions& common, const PeerSceneOptions& options);

/// `accuracy`: the hard cases of ../shared/docs/hard-cases.md as measurements judged by the
/// double-precision brute-force reference. Every row carries a time (of the rays it traced) and
/// error fields (leaks_per_1e7, ulp_max, acne_pct, mismatches, ...). The trace suite's and the
/// BART rows' psnr_db is +inf (JSON null) when the images equal the reference's.
struct AccuracyOptions {
  bool quick = false;   ///< smaller meshes, fewer rays and translations
  std::string dataDir;  ///< folder holding bart/; empty: the BART cases are skipped
};
BenchReport runAccuracySuite(const CommonOptions& common, const AccuracyOptions& options);

}  // namespace tg::bench
