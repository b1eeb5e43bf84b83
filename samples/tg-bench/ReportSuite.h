/// @file ReportSuite.h
/// `tg-bench report`: runs every suite and the accuracy harness in one process and writes the
/// speed-against-error report (markdown, SVG plots, and every suite's JSON).
#pragma once

#include <string>

#include "Suites.h"

namespace tg::bench {

struct ReportOptions {
  bool quick = false;   ///< small sizes: a few minutes, for CI
  std::string outDir;   ///< where REPORT.md, the plots and report.jsonl go
  std::string dataDir;  ///< folder holding bart/; scenes missing there are skipped
};

/// Runs the report; returns the process exit code (0 when every suite ran, 1 when one failed:
/// its section then says why). Progress goes to stderr, the report's path to stdout.
int runReport(const CommonOptions& common, const ReportOptions& options);

}  // namespace tg::bench
