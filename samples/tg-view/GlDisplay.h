// Shows a rendered frame in the current OpenGL context and reads the window back.
#pragma once

#include <cstdint>
#include <vector>

#include "tracegraph/backend/render/Image.h"

namespace tg::view_tool {

/// Draws a linear-RGB image as one texture stretched over the whole window, with the fixed
/// function pipeline of OpenGL 1.1: that is all a full-window image needs, and it runs on any
/// context, including Mesa's llvmpipe under Xvfb. Needs a current context for its lifetime.
class GlDisplay {
 public:
  GlDisplay();
  ~GlDisplay();
  GlDisplay(const GlDisplay&) = delete;
  GlDisplay& operator=(const GlDisplay&) = delete;

  /// Encodes `image` (3 or 4 channels, linear) to 8-bit sRGB and uploads it.
  void upload(const Image& image);
  /// Clears the framebuffer and draws the last uploaded image over all of it.
  void draw(int framebufferWidth, int framebufferHeight) const;
  /// Reads the back buffer (what draw() just drew, before the swap) as an 8-bit RGB image whose
  /// values are code / 255, row 0 on top: write it with PngEncoding::Linear.
  static Image readBack(int framebufferWidth, int framebufferHeight);

 private:
  unsigned texture_ = 0;
  std::uint32_t width_ = 0, height_ = 0;  ///< size of the texture storage
  std::vector<std::uint8_t> pixels_;      ///< staging buffer of the upload
  std::vector<std::uint8_t> srgbTable_;   ///< linear [0, 1] in kTableSize steps -> sRGB code
};

}  // namespace tg::view_tool
