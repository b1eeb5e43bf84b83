/// @file Color.h
/// Linear RGB colour, the value type of SFColor and MFColor.
#pragma once

namespace tg {

/// Linear RGB colour with components usually in [0, 1].
struct Color {
  float r = 0.0f, g = 0.0f, b = 0.0f;
  bool operator==(const Color&) const = default;
};

}  // namespace tg
