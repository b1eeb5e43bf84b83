/// @file SvgPlot.h
/// A minimal SVG scatter/line plot writer for the benchmark report: axes with linear or
/// logarithmic scales, points, lines and a legend. No dependency beyond the standard library.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace tg::bench {

struct PlotSeries {
  std::string name;
  std::vector<std::pair<double, double>> points;  ///< (x, y), plotted in this order
  bool line = true;                               ///< connect the points
  bool hollow = false;                            ///< open markers (e.g. quoted figures)
};

struct Plot {
  std::string title;
  std::string xLabel, yLabel;
  bool logX = false, logY = false;
  /// On a log axis, values <= 0 are drawn at this value (e.g. "0 errors" at 0.1).
  double logFloor = 0.1;
  std::vector<PlotSeries> series;
};

/// Writes `plot` as a standalone SVG document; returns false when the file cannot be written.
bool writeSvg(const Plot& plot, const std::string& path);

}  // namespace tg::bench
