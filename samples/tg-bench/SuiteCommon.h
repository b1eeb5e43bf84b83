/// @file SuiteCommon.h
/// Small helpers shared by the suite implementations.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

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

/// A row timed in one group with others (measureRows).
struct TimedRow {
  std::string caseName;  ///< the row's case
  std::string impl;      ///< the row's implementation
  /// One repetition; returns the milliseconds it measured itself (setup stays outside).
  std::function<double()> sample;
  /// Adds the row's fields once every row of the group is timed; may be empty.
  std::function<void(BenchRow&)> finish;
};

/// Times `rows` in interleaved rounds (measureInterleaved: `reps` rounds, each row sampled once
/// per round right after an untimed sample of its own), then appends them to `report` in order
/// and calls their finish.
/// Rows compared with each other (ours and the peer's, one thread and two) are timed in one
/// group, so that their ratio is not the machine's drift between them. Rows `common` does not
/// time (CommonOptions::rows) are neither timed nor added.
void measureRows(BenchReport& report, const CommonOptions& common, int reps,
                 const std::vector<TimedRow>& rows);

/// Sets the row's Mrays/s from `rays` traced in its median time and records the ray count
/// (field "rays").
void setRays(BenchRow& row, std::size_t rays);

/// Names the row a row is compared with (same case), or "" for none.
using PartnerOf = std::function<std::string(const BenchRow&)>;

/// Adds `key` = this row's median / its partner's median to every row that has a partner row
/// of the same case: below 1, this row is faster.
void addTimeRatios(BenchReport& report, const PartnerOf& partner, const std::string& key);

/// The same with the `peerImpl` row as the partner of every Tracegraph row (impl starting with
/// "tracegraph").
void addTimeRatios(BenchReport& report, const std::string& peerImpl, const std::string& key);

/// Adds `key` = this row's Mrays/s / the peer row's Mrays/s to every Tracegraph row of a case
/// that has a row of `peerImpl` (both traced): above 1, ours traces faster.
void addThroughputRatios(BenchReport& report, const std::string& peerImpl, const std::string& key);

/// Extra fields of a row or report.
ExtraField intField(const std::string& key, std::int64_t value);
ExtraField realField(const std::string& key, double value);
ExtraField textField(const std::string& key, const std::string& value);

/// Progress messages go to stderr, so that stdout holds only the report.
void progress(const std::string& message);

}  // namespace tg::bench
