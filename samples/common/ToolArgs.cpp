#include "ToolArgs.h"

#include <charconv>
#include <system_error>

namespace tg::tools {

bool parseImageSizeArgument(const std::string& text, std::uint32_t& width, std::uint32_t& height) {
  const std::size_t x = text.find('x');
  if (x == std::string::npos) return false;
  // from_chars takes digits only (no blanks or signs) and reports overflow.
  const auto parse = [](const char* first, const char* last, std::uint32_t& value) {
    const std::from_chars_result r = std::from_chars(first, last, value);
    return r.ec == std::errc{} && r.ptr == last && value >= 1 && value <= kMaxImageEdge;
  };
  std::uint32_t w = 0, h = 0;
  const char* begin = text.data();
  if (!parse(begin, begin + x, w) || !parse(begin + x + 1, begin + text.size(), h)) return false;
  width = w;
  height = h;
  return true;
}

}  // namespace tg::tools
