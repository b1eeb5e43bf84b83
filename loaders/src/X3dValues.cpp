// X3D attribute values: numbers separated by white space or commas, booleans, MFString
// quoting; every malformed value is reported with the file, line, element and attribute.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include "X3dImpl.h"
#include "tracegraph/backend/Error.h"

namespace tg::x3d {
namespace {

bool isSeparator(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && isSeparator(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSeparator(s.back())) s.remove_suffix(1);
  return s;
}

/// Parses whitespace/comma separated numbers; returns the first bad token, or nothing.
std::optional<std::string> parseNumbers(std::string_view text, std::vector<double>& out) {
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && isSeparator(text[i])) ++i;
    if (i == text.size()) break;
    std::size_t j = i;
    while (j < text.size() && !isSeparator(text[j])) ++j;
    std::string_view tok = text.substr(i, j - i);
    // from_chars rejects a leading '+', which X3D writers do emit.
    std::string_view num = tok.front() == '+' ? tok.substr(1) : tok;
    double v = 0.0;
    const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), v);
    if (num.empty() || ec != std::errc() || end != num.data() + num.size())
      return std::string(tok.substr(0, 40));
    out.push_back(v);
    i = j;
  }
  return std::nullopt;
}

}  // namespace

SourceText::SourceText(std::string name, std::filesystem::path dir, std::string_view text)
    : name_(std::move(name)), dir_(std::move(dir)) {
  lineStarts_.push_back(0);
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') lineStarts_.push_back(i + 1);
}

int SourceText::lineAt(std::ptrdiff_t offset) const {
  if (offset < 0) return 0;
  const auto it =
      std::upper_bound(lineStarts_.begin(), lineStarts_.end(), static_cast<std::size_t>(offset));
  return static_cast<int>(it - lineStarts_.begin());
}

std::string SourceText::where(int line) const {
  return name_ + ":" + std::to_string(line) + ": ";
}

bool Attributes::has(const char* name) const {
  return !node_.attribute(name).empty();
}

void Attributes::fail(const char* name, const std::string& what) const {
  throw Error(src_.where(line()) + node_.name() + " " + name + ": " + what);
}

std::string Attributes::getString(const char* name, const std::string& def) const {
  const pugi::xml_attribute a = node_.attribute(name);
  return a.empty() ? def : std::string(a.value());
}

std::vector<std::string> Attributes::getStrings(const char* name) const {
  std::vector<std::string> out;
  const std::string_view text = trim(node_.attribute(name).value());
  if (text.empty()) return out;
  if (text.front() != '"') {
    out.emplace_back(text);  // a bare single string, as some writers emit for SFString-like use
    return out;
  }
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && isSeparator(text[i])) ++i;
    if (i == text.size()) break;
    if (text[i] != '"') fail(name, "expected a quoted string");
    std::string s;
    ++i;
    bool closed = false;
    while (i < text.size()) {
      const char c = text[i++];
      if (c == '\\' && i < text.size()) {
        s += text[i++];
      } else if (c == '"') {
        closed = true;
        break;
      } else {
        s += c;
      }
    }
    if (!closed) fail(name, "unterminated string");
    out.push_back(std::move(s));
  }
  return out;
}

