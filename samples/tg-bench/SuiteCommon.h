/// @file SuiteCommon.h
/// Small helpers shared by the suite implementations.
#pragma once

#include <cstdint>
#include <string>

#include "BenchReport.h"
#include "Suites.h"

namespace tg::bench {

/// `common.reps`, or `suiteDefault` when the user gave none.
int repsOrDefault(const CommonOptions& common, int suiteDefault);

/// A report with its suite and thread count filled in, recording the peer's version when
/// Embree is compiled in; otherwise prints to stderr that peer rows are skipped.
BenchReport startReport(const std::string& suite, const CommonOptions& common);

/// Appends a row and returns it for adding extra fields.
BenchRow& addRow(BenchReport& report, const std::string& caseName, const std::string& impl,
                 const TimingSummary& timing);

/// Extra fields of a row or report.
ExtraField intField(const std::string& key, std::int64_t value);
ExtraField realField(const std::string& key, double value);
ExtraField textField(const std::string& key, const std::string& value);

/// Progress messages go to stderr, so that stdout holds only the report.
void progress(const std::string& message);

}  // namespace tg::bench
