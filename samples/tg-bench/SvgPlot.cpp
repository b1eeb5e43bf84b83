#include "SvgPlot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace tg::bench {
namespace {

constexpr double kWidth = 720, kHeight = 460;
constexpr double kLeft = 80, kRight = 200, kTop = 40, kBottom = 60;
const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

/// One axis: maps data values to [0, 1] and proposes tick values.
struct Axis {
  bool log = false;
  double floor = 0.1;
  double lo = 0.0, hi = 1.0;  ///< in transformed units (log10 for log axes)

  double transform(double v) const { return log ? std::log10(v > 0.0 ? v : floor) : v; }
  void fit(const std::vector<double>& values) {
    double a = std::numeric_limits<double>::infinity(), b = -a;
    for (const double v : values) {
      a = std::min(a, transform(v));
      b = std::max(b, transform(v));
    }
    if (!(a <= b)) a = 0.0, b = 1.0;
    if (log) {
      lo = std::floor(a);
      hi = std::ceil(b);
      if (hi <= lo) hi = lo + 1.0;
    } else {
      const double pad = (b - a) * 0.05 + (b == a ? 1.0 : 0.0);
      lo = std::min(0.0, a - pad);
      hi = b + pad;
    }
  }
  double unit(double v) const { return (transform(v) - lo) / (hi - lo); }
  std::vector<double> ticks() const {
    std::vector<double> t;
    if (log) {
      for (double e = lo; e <= hi + 1e-9; e += 1.0) t.push_back(std::pow(10.0, e));
    } else {
      for (int i = 0; i <= 5; ++i) t.push_back(lo + (hi - lo) * i / 5.0);
    }
    return t;
  }
};

}  // namespace

bool writeSvg(const Plot& plot, const std::string& path) {
  std::vector<double> xs, ys;
  for (const PlotSeries& s : plot.series)
    for (const auto& [x, y] : s.points) xs.push_back(x), ys.push_back(y);
  Axis ax{plot.logX, plot.logFloor}, ay{plot.logY, plot.logFloor};
  ax.fit(xs);
  ay.fit(ys);
  const double w = kWidth - kLeft - kRight, h = kHeight - kTop - kBottom;
  const auto px = [&](double x) { return kLeft + ax.unit(x) * w; };
  const auto py = [&](double y) { return kTop + (1.0 - ay.unit(y)) * h; };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << kLeft << "\" y=\"24\" font-size=\"15\">" << escape(plot.title)
      << "</text>\n";
  // Grid and ticks.
  for (const double t : ax.ticks()) {
    const double x = px(t);
    svg << "<line x1=\"" << x << "\" y1=\"" << kTop << "\" x2=\"" << x << "\" y2=\"" << kTop + h
        << "\" stroke=\"#ddd\"/>\n<text x=\"" << x << "\" y=\"" << kTop + h + 16
        << "\" text-anchor=\"middle\">" << number(t) << "</text>\n";
  }
  for (const double t : ay.ticks()) {
    const double y = py(t);
    svg << "<line x1=\"" << kLeft << "\" y1=\"" << y << "\" x2=\"" << kLeft + w << "\" y2=\"" << y
        << "\" stroke=\"#ddd\"/>\n<text x=\"" << kLeft - 6 << "\" y=\"" << y + 4
        << "\" text-anchor=\"end\">" << number(t) << "</text>\n";
  }
  svg << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << w << "\" height=\"" << h
      << "\" fill=\"none\" stroke=\"black\"/>\n"
      << "<text x=\"" << kLeft + w / 2 << "\" y=\"" << kHeight - 18 << "\" text-anchor=\"middle\">"
      << escape(plot.xLabel) << "</text>\n"
      << "<text transform=\"translate(18," << kTop + h / 2
      << ") rotate(-90)\" text-anchor=\"middle\">" << escape(plot.yLabel) << "</text>\n";
  // Series and legend.
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[i];
    const char* colour = kColours[i % std::size(kColours)];
    if (s.line && s.points.size() > 1) {
      svg << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.5\" points=\"";
      for (const auto& [x, y] : s.points) svg << px(x) << ',' << py(y) << ' ';
      svg << "\"/>\n";
    }
    for (const auto& [x, y] : s.points)
      svg << "<circle cx=\"" << px(x) << "\" cy=\"" << py(y) << "\" r=\"3.5\" fill=\""
          << (s.hollow ? "white" : colour) << "\" stroke=\"" << colour << "\"/>\n";
    const double ly = kTop + 14.0 + 18.0 * static_cast<double>(i);
    svg << "<circle cx=\"" << kLeft + w + 16 << "\" cy=\"" << ly - 4 << "\" r=\"4\" fill=\""
        << (s.hollow ? "white" : colour) << "\" stroke=\"" << colour << "\"/>\n<text x=\""
        << kLeft + w + 26 << "\" y=\"" << ly << "\">" << escape(s.name) << "</text>\n";
  }
  svg << "</svg>\n";
  std::ofstream out(path);
  out << svg.str();
  return static_cast<bool>(out);
}

}  // namespace tg::bench
