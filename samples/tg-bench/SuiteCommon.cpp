#include "SuiteCommon.h"

#include <iostream>

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

ExtraField intField(const std::string& key, std::int64_t value) {
  return {key, value};
}
ExtraField realField(const std::string& key, double value) {
  return {key, value};
}
ExtraField textField(const std::string& key, const std::string& value) {
  return {key, value};
}

void progress(const std::string& message) {
  std::cerr << "tg-bench: " << message << '\n';
}

}  // namespace tg::bench
