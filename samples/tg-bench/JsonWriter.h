/// @file JsonWriter.h
/// A minimal streaming JSON writer: enough for the benchmark report, with correct string
/// escaping and number formatting, and no dependency.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace tg::bench {

/// Returns `text` as a quoted JSON string literal (quotes, backslashes and control characters
/// escaped; other bytes, including UTF-8 sequences, copied as they are).
std::string jsonQuote(std::string_view text);

/// Formats a double as the shortest JSON number that reads back to the same value; NaN and
/// infinities, which JSON cannot express, become null.
std::string jsonNumber(double value);

/// Writes one compact JSON value to a stream. Commas between members and elements are inserted
/// automatically; the caller is responsible for pairing begin/end and for calling key() before
/// every value inside an object. The value writers have distinct names on purpose: with
/// overloads, a string literal would silently pick a bool overload.
class JsonWriter {
 public:
  explicit JsonWriter(std::ostream& out) : out_(out) {}

  void beginObject();
  void endObject();
  void beginArray();
  void endArray();
  /// Member name of the next value (inside an object).
  void key(std::string_view name);
  void string(std::string_view text);
  void number(double value);
  void integer(std::int64_t value);
  void boolean(bool value);
  void null();

 private:
  void beforeValue();

  std::ostream& out_;
  std::vector<bool> firstInScope_;  ///< per open object/array: nothing written in it yet
  bool afterKey_ = false;
};

}  // namespace tg::bench
