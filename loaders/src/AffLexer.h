/// @file AffLexer.h
/// Tokenizer for AFF/NFF text (private to the loaders library).
///
/// The text is bytes, not UTF-8. Any of space, tab, LF, CR, VT and FF separates tokens, so CRLF
/// and mixed line endings need no special care; LF alone counts lines. `#` and `%` start a
/// comment that runs to the end of the line, wherever they occur (the data never uses them
/// inside arguments). `{` and `}` are tokens of their own even when glued to a neighbour.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace tg::aff_detail {

/// Byte classes of the tokenizer.
enum AffCharClass : std::uint8_t { kToken = 0, kSpace, kNewline, kComment, kBrace };

/// Class of every byte value; anything not listed (including NUL and bytes ≥ 0x80) is part of
/// a token.
constexpr std::array<std::uint8_t, 256> makeAffCharClasses() {
  std::array<std::uint8_t, 256> c{};
  c[static_cast<unsigned char>(' ')] = kSpace;
  c[static_cast<unsigned char>('\t')] = kSpace;
  c[static_cast<unsigned char>('\r')] = kSpace;
  c[static_cast<unsigned char>('\v')] = kSpace;
  c[static_cast<unsigned char>('\f')] = kSpace;
  c[static_cast<unsigned char>('\n')] = kNewline;
  c[static_cast<unsigned char>('#')] = kComment;
  c[static_cast<unsigned char>('%')] = kComment;
  c[static_cast<unsigned char>('{')] = kBrace;
  c[static_cast<unsigned char>('}')] = kBrace;
  return c;
}

inline constexpr std::array<std::uint8_t, 256> kAffCharClasses = makeAffCharClasses();

/// One token: a view into the text and the line it starts on. An empty view marks the end.
struct AffToken {
  std::string_view text;   ///< the token's bytes (empty at the end of the text)
  std::uint32_t line = 0;  ///< 1-based line of its first byte

  /// True at the end of the text.
  bool atEnd() const { return text.empty(); }
};

/// Splits a text into tokens on demand, with one token of look-ahead.
class AffLexer {
 public:
  /// Tokenizes `text`, which must outlive the lexer and every token it returns.
  explicit AffLexer(std::string_view text)
      : begin_(text.data()), p_(text.data()), end_(text.data() + text.size()) {}

  /// Consumes and returns the next token (empty at the end).
  AffToken next() {
    if (hasLook_) {
      hasLook_ = false;
      return look_;
    }
    return scan();
  }

  /// Returns the next token without consuming it.
  const AffToken& peek() {
    if (!hasLook_) {
      look_ = scan();
      hasLook_ = true;
    }
    return look_;
  }

  /// Bytes from the next unconsumed token (or scan position) to the end of the text. Counts
  /// announced in the file are checked against this before anything is allocated.
  std::size_t remaining() const {
    const char* from = hasLook_ && !look_.atEnd() ? look_.text.data() : p_;
    return static_cast<std::size_t>(end_ - from);
  }

  /// Line of the scan position.
  std::uint32_t line() const { return line_; }

  /// Line to report for "end of file": the last line, not the empty one after a final newline.
  std::uint32_t endLine() const {
    return (line_ > 1 && end_ != begin_ && end_[-1] == '\n') ? line_ - 1 : line_;
  }

  /// Byte offset of the scan position (for diagnostics and tests).
  std::size_t offset() const { return static_cast<std::size_t>(p_ - begin_); }

 private:
  static std::uint8_t classOf(char ch) { return kAffCharClasses[static_cast<unsigned char>(ch)]; }

  AffToken scan() {
    while (p_ < end_) {
      const std::uint8_t c = classOf(*p_);
      if (c == kSpace) {
        ++p_;
      } else if (c == kNewline) {
        ++p_;
        ++line_;
      } else if (c == kComment) {
        const void* nl = std::memchr(p_, '\n', static_cast<std::size_t>(end_ - p_));
        p_ = nl ? static_cast<const char*>(nl) : end_;
      } else {
        break;
      }
    }
    if (p_ == end_) return {std::string_view(), endLine()};
    const char* start = p_;
    if (classOf(*p_) == kBrace) {
      ++p_;
    } else {
      while (p_ < end_ && classOf(*p_) == kToken) ++p_;
    }
    return {std::string_view(start, static_cast<std::size_t>(p_ - start)), line_};
  }

  const char* begin_;
  const char* p_;
  const char* end_;
  std::uint32_t line_ = 1;
  AffToken look_;
  bool hasLook_ = false;
};

}  // namespace tg::aff_detail
