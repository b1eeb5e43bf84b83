#include "ReportFormat.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace tg::bench {

const ExtraField* field(const BenchRow& row, const std::string& key) {
  for (const ExtraField& f : row.extra)
    if (f.key == key) return &f;
  return nullptr;
}

std::optional<double> real(const BenchRow& row, const std::string& key) {
  const ExtraField* f = field(row, key);
  if (!f) return std::nullopt;
  if (const auto* i = std::get_if<std::int64_t>(&f->value)) return static_cast<double>(*i);
  if (const auto* d = std::get_if<double>(&f->value)) return *d;
  return std::nullopt;
}

std::string fmt(double v, int digits) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[48];
  if (v == std::floor(v) && std::abs(v) < 1e9) {
    std::snprintf(buf, sizeof buf, "%.0f", v);  // counts stay exact
    return buf;
  }
  if (v != 0.0 && (std::abs(v) >= 1e6 || std::abs(v) < 1e-3))
    std::snprintf(buf, sizeof buf, "%.2e", v);
  else
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string ms(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, v < 1.0 ? "%.4f" : (v < 100.0 ? "%.3f" : "%.1f"), v);
  return buf;
}

std::string shortCase(const std::string& caseName) {
  std::istringstream words(caseName);
  std::string word, out;
  while (words >> word) {
    const std::size_t slash = word.rfind('/');
    if (!out.empty()) out.push_back(' ');
    out.append(slash == std::string::npos ? word : word.substr(slash + 1));
  }
  return out;
}

const BenchRow* findRow(const std::vector<const BenchRow*>& rows, const std::string& casePart,
                        const std::string& impl) {
  for (const BenchRow* r : rows)
    if (r->caseName.find(casePart) != std::string::npos && r->impl == impl) return r;
  return nullptr;
}

std::string figure(const BenchRow* r, const std::string& key) {
  if (!r) return "not in this run";
  if (key == "mrays") return r->mraysPerS ? fmt(*r->mraysPerS) + " Mrays/s" : "-";
  if (key == "ms") return ms(r->timing.medianMs) + " ms";
  const auto v = real(*r, key);
  return v ? fmt(*v) : "-";
}

}  // namespace tg::bench
