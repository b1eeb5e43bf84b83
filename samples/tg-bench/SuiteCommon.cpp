#include "SuiteCommon.h"

#include <iostream>

#include "BenchTiming.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {

int repsOrDefault(const CommonOptions& common, int suiteDefault) {
  return common.reps > 0 ? common.reps : suiteDefault;
}

BenchReport startReport(const std::string& suite, const CommonOptions& common) {
  BenchReport report;
  report.suite = suite;
  report.threads = common.threads;
#ifdef TG_HAVE_EMBREE
  report.extra.push_back(textField("embree_version", embreeVersion()));
  if (!common.embreeConfig.empty())
    report.extra.push_back(textField("embree_config", common.embreeConfig));
#else
  std::cerr << "tg-bench: built without Embree; peer rows are skipped\n";
#endif
  return report;
}

BenchRow& addRow(BenchReport& report, const std::string& caseName, const std::string& impl,
                 const TimingSummary& timing) {
  BenchRow row;
  row.caseName = caseName;
  row.impl = impl;
  row.timing = timing;
  report.rows.push_back(std::move(row));
  return report.rows.back();
}

void setRays(BenchRow& row, std::size_t rays) {
  // rays / (ms * 1e-3 s/ms) / 1e6 rays per Mray
  if (row.timing.medianMs > 0.0)
    row.mraysPerS = static_cast<double>(rays) / (row.timing.medianMs * 1e3);
  row.extra.push_back(intField("rays", static_cast<std::int64_t>(rays)));
}

namespace {

/// Calls add(row, partner) for every row and the partner row of its case.
template <typename Add>
void forPartners(BenchReport& report, const PartnerOf& partnerOf, const Add& add) {
  for (BenchRow& row : report.rows) {
    const std::string partner = partnerOf(row);
    if (partner.empty()) continue;
    for (const BenchRow& other : report.rows)
      if (other.impl == partner && other.caseName == row.caseName) add(row, other);
  }
}

PartnerOf peerOfOurs(const std::string& peerImpl) {
  return [peerImpl](const BenchRow& row) {
    return row.impl.rfind("tracegraph", 0) == 0 ? peerImpl : std::string();
  };
}

}  // namespace

void addTimeRatios(BenchReport& report, const PartnerOf& partner, const std::string& key) {
  forPartners(report, partner, [&](BenchRow& row, const BenchRow& other) {
    if (other.timing.medianMs > 0.0)
      row.extra.push_back(realField(key, row.timing.medianMs / other.timing.medianMs));
  });
}

void addTimeRatios(BenchReport& report, const std::string& peerImpl, const std::string& key) {
  addTimeRatios(report, peerOfOurs(peerImpl), key);
}

void addThroughputRatios(BenchReport& report, const std::string& peerImpl, const std::string& key) {
  forPartners(report, peerOfOurs(peerImpl), [&](BenchRow& row, const BenchRow& other) {
    if (row.mraysPerS && other.mraysPerS && *other.mraysPerS > 0.0)
      row.extra.push_back(realField(key, *row.mraysPerS / *other.mraysPerS));
  });
}

ExtraField intField(const std::string& key, std::int64_t value) {
  return {key, value};
}
ExtraField realField(const std::string& key, double value) {
  return {key, value};
}
ExtraField textField(const std::string& key, const std::string& value) {
  return {key, value};
}

void measureRows(BenchReport& report, const CommonOptions& common, int reps,
                 const std::vector<TimedRow>& rows) {
  std::string names;
  std::vector<const TimedRow*> timed;
  std::vector<std::function<double(int)>> samples;
  for (const TimedRow& r : rows) {
    if (!common.timesRow(r.impl)) continue;
    names += (names.empty() ? "" : ", ") + r.impl;
    timed.push_back(&r);
    samples.push_back([&r](int) { return r.sample(); });
  }
  if (timed.empty()) {
    progress(report.suite + ": --rows names none of this suite's rows");
    return;
  }
  progress(report.suite + ": " + std::to_string(reps) + " interleaved rounds of " + names);
  const std::vector<TimingSummary> times = measureInterleaved(reps, samples);
  for (std::size_t i = 0; i < timed.size(); ++i) {
    BenchRow& row = addRow(report, timed[i]->caseName, timed[i]->impl, times[i]);
    if (timed[i]->finish) timed[i]->finish(row);
  }
}

void progress(const std::string& message) {
  std::cerr << "tg-bench: " << message << '\n';
}

}  // namespace tg::bench
