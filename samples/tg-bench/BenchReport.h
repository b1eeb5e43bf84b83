/// @file BenchReport.h
/// The rows a suite measured, and their two renderings: a human-readable table and the fixed
/// JSON interface read by scripts.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <variant>
#include <vector>

#include "BenchTiming.h"

namespace tg::bench {

/// A suite-specific extra value of a row (JSON allows new fields; existing ones never change).
struct ExtraField {
  std::string key;
  std::variant<std::int64_t, double, std::string> value;
};

/// One measured (case, implementation) pair.
struct BenchRow {
  std::string caseName;  ///< describes the input, e.g. "661 instances"
  std::string impl;      ///< e.g. "tracegraph-kd", "embree-high"
  TimingSummary timing;
  std::optional<double> mraysPerS;  ///< trace suite only
  std::vector<ExtraField> extra;
};

/// Everything one tg-bench run prints.
struct BenchReport {
  std::string suite;
  int threads = 0;
  std::string machine;
  std::vector<BenchRow> rows;
  std::vector<ExtraField> extra;  ///< run-wide extra fields (e.g. the Embree version)
};

/// Writes the report as exactly one JSON object followed by a newline:
/// {"suite", "threads", "machine", "rows": [{"case", "impl", "median_ms", "min_ms", "max_ms",
/// "reps", ["mrays_per_s"], extras...}], extras...}. The key names are a fixed interface.
void writeJson(const BenchReport& report, std::ostream& out);

/// Writes an aligned table. The "ours/row" column divides the median of the first row of the
/// same case (the Tracegraph row every suite emits first) by this row's median: above 1 means
/// this row is faster than ours.
void writeTable(const BenchReport& report, std::ostream& out);

}  // namespace tg::bench
