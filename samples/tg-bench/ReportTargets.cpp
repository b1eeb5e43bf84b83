#include "ReportTargets.h"

#include <algorithm>
#include <set>
#include <string>

#include "ReportFormat.h"

namespace tg::bench {
namespace {

/// One table line: measure, ours, Embree, ratio, target, met.
struct Line {
  std::string measure, ours, embree, ratio, target, met;
};

std::string verdict(bool met) {
  return met ? "yes" : "**no**";
}

/// The cases of `rows` in first-seen order.
std::vector<std::string> casesOf(const std::vector<const BenchRow*>& rows) {
  std::vector<std::string> out;
  for (const BenchRow* r : rows)
    if (std::find(out.begin(), out.end(), r->caseName) == out.end()) out.push_back(r->caseName);
  return out;
}

const BenchRow* rowOf(const std::vector<const BenchRow*>& rows, const std::string& caseName,
                      const std::string& impl) {
  for (const BenchRow* r : rows)
    if (r->caseName == caseName && r->impl == impl) return r;
  return nullptr;
}

/// Row 1: our top-level builds against embree-medium at 661 instances and the largest count
/// (the issue asks for half of Embree's time).
void toplevel(const std::vector<const BenchRow*>& rows, std::vector<Line>& out) {
  std::set<double> counts;
  for (const BenchRow* r : rows) counts.insert(std::stod(r->caseName));
  if (counts.empty()) return;
  std::set<double> shown = {*counts.rbegin()};
  if (counts.count(661)) shown.insert(661);
  for (const double n : shown) {
    const std::string caseName = fmt(n) + " instances";
    const BenchRow* peer = rowOf(rows, caseName, "embree-medium");
    for (const char* impl : {"tracegraph-kd", "tracegraph-bvh"}) {
      const BenchRow* r = rowOf(rows, caseName, impl);
      const auto ratio = r ? real(*r, "vs_embree_medium") : std::nullopt;
      if (!r || !peer || !ratio) continue;
      out.push_back({"1. top-level rebuild, " + caseName + ", " + impl, figure(r, "ms"),
                     "medium " + figure(peer, "ms"), fmt(*ratio) + " (time)", "<= 0.5",
                     verdict(*ratio <= 0.5)});
    }
  }
}

/// Row 2: static build time and trace speed against embree-medium.
void staticBuild(const std::vector<const BenchRow*>& rows, std::vector<Line>& out) {
  for (const std::string& c : casesOf(rows)) {
    const BenchRow* medium = rowOf(rows, c, "embree-medium");
    const BenchRow* high = rowOf(rows, c, "embree-high");
    for (const char* impl : {"tracegraph-bvh", "tracegraph-sah-kd"}) {
      const BenchRow* r = rowOf(rows, c, impl);
      const auto build = r ? real(*r, "build_vs_embree_medium") : std::nullopt;
      const auto trace = r ? real(*r, "trace_vs_embree_medium") : std::nullopt;
      if (!r || !medium || !build || !trace) continue;
      out.push_back(
          {"2. " + shortCase(c) + ", " + impl,
           "build " + figure(r, "ms") + ", " + figure(r, "mrays"),
           "medium: build " + figure(medium, "ms") + ", " + figure(medium, "mrays") +
               (high ? "; high: build " + figure(high, "ms") + ", " + figure(high, "mrays") : ""),
           "build " + fmt(*build) + ", trace " + fmt(*trace), "build <= 1 at trace >= 1",
           verdict(*build <= 1.0 && *trace >= 1.0)});
    }
  }
}

/// Row 3: instanced / flattened trace time per engine, Embree's beside it.
void overhead(const std::vector<const BenchRow*>& rows, std::vector<Line>& out) {
  for (const std::string& c : casesOf(rows)) {
    const BenchRow* peer = rowOf(rows, c, "embree-high instanced");
    const auto peerRatio = peer ? real(*peer, "instanced_over_flattened") : std::nullopt;
    for (const char* impl : {"tracegraph-bvh", "tracegraph-kd"}) {
      const BenchRow* r = rowOf(rows, c, std::string(impl) + " instanced");
      const BenchRow* flat = rowOf(rows, c, std::string(impl) + " flattened");
      const auto ratio = r ? real(*r, "instanced_over_flattened") : std::nullopt;
      if (!r || !flat || !ratio) continue;
      out.push_back({"3. " + shortCase(c) + ", " + impl,
                     "instanced " + figure(r, "mrays") + ", flattened " + figure(flat, "mrays"),
                     peerRatio ? "high: instanced/flattened " + fmt(*peerRatio) : "-",
                     fmt(*ratio) + " (instanced/flattened time)", "<= 1.10",
                     verdict(*ratio <= 1.10)});
    }
  }
}

/// Row 4: speedup from 1 thread to the run's thread count, Embree's beside it.
void scaling(const std::vector<const BenchRow*>& rows, std::vector<Line>& out) {
  const BenchRow* peer = nullptr;
  for (const BenchRow* r : rows)
    if (r->impl == "embree-intersect1" && real(*r, "speedup")) peer = r;
  for (const BenchRow* r : rows) {
    const auto speedup = real(*r, "speedup");
    const auto threads = real(*r, "trace_threads");
    if (r->impl.rfind("tracegraph", 0) != 0 || !speedup || !threads) continue;
    // 1.9 on 2 threads: 95 % of linear scaling.
    const double target = 0.95 * *threads;
    out.push_back({"4. " + shortCase(r->caseName) + ", " + r->impl,
                   figure(r, "mrays") + ", speedup " + fmt(*speedup),
                   peer ? figure(peer, "mrays") + ", speedup " + fmt(*real(*peer, "speedup")) : "-",
                   figure(r, "speedup_vs_embree") + " (speedup ours/Embree)",
                   "speedup >= " + fmt(target), verdict(*speedup >= target)});
  }
}

/// Row 5: bytes per triangle against embree-medium (no target set; low and refit beside it).
void memory(const std::vector<const BenchRow*>& rows, std::vector<Line>& out) {
  for (const std::string& c : casesOf(rows)) {
    std::string embree;
    for (const char* impl : {"embree-medium", "embree-low", "embree-refit", "embree-high"})
      if (const BenchRow* p = rowOf(rows, c, impl))
        embree += (embree.empty() ? "" : "; ") + std::string(impl).substr(7) + " " +
                  figure(p, "bytes_per_triangle");
    for (const BenchRow* r : rows) {
      if (r->caseName != c || r->impl.rfind("tracegraph", 0) != 0) continue;
      out.push_back({"5. " + shortCase(c) + ", " + r->impl,
                     figure(r, "bytes_per_triangle") + " B/triangle", embree + " B/triangle",
                     figure(r, "bytes_vs_embree_medium") + " (bytes, against medium)", "none set",
                     "-"});
    }
  }
}

/// Throughput ratio ours / peer of two rows of one case, as a line with target ">= 1".
void throughputLine(const std::string& label, const BenchRow* r, const BenchRow* peer,
                    std::vector<Line>& out) {
  if (!r || !peer || !r->mraysPerS || !peer->mraysPerS || !(*peer->mraysPerS > 0.0)) return;
  const double ratio = *r->mraysPerS / *peer->mraysPerS;
  out.push_back({label + ", " + r->impl, figure(r, "mrays"),
                 peer->impl + " " + figure(peer, "mrays"), fmt(ratio) + " (throughput)", ">= 1",
                 verdict(ratio >= 1.0)});
}

/// The faster (by throughput) of Embree's row `query` (HIGH build) and its MEDIUM row, when
/// the run has them: the peer is Embree at its better build quality for the case.
const BenchRow* fasterPeer(const std::vector<const BenchRow*>& rows, const std::string& c,
                           const std::string& query) {
  const BenchRow* high = rowOf(rows, c, "embree-" + query);
  const BenchRow* medium = rowOf(rows, c, "embree-medium-" + query);
  if (!high || !high->mraysPerS) return medium;
  if (!medium || !medium->mraysPerS) return high;
  return *medium->mraysPerS > *high->mraysPerS ? medium : high;
}

/// Row 6: single rays against rtcIntersect1/rtcOccluded1, packets against rtcIntersect8, each
/// on Embree's faster build of the case.
void throughput(const std::vector<const BenchRow*>& rows, std::vector<Line>& out) {
  for (const std::string& c : casesOf(rows)) {
    const bool shadow = c.find(" shadow ") != std::string::npos;
    const std::string label = "6. " + shortCase(c);
    const BenchRow* single = fasterPeer(rows, c, shadow ? "occluded1" : "intersect1");
    throughputLine(label, rowOf(rows, c, "tracegraph-bvh"), single, out);
    // Shadow rays without the occluder hint of their neighbours: the walk alone.
    if (shadow) throughputLine(label, rowOf(rows, c, "tracegraph-bvh-unhinted"), single, out);
    throughputLine(label, rowOf(rows, c, "tracegraph-bvh-packets"),
                   shadow ? single : fasterPeer(rows, c, "intersect8"), out);
  }
}

/// Row 7: the deforming rebuild against Embree LOW and the refit against Embree's refit, at
/// the largest triangle count of the run.
void rebuild(const std::vector<const BenchRow*>& rows, std::vector<Line>& out) {
  const std::vector<std::string> cases = casesOf(rows);
  if (cases.empty()) return;
  const std::string c =
      *std::max_element(cases.begin(), cases.end(),
                        [](const auto& a, const auto& b) { return std::stod(a) < std::stod(b); });
  const auto timeLine = [&](const char* impl, const char* peerImpl) {
    const BenchRow* r = rowOf(rows, c, impl);
    const BenchRow* peer = rowOf(rows, c, peerImpl);
    if (!r || !peer || !(peer->timing.medianMs > 0.0)) return;
    const double ratio = r->timing.medianMs / peer->timing.medianMs;
    out.push_back({"7. rebuild, " + c + ", " + impl, figure(r, "ms"),
                   std::string(peerImpl) + " " + figure(peer, "ms"), fmt(ratio) + " (time)", "<= 1",
                   verdict(ratio <= 1.0)});
  };
  timeLine("tracegraph-bvh-fast", "embree-low");
  timeLine("tracegraph-bvh-fast-refit", "embree-refit");
}

/// Row 8: frame rates of the BART kitchen against the absolute targets (no peer).
void frames(const std::vector<const BenchRow*>& rows, std::vector<Line>& out) {
  for (const BenchRow* r : rows) {
    if (r->caseName.find("kitchen") == std::string::npos) continue;
    const auto fps = real(*r, "fps");
    if (!fps) continue;
    const bool whitted = r->impl.find("whitted") != std::string::npos;
    const double target = whitted ? 4.0 : 60.0;
    out.push_back({"8. " + shortCase(r->caseName) + ", " + r->impl, fmt(*fps) + " fps", "-", "-",
                   ">= " + fmt(target) + " fps", verdict(*fps >= target)});
  }
}

}  // namespace

void writeTargets(std::ostream& md, const TopicRows& topicRows) {
  std::vector<Line> lines;
  toplevel(topicRows("toplevel"), lines);
  staticBuild(topicRows("static"), lines);
  overhead(topicRows("overhead"), lines);
  scaling(topicRows("scaling"), lines);
  memory(topicRows("memory"), lines);
  throughput(topicRows("trace"), lines);
  rebuild(topicRows("rebuild"), lines);
  frames(topicRows("frame"), lines);
  md << "## Targets against Embree\n\n"
     << "Each line compares rows of the tables above, measured in this run in the same process "
        "and with the same threads. Ratios of times are ours / Embree's (below 1: ours is "
        "faster); ratios of throughput, speedups and bytes are ours / Embree's. Embree traces "
        "single rays in lines 2-4 (rtcIntersect1), as ours do; line 6 sets our packets "
        "against its 8-wide packets (rtcIntersect8) for primary rays, and every line 6 takes "
        "the faster of Embree's HIGH and MEDIUM builds of the case (the embree- and "
        "embree-medium- rows of the trace tables). Line 8 has no peer: the "
        "frame rates are the issue's absolute targets. A speedup needs idle cores: when "
        "Embree's own speedup is near 1 too, other work held the cores (see the load average "
        "above), and the scaling lines say nothing about our code.\n\n"
     << "| measure | ours | Embree | ratio | target | met |\n|---|---|---|---|---|---|\n";
  for (const Line& l : lines)
    md << "| " << l.measure << " | " << l.ours << " | " << l.embree << " | " << l.ratio << " | "
       << l.target << " | " << l.met << " |\n";
  if (lines.empty()) md << "| not in this run (built without Embree?) | | | | | |\n";
  md << '\n';
}

}  // namespace tg::bench
