// The report: one command runs every suite (build, toplevel, rebuild, trace, frame, sync, load)
// and the accuracy harness, then writes REPORT.md with one table per topic -- every speed row
// beside its error -- the plots, and the raw rows of every suite as JSON lines. All figures
// come from measurements of this run.
#include "ReportSuite.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <tuple>

#include "MachineInfo.h"
#include "ReportFormat.h"
#include "ReportTargets.h"
#include "SuiteCommon.h"
#include "SvgPlot.h"
#include "tracegraph/backend/Error.h"

namespace tg::bench {
namespace {

/// What one run measures: --quick keeps every topic but shrinks sizes and repetitions.
struct Plan {
  int buildReps, traceReps;
  std::vector<std::size_t> instances, triangles;
  std::vector<std::string> buildScenes;
  /// Trace cases: scene, rays ("primary"/"shadow"), view ("bounds"/"scene").
  std::vector<std::tuple<std::string, std::string, std::string>> traces;
  ImageSize traceSize, frameSize;
  std::vector<std::optional<std::string>> frameScenes;
  int frames;
  std::vector<std::size_t> syncNodes;
  std::optional<std::string> syncScene;
  std::vector<std::string> loadScenes;
  /// The scene suites against Embree (static, overhead, scaling, memory).
  std::vector<std::string> staticScenes, overheadScenes, scalingScenes, memoryScenes;
  ImageSize peerSize;
  std::size_t peerJudged;
};

Plan makePlan(bool quick, const std::string& data) {
  const std::string kitchen = data + "/bart/kitchen/aff/kitchen.aff";
  const std::string robots = data + "/bart/robots/aff/Robot.aff";
  const std::string museum = data + "/bart/museum/aff/museum5.aff";
  const auto have = [](const std::string& p) { return std::filesystem::exists(p); };
  Plan p;
  if (quick) {
    p.buildReps = 3;
    p.traceReps = 1;
    p.instances = {64, 661, 4096};
    p.triangles = {64, 1024, 16384};
    p.buildScenes = {"builtin:sphereflake:2"};
    p.traces = {{"builtin:sphereflake:2", "primary", "bounds"},
                {"builtin:sphereflake:2", "shadow", "bounds"}};
    p.traceSize = {128, 96};
    p.frameSize = {64, 48};
    p.frameScenes = {std::nullopt};
    p.frames = 2;
    p.syncNodes = {1000};
    p.instances.push_back(16384);
    // The scene rows against Embree on small built-in scenes: the BART scenes' brute-force
    // reference and builds would take minutes here.
    p.staticScenes = {"builtin:sphereflake:2"};
    p.overheadScenes = {"builtin:sphereflake:2"};
    p.scalingScenes = {"builtin:sphereflake:2"};
    p.memoryScenes = {"builtin:sphereflake:2", "builtin:random:16384"};
    p.peerSize = {96, 72};
    p.peerJudged = 256;
    if (have(museum)) {
      p.buildScenes.push_back(museum);
      p.traces.push_back({museum, "primary", "bounds"});
      p.loadScenes = {museum};
    }
#ifdef TG_BENCH_SANITIZED
    p.buildReps = 1;
    p.instances = {64, 661};
    p.triangles = {64, 1024};
    p.traceSize = {48, 32};
    p.frameSize = {32, 24};
    p.peerSize = {32, 24};
    p.peerJudged = 64;
    p.memoryScenes = {"builtin:sphereflake:1", "builtin:random:1024"};
#endif
    return p;
  }
  p.buildReps = 11;
  p.traceReps = 5;
  p.instances = {64, 161, 661, 2048, 8192, 32768, 100000};
  p.triangles = {64, 256, 1024, 4096, 16384, 65536};
  p.buildScenes = {"builtin:sphereflake"};
  p.traces = {{"builtin:sphereflake", "primary", "bounds"},
              {"builtin:sphereflake", "shadow", "bounds"}};
  p.traceSize = {640, 480};
  p.frameSize = {640, 480};
  p.frameScenes = {std::nullopt};
  p.frames = 5;
  p.syncNodes = {1000, 10000, 100000};
  for (const std::string& s : {kitchen, robots, museum}) {
    if (!have(s)) continue;
    p.buildScenes.push_back(s);
    p.traces.push_back({s, "primary", "bounds"});
    p.loadScenes.push_back(s);
  }
  // Shadow rays of the two scenes the shadow target names.
  for (const std::string& s : {kitchen, robots})
    if (have(s)) p.traces.push_back({s, "shadow", "bounds"});
  // The view a frame of the file traces, from inside the scene: the camera framing the bounds
  // sees the scene from outside, where most rays stop early or miss.
  for (const std::string& s : {kitchen, robots})
    if (have(s)) p.traces.push_back({s, "primary", "scene"});
  for (const std::string& s : {kitchen, robots})
    if (have(s)) p.traces.push_back({s, "shadow", "scene"});
  if (have(kitchen)) p.frameScenes.push_back(kitchen);
  if (have(robots)) p.frameScenes.push_back(robots), p.syncScene = robots;
  const std::string staticScene = have(kitchen) ? kitchen : "builtin:sphereflake";
  p.staticScenes = {staticScene};
  p.overheadScenes = {staticScene};
  if (have(robots)) p.overheadScenes.push_back(robots);
  p.scalingScenes = {staticScene};
  p.memoryScenes = {staticScene, "builtin:random:65536"};
  p.peerSize = {640, 480};
  p.peerJudged = 1024;
  return p;
}

// ---------------------------------------------------------------------------------------------
// Formatting

/// The error figures of a row, in words. Rows that time builds or graph work without tracing
/// say so; no row is left without an entry.
std::string errorCell(const BenchRow& row) {
  std::vector<std::string> parts;
  const auto add = [&](const std::string& key, const std::function<std::string(double)>& f) {
    if (const auto v = real(row, key)) parts.push_back(f(*v));
  };
  add("leaks_per_1e7", [&](double v) {
    return "leaks " + fmt(v) + " /1e7 (" + fmt(*real(row, "leaks")) + " of " +
           fmt(*real(row, "rays")) + ")";
  });
  add("ulp_max", [&](double v) {
    return "t err " + fmt(v) + " ulp max, " + fmt(*real(row, "ulp_median")) + " median (" +
           fmt(*real(row, "t_compared")) + " rays)";
  });
  add("mismatches", [&](double v) {
    return "ref mismatches " + fmt(v) + "/" + fmt(real(row, "judged").value_or(0)) +
           (real(row, "ambiguous").value_or(0) > 0
                ? " (+" + fmt(*real(row, "ambiguous")) + " ambiguous)"
                : "");
  });
  add("ref_mismatches", [&](double v) {
    return "ref mismatches " + fmt(v) + "/" + fmt(real(row, "judged").value_or(0));
  });
  add("prim_mismatches", [](double v) { return "prim ids differing from ours " + fmt(v); });
  add("hit_mismatches", [](double v) { return "hit/miss differing from ours " + fmt(v); });
  add("psnr_db", [](double v) { return "eye-light PSNR " + fmt(v) + " dB"; });
  add("flip_mean", [](double v) { return "FLIP " + fmt(v); });
  add("acne_pct", [](double v) { return "acne " + fmt(v) + " %"; });
  add("smallest_correct_gap", [&](double v) {
    std::string s = "smallest correct gap " + (v > 0.0 ? fmt(v) : std::string("none")) +
                    ", light leaking at contact " + fmt(*real(row, "contact_leak_pct")) + " %;";
    for (const ExtraField& f : row.extra)
      if (f.key.rfind("wrong_pct_gap_", 0) == 0)
        s += " " + f.key.substr(14) + ": " + fmt(*real(row, f.key)) + " %";
    return s;
  });
  add("exit_fail_pct", [](double v) { return "failed exits " + fmt(v) + " %"; });
  add("differing", [](double v) { return "differing answers " + fmt(v); });
  add("threads_diff_values", [](double v) { return "values differing 1 vs N threads " + fmt(v); });
  add("psnr_vs_16spp_db",
      [](double v) { return "PSNR against 4x4 samples/pixel " + fmt(v) + " dB"; });
  if (parts.empty()) {
    if (real(row, "bytes_per_triangle"))
      return "n/a: memory of a structure built, not traced (" +
             fmt(*real(row, "bytes_per_triangle")) + " B/triangle)";
    if (row.impl.rfind("embree", 0) == 0) return "n/a: peer structure built, not traced";
    if (row.impl.find("-build") != std::string::npos)
      return "n/a: same builder as the " + row.impl.substr(0, row.impl.size() - 6) + " row";
    return "n/a: no rays traced (graph/parse time)";
  }
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : "; ") + p;
  return out;
}

std::string throughputCell(const BenchRow& row) {
  std::string out;
  if (const auto fps = real(row, "fps")) out = fmt(*fps) + " fps";
  if (row.mraysPerS) out += (out.empty() ? "" : ", ") + fmt(*row.mraysPerS) + " Mrays/s";
  return out.empty() ? "-" : out;
}

void writeTable(std::ostream& md, const std::vector<const BenchRow*>& rows) {
  md << "| case | impl | median ms | min-max ms | reps | throughput | ours/row | error |\n"
     << "|---|---|---:|---:|---:|---:|---:|---|\n";
  std::map<std::string, double> first;
  for (const BenchRow* r : rows) {
    const double ours = first.emplace(r->caseName, r->timing.medianMs).first->second;
    md << "| " << shortCase(r->caseName) << " | " << r->impl << " | " << ms(r->timing.medianMs)
       << " | " << ms(r->timing.minMs) << "-" << ms(r->timing.maxMs) << " | " << r->timing.reps
       << " | " << throughputCell(*r) << " | "
       << (r->timing.medianMs > 0.0 ? fmt(ours / r->timing.medianMs) : "-") << " | "
       << errorCell(*r) << " |\n";
  }
  md << '\n';
}

std::vector<const BenchRow*> rowsOf(const std::vector<BenchReport>& reports) {
  std::vector<const BenchRow*> out;
  for (const BenchReport& r : reports)
    for (const BenchRow& row : r.rows) out.push_back(&row);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Plots

/// Errors per 10^7 rays of a row that traced rays, if it reports any.
std::optional<double> errorRate(const BenchRow& row) {
  if (const auto v = real(row, "leaks_per_1e7")) return v;
  if (const auto v = real(row, "acne_pct")) return *v * 1e5;
  if (const auto v = real(row, "exit_fail_pct")) return *v * 1e5;
  const auto judged = real(row, "judged");
  if (!judged || *judged <= 0) return std::nullopt;
  const auto m = real(row, "mismatches") ? real(row, "mismatches") : real(row, "ref_mismatches");
  if (!m) return std::nullopt;
  return *m / *judged * 1e7;
}

std::string family(const std::string& impl) {
  if (impl.rfind("tracegraph", 0) == 0) return "Tracegraph";
  if (impl.rfind("embree", 0) == 0) return "Embree";
  if (impl.rfind("fan-moller", 0) == 0 || impl.rfind("bruteforce-moller", 0) == 0)
    return "Moller-Trumbore (bench)";
  if (impl.rfind("fan-", 0) == 0 || impl.rfind("bruteforce-", 0) == 0) return "watertight (bench)";
  if (impl == "scaled-offset") return "scaled offset";
  return "epsilon / no offset";
}

void plotSpeedAgainstError(const std::vector<const BenchRow*>& rows, const std::string& path) {
  Plot plot;
  plot.title = "Speed against error (every traced row of this run)";
  plot.xLabel = "Mrays/s";
  plot.yLabel = "errors per 10^7 rays (0 drawn at 0.1)";
  plot.logX = plot.logY = true;
  std::map<std::string, PlotSeries> byFamily;
  for (const BenchRow* r : rows) {
    const auto e = errorRate(*r);
    if (!r->mraysPerS || !e || *r->mraysPerS <= 0.0) continue;
    PlotSeries& s = byFamily[family(r->impl)];
    s.name = family(r->impl);
    s.line = false;
    s.points.push_back({*r->mraysPerS, *e});
  }
  for (auto& [name, s] : byFamily) plot.series.push_back(std::move(s));
  writeSvg(plot, path);
}

/// Median ms against a size parsed from the case name ("661 instances"), one line per impl.
void plotScaling(const std::vector<const BenchRow*>& rows, const std::string& title,
                 const std::string& xLabel, const std::string& path) {
  Plot plot;
  plot.title = title;
  plot.xLabel = xLabel;
  plot.yLabel = "median ms";
  plot.logX = plot.logY = true;
  std::map<std::string, PlotSeries> byImpl;
  for (const BenchRow* r : rows) {
    if (r->impl.find("-build") != std::string::npos) continue;
    PlotSeries& s = byImpl[r->impl];
    s.name = r->impl;
    s.points.push_back({std::stod(r->caseName), r->timing.medianMs});
  }
  for (auto& [name, s] : byImpl) plot.series.push_back(std::move(s));
  writeSvg(plot, path);
}

// ---------------------------------------------------------------------------------------------

std::string runCommand(const std::string& command) {
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, pipe)) out += buf;
    pclose(pipe);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out.empty() ? "unknown" : out;
}

