// Token-level reading for the AFF/NFF parser: numbers in strtod syntax, integers, counts
// checked against the bytes left in the file, indices checked against their arrays, and names.
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>

#include "AffParserImpl.h"

namespace tg::aff_detail {
namespace {

bool isDigit(char c) {
  return c >= '0' && c <= '9';
}

/// Parses an unsigned decimal integer (optional '+') no greater than `max`.
bool parseUnsigned(std::string_view t, std::uint64_t max, std::uint64_t& out) {
  std::size_t i = (!t.empty() && t[0] == '+') ? 1 : 0;
  if (i == t.size()) return false;
  std::uint64_t v = 0;
  for (; i < t.size(); ++i) {
    if (!isDigit(t[i])) return false;
    const auto digit = static_cast<std::uint64_t>(t[i] - '0');
    if (v > (max - digit) / 10) return false;  // checked before it could wrap around
    v = v * 10 + digit;
  }
  out = v;
  return true;
}

/// Exact powers of ten representable in a double (10^0 … 10^22).
constexpr std::array<double, 23> kPow10 = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                           1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                           1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/// Fast path for the common short decimals ("-0.279", "3.", "2.6E-4"): when the digits form an
/// integer m < 2^53 and the decimal exponent e satisfies |e| ≤ 22, both m and 10^|e| are exact
/// doubles, so one IEEE multiplication or division rounds correctly — the same result strtod
/// gives. Returns false (leaving the work to from_chars) for anything else.
bool parseSimpleDecimal(const char* p, const char* e, double& out) {
  bool negative = false;
  if (p != e && *p == '-') {
    negative = true;
    ++p;
  }
  std::uint64_t mantissa = 0;
  int digits = 0, exponent = 0;
  bool any = false;
  for (; p != e && isDigit(*p); ++p, any = true) {
    if (digits < 19) {
      mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p - '0');
      if (mantissa != 0) ++digits;
    } else {
      return false;
    }
  }
  if (p != e && *p == '.') {
    for (++p; p != e && isDigit(*p); ++p, any = true) {
      if (digits >= 19) return false;
      mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p - '0');
      if (mantissa != 0) ++digits;
      --exponent;
    }
  }
  if (!any) return false;
  if (p != e && (*p == 'e' || *p == 'E')) {
    ++p;
    bool expNegative = false;
    if (p != e && (*p == '-' || *p == '+')) expNegative = *p++ == '-';
    if (p == e) return false;
    int value = 0;
    for (; p != e && isDigit(*p); ++p) {
      if (value > 1000) return false;
      value = value * 10 + (*p - '0');
    }
    exponent += expNegative ? -value : value;
  }
  if (p != e) return false;
  if (mantissa > (std::uint64_t{1} << 53) || exponent < -22 || exponent > 22) return false;
  const double m = static_cast<double>(mantissa);
  const double v = exponent < 0 ? m / kPow10[static_cast<std::size_t>(-exponent)]
                                : m * kPow10[static_cast<std::size_t>(exponent)];
  out = negative ? -v : v;
  return true;
}

}  // namespace

bool parseDouble(std::string_view token, double& out) {
  const char* b = token.data();
  const char* e = b + token.size();
  if (parseSimpleDecimal(b, e, out)) return true;
  if (b != e && *b == '+') {
    ++b;  // strtod accepts one leading plus; from_chars does not
    if (b != e && (*b == '+' || *b == '-')) return false;
  }
  if (b == e) return false;
  const std::from_chars_result r = std::from_chars(b, e, out, std::chars_format::general);
  if (r.ptr != e) return false;
  if (r.ec == std::errc()) return true;
  if (r.ec == std::errc::result_out_of_range) {
    // from_chars leaves `out` alone on overflow and underflow; strtod on a terminated copy
    // gives the C answer (0 or a subnormal, or ±HUGE_VAL that the caller rejects).
    const std::string copy(b, e);
    out = std::strtod(copy.c_str(), nullptr);
    return true;
  }
  return false;
}

std::string quoteToken(std::string_view token) {
  constexpr std::size_t kMax = 40;
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string r = "'";
  for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7F) {
      r += static_cast<char>(c);
    } else {
      r += "\\x";
      r += kHex[c >> 4];
      r += kHex[c & 15];
    }
  }
  if (token.size() > kMax) r += "...";
  r += '\'';
  return r;
}

// --- token readers ---

