#include "JsonWriter.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace tg::bench {

std::string jsonQuote(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size() + 2);
  out.push_back('"');
  for (const char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default: {
        const auto byte = static_cast<unsigned char>(c);
        if (byte < 0x20) {
          out += "\\u00";
          out.push_back(kHex[byte >> 4]);
          out.push_back(kHex[byte & 15]);
        } else {
          out.push_back(c);
        }
      }
    }
  }
  out.push_back('"');
  return out;
}

std::string jsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[64];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (r.ec != std::errc{}) return "null";
  return std::string(buffer, r.ptr);
}

void JsonWriter::beforeValue() {
  if (afterKey_) {
    afterKey_ = false;
    return;
  }
  if (!firstInScope_.empty()) {
    if (!firstInScope_.back()) out_ << ',';
    firstInScope_.back() = false;
  }
}

void JsonWriter::beginObject() {
  beforeValue();
  out_ << '{';
  firstInScope_.push_back(true);
}

void JsonWriter::endObject() {
  firstInScope_.pop_back();
  out_ << '}';
}

void JsonWriter::beginArray() {
  beforeValue();
  out_ << '[';
  firstInScope_.push_back(true);
}

void JsonWriter::endArray() {
  firstInScope_.pop_back();
  out_ << ']';
}

void JsonWriter::key(std::string_view name) {
  beforeValue();
  out_ << jsonQuote(name) << ':';
  afterKey_ = true;
}

void JsonWriter::string(std::string_view text) {
  beforeValue();
  out_ << jsonQuote(text);
}

void JsonWriter::number(double value) {
  beforeValue();
  out_ << jsonNumber(value);
}

void JsonWriter::integer(std::int64_t value) {
  beforeValue();
  out_ << value;
}

void JsonWriter::boolean(bool value) {
  beforeValue();
  out_ << (value ? "true" : "false");
}

void JsonWriter::null() {
  beforeValue();
  out_ << "null";
}

}  // namespace tg::bench