/// The 1-, 5- and 15-minute load averages, or "unknown": speedups and throughput on a shared
/// machine are only as good as the idle cores they had.
std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c)) return "unknown";
  return fmt(a, 2) + ", " + fmt(b, 2) + ", " + fmt(c, 2);
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
  return buf;
}

}  // namespace

int runReport(const CommonOptions& common, const ReportOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string loadAtStart = loadAverage();
  std::filesystem::create_directories(options.outDir);
  const Plan plan = makePlan(options.quick, options.dataDir);
  CommonOptions suiteCommon = common;
  suiteCommon.json = true;

  struct Topic {
    std::string title, suite, blurb;
    std::vector<BenchReport> reports;
    std::vector<std::string> failures;
  };
  std::vector<Topic> topics;
  bool failed = false;
  const auto run = [&](Topic& topic, const std::function<BenchReport()>& suite) {
    try {
      BenchReport r = suite();
      r.machine = machineDescription();
      topic.reports.push_back(std::move(r));
    } catch (const std::exception& e) {
      topic.failures.push_back(e.what());
      progress(std::string("report: suite failed: ") + e.what());
      failed = true;
    }
  };

  {
    Topic t{"Top-level rebuild",
            "toplevel",
            "Rebuild of the top-level structure after every instance moved (the paper's per-frame "
            "cost), against Embree's top-level builds and refit.",
            {},
            {}};
    suiteCommon.reps = plan.buildReps;
    for (const std::size_t n : plan.instances)
      run(t, [&] { return runToplevelSuite(suiteCommon, ToplevelOptions{n}); });
    topics.push_back(std::move(t));
  }
  {
    Topic t{"Object rebuild",
            "rebuild",
            "From-scratch build of a deforming object of N triangles (the paper's fast kd-tree and "
            "our SAH build), against Embree's builders and refit.",
            {},
            {}};
    suiteCommon.reps = plan.buildReps;
    for (const std::size_t n : plan.triangles)
      run(t, [&] { return runRebuildSuite(suiteCommon, RebuildOptions{n}); });
    topics.push_back(std::move(t));
  }
  {
    Topic t{"Scene build",
            "build",
            "Building every object and the top level of a whole scene.",
            {},
            {}};
    suiteCommon.reps = std::max(1, plan.buildReps / 2);
    for (const std::string& s : plan.buildScenes)
      run(t, [&] { return runBuildSuite(suiteCommon, BuildOptions{s}); });
    topics.push_back(std::move(t));
  }
  {
    Topic t{"Ray throughput",
            "trace",
            "Closest-hit (primary) and any-hit (shadow) rays; Tracegraph traces single rays and "
            "8-wide packets (whose answers must equal the single rays': single_ray_mismatches): "
            "tracegraph-bvh-packets walks each two neighbouring packets as one where the active "
            "kernels can (16 lanes per node test with AVX-512; shadow packets with AVX2 too), "
            "tracegraph-bvh-packets8 every packet alone. Embree traces single rays (intersect1) "
            "and 8-wide and 16-wide packets (intersect8 over 4x2 pixel blocks, intersect16 over "
            "4x4). Our any-hit queries first test the triangle that blocked the previous ray of "
            "the same context (neighbouring shadow rays share blockers); tracegraph-bvh-unhinted "
            "traces every shadow ray as if alone, the walk without that hint.",
            {},
            {}};
    suiteCommon.reps = plan.traceReps;
    for (const auto& [scene, rays, view] : plan.traces)
      run(t, [&] {
        return runTraceSuite(suiteCommon, TraceOptions{scene, rays, plan.traceSize, view});
      });
    topics.push_back(std::move(t));
  }
  {
    // The scene suites against Embree: one topic each, every scene of the plan one report.
    using PeerSuite = BenchReport (*)(const CommonOptions&, const PeerSceneOptions&);
    struct PeerTopic {
      const char* title;
      const char* suite;
      const char* blurb;
      const std::vector<std::string>* scenes;
      PeerSuite runSuite;
      int reps;
    };
    const int buildReps = std::max(1, plan.buildReps / 2);
    const PeerTopic peerTopics[] = {
        {"Static build against Embree", "static",
         "A whole static scene flattened into one mesh, built from scratch by our static "
         "builders and by Embree; *median ms* is the build, *throughput* the primary rays of the "
         "structure built (single rays for both), *error* that trace's.",
         // The static build's target compares two medians a few percent apart: the full build
         // count (11 in a full report), not the memory suite's half, whose medians of five moved
         // from run to run by more than that gap.
         &plan.staticScenes, runStaticBuildSuite, plan.buildReps},
        {"Two-level overhead", "overhead",
         "Primary rays through the scene as the scene graph instances it and through the same "
         "triangles flattened into one object, per engine and for Embree (high quality).",
         &plan.overheadScenes, runOverheadSuite, plan.traceReps},
        {"Thread scaling", "scaling",
         "Primary-ray throughput on 1 thread and on the run's threads (task arenas of each size "
         "over the same structures), per engine and for Embree.",
         &plan.scalingScenes, runScalingSuite, plan.traceReps},
        {"Memory per triangle", "memory",
         "Accelerator and mesh bytes per triangle of every accelerator (BuildStats::bytes) and "
         "of Embree's builds (its memory-monitor callback), the scene flattened into one mesh; "
         "*median ms* is the build.",
         &plan.memoryScenes, runMemorySuite, buildReps},
    };
    for (const PeerTopic& p : peerTopics) {
      Topic t{p.title, p.suite, p.blurb, {}, {}};
      suiteCommon.reps = p.reps;
      for (const std::string& s : *p.scenes)
        run(t, [&] { return p.runSuite(suiteCommon, {s, plan.peerSize, plan.peerJudged}); });
      topics.push_back(std::move(t));
    }
  }
  {
    Topic t{"Frames",
            "frame",
            "Whole animation frames (animators, sync, rebuilds, render) as tg-render runs them.",
            {},
            {}};
    suiteCommon.reps = 1;
    for (const auto& scene : plan.frameScenes) {
      FrameSuiteOptions f;
      f.scene = scene;
      f.size = plan.frameSize;
      f.frames = plan.frames;
      run(t, [&] { return runFrameSuite(suiteCommon, f); });
      // The BART scenes' textures once more through mip-mapped lookups: speed against aliasing.
      if (scene) {
        f.modes = {"opengl"};
        f.engines = {"bvh"};
        f.textureFilter = "trilinear";
        run(t, [&] { return runFrameSuite(suiteCommon, f); });
      }
    }
    topics.push_back(std::move(t));
  }
  {
    Topic t{"Scene-graph sync",
            "sync",
            "Sync after one field edit in graphs of N nodes, and whole frame steps against a flat "
            "Embree rebuild per frame.",
            {},
            {}};
    suiteCommon.reps = options.quick ? 5 : kDefaultSyncReps;
    SyncSuiteOptions s;
    s.nodes = plan.syncNodes;
    s.scene = plan.syncScene;
    run(t, [&] { return runSyncSuite(suiteCommon, s); });
    topics.push_back(std::move(t));
  }
  {
    Topic t{
        "Loading", "load", "Parsing, node-graph conversion and first sync of BART files.", {}, {}};
    suiteCommon.reps = options.quick ? 1 : 3;
    for (const std::string& s : plan.loadScenes)
      run(t, [&] { return runLoadSuite(suiteCommon, LoadOptions{s}); });
    topics.push_back(std::move(t));
  }
  {
    Topic t{"Accuracy",
            "accuracy",
            "The hard cases of docs/hard-cases.md measured against the double-precision "
            "brute-force reference; every row also times the rays it traced.",
            {},
            {}};
    suiteCommon.reps = 0;
    run(t, [&] {
      return runAccuracySuite(suiteCommon, AccuracyOptions{options.quick, options.dataDir});
    });
    topics.push_back(std::move(t));
  }

  const double minutes =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 60.0;
  const std::string dir = options.outDir;
  {
    std::ofstream jsonl(dir + "/report.jsonl");
    for (const Topic& t : topics)
      for (const BenchReport& r : t.reports) writeJson(r, jsonl);
  }

  std::vector<const BenchRow*> all;
  for (const Topic& t : topics)
    for (const BenchRow* r : rowsOf(t.reports)) all.push_back(r);
  const auto topicRows = [&](const std::string& suite) {
    for (const Topic& t : topics)
      if (t.suite == suite) return rowsOf(t.reports);
    return std::vector<const BenchRow*>{};
  };
  plotSpeedAgainstError(all, dir + "/speed-vs-error.svg");
  plotScaling(topicRows("rebuild"), "Object rebuild time against triangle count", "triangles",
              dir + "/rebuild.svg");
  plotScaling(topicRows("toplevel"), "Top-level rebuild time against instance count", "instances",
              dir + "/toplevel.svg");

  std::ofstream md(dir + "/REPORT.md");
  std::string embree = "not compiled in";
  for (const Topic& t : topics)
    for (const BenchReport& r : t.reports)
      for (const ExtraField& f : r.extra)
        if (f.key == "embree_version") embree = std::get<std::string>(f.value);
  md << "# Tracegraph: speed against error\n\n"
     << "| | |\n|---|---|\n"
     << "| run | " << (options.quick ? "`tg-bench report --quick`" : "`tg-bench report`") << ", "
     << utcNow() << ", " << fmt(minutes) << " min |\n"
     << "| commit | "
     << runCommand("git -C \"" TG_BENCH_SOURCE_DIR "\" rev-parse --short HEAD 2>/dev/null")
     << " |\n"
     << "| machine | " << machineDescription() << " |\n"
     << "| threads | " << common.threads << " (Tracegraph and Embree alike) |\n"
     << "| load average | " << loadAtStart << " at the start, " << loadAverage()
     << " at the end (1, 5, 15 min) |\n"
     << "| peer | Embree " << embree
     << (common.embreeConfig.empty() ? std::string()
                                     : ", device configured with `" + common.embreeConfig + "`")
     << ", in the same process and run |\n\n"
     << "Every figure below was measured in this run. Columns: *median ms* of the timed "
        "repetitions (after one untimed warm-up; the traces of the trace, static, overhead and "
        "scaling tables in interleaved rounds, every row once per round right after an "
        "untimed trace of its own), *throughput* in "
        "Mrays/s or frames/s, "
        "*ours/row* = Tracegraph's median / this row's median (above 1: this row is faster), "
        "and *error*: what the same structures answered wrong, judged by a double-precision "
        "brute-force reference (`ReferenceIntersector`), never by the code under test. "
        "*ref mismatches a/b*: a of b judged rays differ from the reference where the "
        "reference is unambiguous. *Eye-light PSNR*: |cos| shading of the primary hits "
        "against the reference's (inf: identical). *FLIP*: mean perceptual error (0: "
        "identical, 1: largest) of the eye-light image against the reference's, on a regular "
        "grid of the image's pixels (`FlipMetric.h`; PSNR counts every wrong pixel alike, FLIP "
        "weighs what a viewer would notice). *PSNR against 4x4 samples/pixel* (frames): the "
        "last frame against the same frame rendered 4 x 4 times larger and averaged per "
        "pixel, linear values clamped to [0, 1]: what one sample per pixel loses to "
        "aliasing.\n\n";

  md << "## Contents\n\n";
  for (const Topic& t : topics) md << "- " << t.title << " (`" << t.suite << "`)\n";
  md << "- Variants compared\n- Targets against Embree\n- The 2003 paper beside ours\n- "
        "Plots\n\n";

  for (const Topic& t : topics) {
    md << "## " << t.title << "\n\n" << t.blurb << "\n\n";
    for (const std::string& f : t.failures) md << "**Suite failed:** " << f << "\n\n";
    if (t.suite == "accuracy") {
      // One table per hard case: the case names start with "<topic>:".
      std::vector<std::string> order;
      std::map<std::string, std::vector<const BenchRow*>> groups;
      for (const BenchRow* r : rowsOf(t.reports)) {
        const std::string key = r->caseName.substr(0, r->caseName.find(':'));
        if (!groups.count(key)) order.push_back(key);
        groups[key].push_back(r);
      }
      for (const std::string& key : order) {
        md << "### " << key << "\n\n";
        writeTable(md, groups[key]);
      }
    } else {
      writeTable(md, rowsOf(t.reports));
    }
  }

  // What each implementation choice buys and costs, pulled from the rows above.
  md << "## Variants compared\n\n"
     << "| choice | figure | A | B |\n|---|---|---|---|\n";
  const auto line = [&](const std::string& choice, const std::string& what, const std::string& a,
                        const std::string& b) {
    md << "| " << choice << " | " << what << " | " << a << " | " << b << " |\n";
  };
  const BenchRow* wt = findRow(all, "leaks: icosphere", "fan-watertight");
  const BenchRow* mt = findRow(all, "leaks: icosphere", "fan-moller-trumbore-f32");
  line("A watertight vs B Moller-Trumbore (f32)", "leaks per 1e7 vertex/edge rays, icosphere",
       figure(wt, "leaks_per_1e7"), figure(mt, "leaks_per_1e7"));
  line("A watertight vs B Moller-Trumbore (f32)", "fan tests, Mrays/s", figure(wt, "mrays"),
       figure(mt, "mrays"));
  const std::vector<std::string> bartCases = {"BART ids: kitchen", "BART ids: robots",
                                              "BART ids: museum"};
  for (const std::string& c : bartCases) {
    line("A SAH kd-tree vs B fast kd-tree", c + " primary, Mrays/s",
         figure(findRow(all, c, "tracegraph-sah-kd"), "mrays"),
         figure(findRow(all, c, "tracegraph-fast-kd"), "mrays"));
    line("A instanced vs B flattened (two-level overhead)", c + " primary, Mrays/s",
         figure(findRow(all, c, "tracegraph-sah-kd"), "mrays"),
         figure(findRow(all, c, "tracegraph-sah-kd flattened"), "mrays"));
    line("A single rays vs B packets of 8 (Embree)", c + " primary, Mrays/s",
         figure(findRow(all, c, "embree-intersect1"), "mrays"),
         figure(findRow(all, c, "embree-intersect8"), "mrays"));
  }
  // Tracegraph's own packets: the same rays and structures as its single rays, in the trace
  // topic; their answers equal the single rays' (single_ray_mismatches).
  const std::vector<const BenchRow*> traceRows = topicRows("trace");
  for (const char* c :
       {"kitchen.aff primary", "Robot.aff primary", "kitchen.aff shadow", "Robot.aff shadow"}) {
    const BenchRow* single = findRow(traceRows, c, "tracegraph-bvh");
    const BenchRow* packets = findRow(traceRows, c, "tracegraph-bvh-packets");
    if (!single || !packets) continue;
    line("A single rays vs B packets of 8 (Tracegraph BVH)", std::string(c) + ", Mrays/s",
         figure(single, "mrays"), figure(packets, "mrays"));
    line("A single rays vs B packets of 8 (Tracegraph BVH)",
         std::string(c) + ", reference mismatches / answers differing from single rays",
         figure(single, "ref_mismatches"),
         figure(packets, "ref_mismatches") + " / " + figure(packets, "single_ray_mismatches"));
    line("A kd-tree engine vs B BVH engine", std::string(c) + ", Mrays/s",
         figure(findRow(traceRows, c, "tracegraph-kd"), "mrays"), figure(single, "mrays"));
  }
  line("A single rays vs B packets of 8 (Tracegraph BVH)",
       "leaks per 1e7 vertex/edge rays, icosphere",
       figure(findRow(all, "leaks: icosphere", "tracegraph-bvh"), "leaks_per_1e7"),
       figure(findRow(all, "leaks: icosphere", "tracegraph-bvh-packets"), "leaks_per_1e7"));
  line("A instanced vs B flattened", "t error (max ulp) at translation 1e2",
       figure(findRow(all, "t error: translation 1e2", "tracegraph-sah-kd instanced"), "ulp_max"),
       figure(findRow(all, "t error: translation 1e2", "tracegraph-sah-kd flattened"), "ulp_max"));
  line("A double vs B float reference (brute force, flattened)", "t error (median ulp) at 1e0",
       figure(findRow(all, "t error: translation 1e0", "bruteforce-moller-trumbore-f64 flattened"),
              "ulp_median"),
       figure(findRow(all, "t error: translation 1e0", "bruteforce-moller-trumbore-f32 flattened"),
              "ulp_median"));
  line("A instanced vs B flattened", "t error (max ulp) at translation 1e6",
       figure(findRow(all, "t error: translation 1e6", "tracegraph-sah-kd instanced"), "ulp_max"),
       figure(findRow(all, "t error: translation 1e6", "tracegraph-sah-kd flattened"), "ulp_max"));
  line("A scaled offset vs B fixed epsilon 1e-4", "acne % at translation 1e6",
       figure(findRow(all, "acne: plane at 1e6", "scaled-offset"), "acne_pct"),
       figure(findRow(all, "acne: plane at 1e6", "epsilon-1e-4"), "acne_pct"));
  line("A scaled offset vs B fixed epsilon 1e-4", "smallest correct contact gap",
       figure(findRow(all, "contact shadows", "scaled-offset"), "smallest_correct_gap"),
       figure(findRow(all, "contact shadows", "epsilon-1e-4"), "smallest_correct_gap"));
  line("A scaled offset vs B fixed epsilon 1e-4", "failed exits %, slab 1e-5 thick",
       figure(findRow(all, "thin glass: slab 1e-5", "scaled-offset"), "exit_fail_pct"),
       figure(findRow(all, "thin glass: slab 1e-5", "epsilon-1e-4"), "exit_fail_pct"));
  md << "\nThe variant lists live in `samples/tg-bench/Variants.h`.\n\n";
  writeTargets(md, topicRows);

  md << "## The 2003 paper beside ours\n\n"
     << "Wald, Benthin and Slusallek (2003) measured on 2003 hardware (single CPUs for builds, a "
        "cluster of PCs for frames). Only statements we are sure of are quoted, and labelled "
        "approximate; exact figures of the paper are not reproduced here.\n\n"
     << "| measure | 2003 paper (approximate) | this run |\n|---|---|---|\n";
  md << "| top-level rebuild, 161 instances | well under a frame's time on one 2003 CPU "
        "(approximate) | "
     << figure(findRow(all, "161 instances", "tracegraph-kd"), "ms") << " |\n"
     << "| top-level rebuild, 661 instances | 4 ms | Algorithm 1: "
     << figure(findRow(all, "661 instances", "tracegraph-kd"), "ms")
     << "; BVH: " << figure(findRow(all, "661 instances", "tracegraph-bvh"), "ms") << " |\n";
  for (const std::size_t n : {64, 1024, 16384, 65536})
    md << "| rebuild of a deforming object, " << n
       << " triangles (fast kd-tree; the museum's range) | the paper measures this range; "
       << "figures not quoted | "
       << figure(findRow(all, std::to_string(n) + " triangles", "tracegraph-fast-kd"), "ms")
       << " |\n";
  for (const char* scene : {"kitchen", "Robot"}) {
    for (const char* engine : {"bvh", "kd"}) {
      const BenchRow* r = nullptr;
      for (const BenchRow* row : topicRows("frame"))
        if (row->caseName.find(scene) != std::string::npos &&
            row->impl == std::string("tracegraph-") + engine + "-whitted")
          r = row;
      md << "| " << scene << " frame rate, Whitted, " << engine
         << " engine | about 4 fps with shadows and reflections on 32 CPUs | "
         << (r ? fmt(*real(*r, "fps")) + " fps on " + std::to_string(common.threads) + " threads"
               : std::string("not in this run"))
         << " |\n";
    }
  }
  for (const std::string& c : bartCases) {
    const BenchRow* a = findRow(all, c, "tracegraph-sah-kd");
    const BenchRow* b = findRow(all, c, "tracegraph-sah-kd flattened");
    md << "| two-level overhead, " << c << " | the paper reports the cost of the two levels; "
       << "figures not quoted | "
       << (a && b && a->mraysPerS && b->mraysPerS
               ? "instanced/flattened throughput " + fmt(*a->mraysPerS / *b->mraysPerS)
               : std::string("not in this run"))
       << " |\n";
  }
  for (const BenchRow* r : topicRows("overhead"))
    if (const auto ratio = real(*r, "instanced_over_flattened"))
      md << "| " << shortCase(r->caseName) << ", " << r->impl
         << " | the two levels trade some traversal cost for a cheap per-frame update (the "
            "paper's design); no figure of the paper quoted | instanced/flattened time "
         << fmt(*ratio) << " |\n";
  md << "\n## Plots\n\n"
     << "![Mrays/s against error](speed-vs-error.svg)\n\n"
     << "![Rebuild time against triangle count](rebuild.svg)\n\n"
     << "![Top-level time against instance count](toplevel.svg)\n\n"
     << "The rebuild plot carries no 2003 points: the paper's rebuild times per triangle "
        "count could not be checked against its text (table and section), and unverified "
        "figures are not drawn. The top-level plot runs up to "
     << fmt(static_cast<double>(plan.instances.back())) << " instances.\n";
  md.close();
  std::cout << dir << "/REPORT.md\n";
  return failed || !md ? 1 : 0;
}

}  // namespace tg::bench
