// tg-bench: measures Tracegraph's builders and traversal against Embree.
//
//   tg-bench <suite> [options] [--json] [--threads N] [--reps R]
//
// Suites: toplevel, rebuild, build, trace, sync, frame, load, accuracy, static, overhead,
// scaling, memory (see Suites.h); `report`
// runs them all and writes a markdown report (ReportSuite.h). stdout holds only
// the report (a table, or with --json exactly one JSON object); progress and notes go to
// stderr. Exit codes: 0 success, 1 bad input (e.g. a scene that cannot be loaded), 2 bad
// command line.
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "BenchReport.h"
#include "MachineInfo.h"
#include "RayGenerators.h"
#include "ReportSuite.h"
#include "Suites.h"
#include "tracegraph/backend/Error.h"

namespace {

using namespace tg::bench;

void addCommonOptions(CLI::App& sub, CommonOptions& common) {
  sub.add_flag("--json", common.json, "Print one JSON object instead of a table");
  sub.add_option("--threads", common.threads,
                 "Worker threads for Tracegraph and Embree (default: hardware threads)")
      ->check(CLI::Range(1, 4096));
  sub.add_option("--reps", common.reps,
                 "Timed repetitions, reported as median/min/max (default: 11 for builds, 5 for "
                 "trace, 31 for sync; frame: passes over its frames, default 1)")
      ->check(CLI::Range(1, 100000));
  sub.add_option("--embree-config", common.embreeConfig,
                 "Appended to Embree's device configuration, e.g. tri_accel=bvh4.triangle4 "
                 "(its 4-wide BVH) or isa=avx2; the peer rows then measure that Embree");
}

/// Accepts what parseImageSize accepts.
CLI::Validator imageSizeValidator() {
  return CLI::Validator(
      [](std::string& text) {
        ImageSize size;
        return parseImageSize(text, size) ? std::string() : "expected WxH with 1 <= W, H <= 16384";
      },
      "WxH");
}

/// --scene, --size and --judged of the scene suites against Embree.
void addPeerSceneOptions(CLI::App& sub, PeerSceneOptions& options, std::string& sizeText,
                         const std::string& sceneHelp) {
  sub.add_option("--scene", options.scene, sceneHelp)->required();
  sub.add_option("--size", sizeText, "Primary-ray image size WxH")
      ->check(imageSizeValidator())
      ->capture_default_str();
  sub.add_option("--judged", options.judged,
                 "Rays judged by the brute-force reference (and pixels of its FLIP image)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1'000'000}))
      ->capture_default_str();
  sub.add_option("--view", options.view,
                 "Primary rays from a camera framing the scene's bounds, or from the scene "
                 "file's own camera (.aff/.nff with a viewpoint)")
      ->check(CLI::IsMember({"bounds", "scene"}))
      ->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tg-bench: Tracegraph build and trace benchmarks, with Embree as the peer"};
  app.require_subcommand(1, 1);

  CommonOptions common;
  common.threads = hardwareThreads();
  ToplevelOptions toplevel;
  RebuildOptions rebuild;
  BuildOptions build;
  TraceOptions trace;
  LoadOptions load;
  SyncSuiteOptions syncOptions;
  FrameSuiteOptions frameOptions;
  AccuracyOptions accuracy;
  accuracy.dataDir = TG_BENCH_DATA_DIR;

  CLI::App* toplevelCmd =
      app.add_subcommand("toplevel", "Top-level rebuild over N moving instances of a box");
  toplevelCmd->add_option("--instances", toplevel.instances, "Number of instances")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10'000'000}))
      ->capture_default_str();
  addCommonOptions(*toplevelCmd, common);

  CLI::App* rebuildCmd =
      app.add_subcommand("rebuild", "Object rebuild over N random triangles (deforming object)");
  rebuildCmd->add_option("--triangles", rebuild.triangles, "Number of triangles")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100'000'000}))
      ->capture_default_str();
  addCommonOptions(*rebuildCmd, common);

  const std::string sceneHelp =
      "Scene: builtin:sphereflake[:depth], builtin:random:N, or an .aff/.nff file (frame 0)";
  CLI::App* buildCmd = app.add_subcommand("build", "Build every object and the top level");
  buildCmd->add_option("--scene", build.scene, sceneHelp)->required();
  addCommonOptions(*buildCmd, common);

  CLI::App* traceCmd = app.add_subcommand("trace", "Primary or shadow ray throughput");
  traceCmd->add_option("--scene", trace.scene, sceneHelp)->required();
  traceCmd->add_option("--rays", trace.rays, "Ray kind")
      ->check(CLI::IsMember({"primary", "shadow"}))
      ->capture_default_str();
  traceCmd
      ->add_option("--view", trace.view,
                   "Primary rays from a camera framing the scene's bounds, or from the "
                   "scene file's own camera (.aff/.nff with a viewpoint)")
      ->check(CLI::IsMember({"bounds", "scene"}))
      ->capture_default_str();
  traceCmd->add_flag("--flatten", trace.flatten,
                     "Trace the scene's triangles flattened into one object (no top level); "
                     "Embree gets the same single mesh");
  std::string sizeText = "1024x768";
  traceCmd->add_option("--size", sizeText, "Image size WxH")
      ->check(imageSizeValidator())
      ->capture_default_str();
  addCommonOptions(*traceCmd, common);

  // The scene suites against Embree: one options set, a subcommand each.
  PeerSceneOptions peerScene;
  std::string peerSizeText = "640x480";
  CLI::App* staticCmd = app.add_subcommand(
      "static", "Static build of a flattened scene, with the trace speed of what was built");
  CLI::App* overheadCmd = app.add_subcommand(
      "overhead", "Two-level overhead: the scene instanced against the same triangles flattened");
  CLI::App* scalingCmd =
      app.add_subcommand("scaling", "Primary-ray throughput on 1 thread and on --threads threads");
  CLI::App* memoryCmd = app.add_subcommand(
      "memory", "Bytes per triangle of every accelerator and of Embree's builds (flattened scene)");
  for (CLI::App* cmd : {staticCmd, overheadCmd, scalingCmd, memoryCmd}) {
    addPeerSceneOptions(*cmd, peerScene, peerSizeText, sceneHelp);
    addCommonOptions(*cmd, common);
  }
  for (CLI::App* cmd : {traceCmd, staticCmd, overheadCmd, scalingCmd})
    cmd->add_option("--rows", common.rows,
                    "Time only these rows (implementations, comma-separated, e.g. "
                    "tracegraph-bvh-unhinted); the ratio fields that need the others are left "
                    "out. For profiling one path")
        ->delimiter(',');

  CLI::App* loadCmd =
      app.add_subcommand("load", "Parse, node-graph conversion and first sync of a scene file");
  loadCmd->add_option("--scene", load.scene, "Scene file (.aff or .nff)")->required();
  addCommonOptions(*loadCmd, common);

  const std::string graphSceneHelp =
      "Scene file (loaded as tg-render loads it); default: the built-in demo";
  CLI::App* syncCmd = app.add_subcommand(
      "sync",
      "Sync after one field edit in graphs of N nodes, and whole frame steps of a scene "
      "against a flat Embree LOW rebuild");
  syncCmd->add_option("--nodes", syncOptions.nodes, "Graph sizes in nodes, comma-separated")
      ->delimiter(',')
      ->check(CLI::Range(std::size_t{3}, std::size_t{10'000'000}))
      ->capture_default_str();
  syncCmd->add_option("--scene", syncOptions.scene, graphSceneHelp);
  addCommonOptions(*syncCmd, common);

  CLI::App* frameCmd =
      app.add_subcommand("frame", "Whole frames (sync + render): frames/s and rays/s by kind");
  frameCmd->add_option("--scene", frameOptions.scene, graphSceneHelp);
  std::string frameSizeText = "640x480";
  frameCmd->add_option("--size", frameSizeText, "Image size WxH")
      ->check(imageSizeValidator())
      ->capture_default_str();
  std::string frameMode;
  frameCmd->add_option("--mode", frameMode, "Render mode (default: both, one row each)")
      ->check(CLI::IsMember({"opengl", "whitted"}));
  std::string frameEngine;
  frameCmd->add_option("--accel", frameEngine, "Engine (default: both, one row each)")
      ->check(CLI::IsMember({"bvh", "kd"}));
  frameCmd->add_option("--depth", frameOptions.depth, "Whitted bounces after the primary hit")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  frameCmd
      ->add_option("--texture-filter", frameOptions.textureFilter,
                   "Texture lookups, as tg-render's --texture-filter")
      ->check(CLI::IsMember({"nearest", "bilinear", "trilinear"}))
      ->capture_default_str();
  frameCmd
      ->add_option("--frames", frameOptions.frames,
                   "Frames spread evenly over the animation (--reps: passes over them)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  addCommonOptions(*frameCmd, common);

  CLI::App* accuracyCmd = app.add_subcommand(
      "accuracy", "The hard numerical cases measured against the double-precision reference");
  accuracyCmd->add_flag("--quick", accuracy.quick, "Small sizes (a CI smoke run)");
  accuracyCmd->add_option("--data", accuracy.dataDir, "Folder holding bart/ (BART scenes)")
      ->capture_default_str();
  addCommonOptions(*accuracyCmd, common);

  ReportOptions reportOptions;
  reportOptions.dataDir = TG_BENCH_DATA_DIR;
  reportOptions.outDir = "tg-bench-report";
  CLI::App* reportCmd = app.add_subcommand(
      "report",
      "Every suite and the accuracy harness: a markdown report with plots (speed and "
      "error side by side)");
  reportCmd->add_flag("--quick", reportOptions.quick, "Small sizes: a few minutes, for CI");
  reportCmd->add_option("--out", reportOptions.outDir, "Output folder")->capture_default_str();
  reportCmd->add_option("--data", reportOptions.dataDir, "Folder holding bart/ (BART scenes)")
      ->capture_default_str();
  reportCmd
      ->add_option("--threads", common.threads,
                   "Worker threads for Tracegraph and Embree (default: hardware threads)")
      ->check(CLI::Range(1, 4096));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help requests exit 0; every command-line error exits 2.
    return app.exit(e) == 0 ? 0 : 2;
  }
  parseImageSize(sizeText, trace.size);
  parseImageSize(frameSizeText, frameOptions.size);
  parseImageSize(peerSizeText, peerScene.size);
  if (!frameMode.empty()) frameOptions.modes = {frameMode};
  if (!frameEngine.empty()) frameOptions.engines = {frameEngine};

  try {
    // Caps every TBB parallel region in the process, Tracegraph's and Embree's alike.
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(common.threads));
    if (*reportCmd) return runReport(common, reportOptions);
    BenchReport report;
    if (*toplevelCmd) {
      report = runToplevelSuite(common, toplevel);
    } else if (*rebuildCmd) {
      report = runRebuildSuite(common, rebuild);
    } else if (*buildCmd) {
      report = runBuildSuite(common, build);
    } else if (*syncCmd) {
      report = runSyncSuite(common, syncOptions);
    } else if (*frameCmd) {
      report = runFrameSuite(common, frameOptions);
    } else if (*accuracyCmd) {
      report = runAccuracySuite(common, accuracy);
    } else if (*traceCmd) {
      report = runTraceSuite(common, trace);
    } else if (*staticCmd) {
      report = runStaticBuildSuite(common, peerScene);
    } else if (*overheadCmd) {
      report = runOverheadSuite(common, peerScene);
    } else if (*scalingCmd) {
      report = runScalingSuite(common, peerScene);
    } else if (*memoryCmd) {
      report = runMemorySuite(common, peerScene);
    } else {
      report = runLoadSuite(common, load);
    }
    report.machine = machineDescription();
    if (common.json) {
      writeJson(report, std::cout);
    } else {
      writeTable(report, std::cout);
    }
    std::cout.flush();
    return std::cout ? 0 : 1;
  } catch (const tg::Error& e) {
    std::cerr << "tg-bench: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "tg-bench: unexpected failure: " << e.what() << '\n';
    return 1;
  }
}