bool Attributes::getBool(const char* name, bool def) const {
  if (!has(name)) return def;
  std::string v(trim(node_.attribute(name).value()));
  std::transform(v.begin(), v.end(), v.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (v == "true") return true;
  if (v == "false") return false;
  fail(name, "expected true or false, got '" + v.substr(0, 40) + "'");
}

std::vector<double> Attributes::numbers(const char* name, std::size_t tuple) const {
  std::vector<double> v;
  if (const auto bad = parseNumbers(node_.attribute(name).value(), v))
    fail(name, "'" + *bad + "' is not a number");
  for (const double x : v)
    // Beyond 1e18 nothing in a scene makes sense, and products of such numbers overflow.
    if (!std::isfinite(x) || std::abs(x) > 1.0e18) fail(name, "NaN, infinite or out of range");
  if (v.size() % tuple != 0)
    fail(name, std::to_string(v.size()) + " numbers is not a multiple of " + std::to_string(tuple));
  return v;
}

double Attributes::getDouble(const char* name, double def) const {
  if (!has(name)) return def;
  const std::vector<double> v = numbers(name, 1);
  if (v.size() != 1) fail(name, "expected one number");
  return v[0];
}

float Attributes::getFloat(const char* name, float def) const {
  return static_cast<float>(getDouble(name, def));
}

std::int32_t Attributes::getInt(const char* name, std::int32_t def) const {
  const double d = getDouble(name, def);
  if (d != std::floor(d) || d < -2147483648.0 || d > 2147483647.0)
    fail(name, "expected an integer");
  return static_cast<std::int32_t>(d);
}

Vec2f Attributes::getVec2(const char* name, Vec2f def) const {
  if (!has(name)) return def;
  const std::vector<double> v = numbers(name, 2);
  if (v.size() != 2) fail(name, "expected 2 numbers");
  return {static_cast<float>(v[0]), static_cast<float>(v[1])};
}

Vec3f Attributes::getVec3(const char* name, Vec3f def) const {
  if (!has(name)) return def;
  const std::vector<double> v = numbers(name, 3);
  if (v.size() != 3) fail(name, "expected 3 numbers");
  return Vec3f(Vec3d(v[0], v[1], v[2]));
}

Color Attributes::getColor(const char* name, Color def) const {
  if (!has(name)) return def;
  const Vec3f c = getVec3(name, {});
  return {c.x, c.y, c.z};
}

Rotation Attributes::getRotation(const char* name, Rotation def) const {
  if (!has(name)) return def;
  const std::vector<double> v = numbers(name, 4);
  if (v.size() != 4) fail(name, "expected 4 numbers (axis and angle)");
  return {Vec3f(Vec3d(v[0], v[1], v[2])), static_cast<float>(v[3])};
}

std::vector<float> Attributes::getFloats(const char* name) const {
  const std::vector<double> v = numbers(name, 1);
  return std::vector<float>(v.begin(), v.end());
}

std::vector<std::int32_t> Attributes::getInts(const char* name) const {
  const std::vector<double> v = numbers(name, 1);
  std::vector<std::int32_t> out;
  out.reserve(v.size());
  for (const double d : v) {
    if (d != std::floor(d) || d < -2147483648.0 || d > 2147483647.0)
      fail(name, "expected integers");
    out.push_back(static_cast<std::int32_t>(d));
  }
  return out;
}

std::vector<Vec2f> Attributes::getVec2s(const char* name) const {
  const std::vector<double> v = numbers(name, 2);
  std::vector<Vec2f> out(v.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {static_cast<float>(v[2 * i]), static_cast<float>(v[2 * i + 1])};
  return out;
}

std::vector<Vec3f> Attributes::getVec3s(const char* name) const {
  const std::vector<double> v = numbers(name, 3);
  std::vector<Vec3f> out(v.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = Vec3f(Vec3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]));
  return out;
}

std::vector<Color> Attributes::getColors(const char* name, int components) const {
  const std::size_t n = static_cast<std::size_t>(components);
  const std::vector<double> v = numbers(name, n);
  std::vector<Color> out(v.size() / n);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {static_cast<float>(v[n * i]), static_cast<float>(v[n * i + 1]),
              static_cast<float>(v[n * i + 2])};
  return out;
}

std::vector<Rotation> Attributes::getRotations(const char* name) const {
  const std::vector<double> v = numbers(name, 4);
  std::vector<Rotation> out(v.size() / 4);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {Vec3f(Vec3d(v[4 * i], v[4 * i + 1], v[4 * i + 2])), static_cast<float>(v[4 * i + 3])};
  return out;
}

}  // namespace tg::x3d