AffToken AffParserImpl::expectToken(Source& s, const char* what) {
  const AffToken t = s.lex.next();
  if (t.atEnd()) fail(s, t.line, std::string("unexpected end of file: expected ") + what);
  lastLine_ = t.line;
  return t;
}

void AffParserImpl::expectKeyword(Source& s, std::string_view keyword, const char* context) {
  const AffToken t = s.lex.next();
  if (t.text != keyword) {
    fail(s, t.line,
         "expected '" + std::string(keyword) + "' " + context + ", found " +
             (t.atEnd() ? std::string("end of file") : quoteToken(t.text)));
  }
}

double AffParserImpl::readDouble(Source& s, const char* what) {
  const AffToken t = expectToken(s, what);
  double v = 0.0;
  if (!parseDouble(t.text, v))
    fail(s, t.line, "bad number " + quoteToken(t.text) + " (expected " + what + ")");
  if (!std::isfinite(v))
    fail(s, t.line, "NaN or infinite number " + quoteToken(t.text) + " (" + what + ")");
  return v;
}

float AffParserImpl::readFloat(Source& s, const char* what) {
  const double v = readDouble(s, what);
  if (std::abs(v) > static_cast<double>(std::numeric_limits<float>::max()))
    fail(s, lastLine_, std::string("number out of single-precision range (") + what + ")");
  return static_cast<float>(v);
}

Vec3d AffParserImpl::readVec3d(Source& s, const char* what) {
  const double x = readDouble(s, what);
  const double y = readDouble(s, what);
  return {x, y, readDouble(s, what)};
}

Vec3f AffParserImpl::readVec3f(Source& s, const char* what) {
  const float x = readFloat(s, what);
  const float y = readFloat(s, what);
  return {x, y, readFloat(s, what)};
}

int AffParserImpl::readInt(Source& s, const char* what) {
  const AffToken t = expectToken(s, what);
  std::string_view digits = t.text;
  const bool negative = !digits.empty() && digits[0] == '-';
  if (negative) digits.remove_prefix(1);
  std::uint64_t v = 0;
  if (!parseUnsigned(digits, static_cast<std::uint64_t>(std::numeric_limits<int>::max()), v) ||
      (negative && !digits.empty() && digits[0] == '+')) {
    fail(s, t.line, "bad integer " + quoteToken(t.text) + " (expected " + what + ")");
  }
  return negative ? -static_cast<int>(v) : static_cast<int>(v);
}

std::uint32_t AffParserImpl::readCount(Source& s, const char* what, std::uint32_t tokensPerItem) {
  const AffToken t = expectToken(s, what);
  std::uint64_t v = 0;
  if (!parseUnsigned(t.text, std::numeric_limits<std::uint32_t>::max(), v))
    fail(s, t.line, "bad count " + quoteToken(t.text) + " (expected " + what + ")");
  // Every further token needs a separator and at least one byte.
  const std::uint64_t needed = v * tokensPerItem * 2;
  if (needed > s.lex.remaining()) {
    fail(s, t.line,
         std::string(what) + " " + std::to_string(v) + " is more than the remaining " +
             std::to_string(s.lex.remaining()) + " bytes of the file can hold");
  }
  return static_cast<std::uint32_t>(v);
}

std::uint32_t AffParserImpl::readIndex(Source& s, std::uint32_t limit, const char* what) {
  const AffToken t = expectToken(s, what);
  std::uint64_t v = 0;
  if (!parseUnsigned(t.text, std::numeric_limits<std::uint64_t>::max(), v))
    fail(s, t.line, "bad index " + quoteToken(t.text) + " (expected " + what + ")");
  if (v >= limit) {
    fail(s, t.line,
         std::string(what) + " " + std::to_string(v) + " out of range (" + std::to_string(limit) +
             " entries)");
  }
  return static_cast<std::uint32_t>(v);
}

std::string_view AffParserImpl::readName(Source& s, const char* what) {
  const AffToken t = expectToken(s, what);
  if (t.text == "{" || t.text == "}")
    fail(s, t.line, std::string("expected ") + what + ", found " + quoteToken(t.text));
  return t.text;
}

bool AffParserImpl::nextIsNumber(Source& s) {
  const AffToken& t = s.lex.peek();
  if (t.atEnd()) return false;
  const char c = t.text[0];
  return isDigit(c) || c == '-' || c == '+' || c == '.';
}

}  // namespace tg::aff_detail
