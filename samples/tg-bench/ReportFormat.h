/// @file ReportFormat.h
/// Reading rows and writing their figures for the markdown report (ReportSuite, ReportTargets).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "BenchReport.h"

namespace tg::bench {

/// The extra field `key` of a row, or null.
const ExtraField* field(const BenchRow& row, const std::string& key);
/// A numeric extra field as a double, or nothing (absent or text).
std::optional<double> real(const BenchRow& row, const std::string& key);

/// A number for a table: counts exact, others to `digits` significant digits, tiny and huge
/// ones in exponent form, infinities as "inf".
std::string fmt(double v, int digits = 3);
/// Milliseconds with a precision that suits their size.
std::string ms(double v);

/// A case name with every file path shortened to the file's name.
std::string shortCase(const std::string& caseName);

/// The first row whose case contains `casePart` and whose impl is `impl`, or null.
const BenchRow* findRow(const std::vector<const BenchRow*>& rows, const std::string& casePart,
                        const std::string& impl);

/// A row's figure for a table cell: "mrays" (Mrays/s), "ms" (median) or an extra field;
/// "not in this run" for a null row, "-" for a missing figure.
std::string figure(const BenchRow* r, const std::string& key);

}  // namespace tg::bench
