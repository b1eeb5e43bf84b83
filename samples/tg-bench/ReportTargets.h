/// @file ReportTargets.h
/// The report's table of the targets set against Embree: the top-level rebuild, the static
/// build, the two-level overhead, thread scaling and memory per triangle, each from rows of the
/// same run.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "BenchReport.h"

namespace tg::bench {

/// The rows one suite produced in this run (empty when it did not run).
using TopicRows = std::function<std::vector<const BenchRow*>(const std::string& suite)>;

/// Writes the "Targets against Embree" section: one line per measure with ours, Embree's
/// figure, their ratio, the target and whether this run met it.
void writeTargets(std::ostream& md, const TopicRows& topicRows);

}  // namespace tg::bench
