// Parsing of command-line values that several tools accept in the same form.
#pragma once

#include <cstdint>
#include <string>

namespace tg::tools {

/// Largest image edge any tool accepts, in pixels.
inline constexpr std::uint32_t kMaxImageEdge = 16384;

/// Parses "WxH" (decimal, nothing else around it) with 1 <= W, H <= kMaxImageEdge. Returns
/// false, leaving the outputs alone, for anything else.
bool parseImageSizeArgument(const std::string& text, std::uint32_t& width, std::uint32_t& height);

}  // namespace tg::tools
