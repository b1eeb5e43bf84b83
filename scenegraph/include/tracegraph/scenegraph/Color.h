/// @file Color.h
/// Linear RGB colour, the value type of SFColor and MFColor.
#pragma once

namespace tg {

/// Linear RGB colour with components usually in [0, 1].
struct Color {
  ///@{
  /// Linear red, green and blue.
  float r = 0.0f, g = 0.0f, b = 0.0f;
  ///@}
  /// Exact equality of every channel.
  bool operator==(const Color&) const = default;
};

}  // namespace tg
