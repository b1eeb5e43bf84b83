#include "BenchReport.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "JsonWriter.h"

namespace tg::bench {
namespace {

void writeExtra(JsonWriter& json, const ExtraField& field) {
  json.key(field.key);
  if (const auto* i = std::get_if<std::int64_t>(&field.value)) {
    json.integer(*i);
  } else if (const auto* d = std::get_if<double>(&field.value)) {
    json.number(*d);
  } else {
    json.string(std::get<std::string>(field.value));
  }
}

std::string formatFixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

/// Milliseconds with about four significant digits, whatever their magnitude.
std::string formatMs(double ms) {
  if (ms >= 100.0) return formatFixed(ms, 1);
  if (ms >= 1.0) return formatFixed(ms, 3);
  return formatFixed(ms, 4);
}

std::string formatExtra(const ExtraField& field) {
  std::string text = field.key + "=";
  if (const auto* i = std::get_if<std::int64_t>(&field.value)) {
    text += std::to_string(*i);
  } else if (const auto* d = std::get_if<double>(&field.value)) {
    text += formatFixed(*d, 3);
  } else {
    text += std::get<std::string>(field.value);
  }
  return text;
}

}  // namespace

void writeJson(const BenchReport& report, std::ostream& out) {
  JsonWriter json(out);
  json.beginObject();
  json.key("suite");
  json.string(report.suite);
  json.key("threads");
  json.integer(report.threads);
  json.key("machine");
  json.string(report.machine);
  json.key("rows");
  json.beginArray();
  for (const BenchRow& row : report.rows) {
    json.beginObject();
    json.key("case");
    json.string(row.caseName);
    json.key("impl");
    json.string(row.impl);
    json.key("median_ms");
    json.number(row.timing.medianMs);
    json.key("min_ms");
    json.number(row.timing.minMs);
    json.key("max_ms");
    json.number(row.timing.maxMs);
    json.key("reps");
    json.integer(row.timing.reps);
    if (row.mraysPerS) {
      json.key("mrays_per_s");
      json.number(*row.mraysPerS);
    }
    for (const ExtraField& field : row.extra) writeExtra(json, field);
    json.endObject();
  }
  json.endArray();
  for (const ExtraField& field : report.extra) writeExtra(json, field);
  json.endObject();
  out << '\n';
}

void writeTable(const BenchReport& report, std::ostream& out) {
  out << "suite " << report.suite << ", threads " << report.threads << ", " << report.machine
      << '\n';
  for (const ExtraField& field : report.extra) out << formatExtra(field) << '\n';

  const bool withRays = std::any_of(report.rows.begin(), report.rows.end(),
                                    [](const BenchRow& r) { return r.mraysPerS.has_value(); });
  std::vector<std::string> header = {"case", "impl", "median ms", "min ms", "max ms", "reps"};
  if (withRays) header.push_back("Mrays/s");
  header.push_back("ours/row");
  header.push_back("");  // free-form extras, left unpadded

  std::map<std::string, double> reference;  // case -> median of its first row
  std::vector<std::vector<std::string>> cells;
  for (const BenchRow& row : report.rows) {
    const double ours = reference.emplace(row.caseName, row.timing.medianMs).first->second;
    std::vector<std::string> line = {row.caseName,
                                     row.impl,
                                     formatMs(row.timing.medianMs),
                                     formatMs(row.timing.minMs),
                                     formatMs(row.timing.maxMs),
                                     std::to_string(row.timing.reps)};
    if (withRays) line.push_back(row.mraysPerS ? formatFixed(*row.mraysPerS, 2) : "-");
    line.push_back(row.timing.medianMs > 0.0 ? formatFixed(ours / row.timing.medianMs, 2) : "-");
    std::string extras;
    for (const ExtraField& field : row.extra) {
      if (!extras.empty()) extras += ' ';
      extras += formatExtra(field);
    }
    line.push_back(extras);
    cells.push_back(std::move(line));
  }

  std::vector<std::size_t> width(header.size(), 0);
  for (std::size_t c = 0; c < header.size(); ++c) width[c] = header[c].size();
  for (const auto& line : cells)
    for (std::size_t c = 0; c < line.size(); ++c) width[c] = std::max(width[c], line[c].size());

  // Text columns (case, impl) are left aligned, numbers right aligned.
  auto printLine = [&](const std::vector<std::string>& line) {
    std::string text;
    for (std::size_t c = 0; c < line.size(); ++c) {
      const std::size_t pad = width[c] - line[c].size();
      if (c + 1 == line.size()) {
        text += line[c];
      } else if (c < 2) {
        text += line[c] + std::string(pad, ' ');
      } else {
        text += std::string(pad, ' ') + line[c];
      }
      if (c + 1 < line.size()) text += "  ";
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    out << text << '\n';
  };
  printLine(header);
  for (const auto& line : cells) printLine(line);
}

}  // namespace tg::bench
