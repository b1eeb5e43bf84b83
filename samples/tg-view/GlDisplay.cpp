#include "GlDisplay.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>

#include "tracegraph/backend/render/ImageIO.h"

namespace tg::view_tool {
namespace {

// A table lookup instead of srgbEncode per value: the curve costs a pow() per channel, which
// at 640x480 takes longer than tracing the OpenGL mode. 16384 steps keep every dark code
// reachable (the curve's steepest slope, 12.92, spans under one code per step).
constexpr std::size_t kTableSize = 16384;

}  // namespace

GlDisplay::GlDisplay() : srgbTable_(kTableSize) {
  for (std::size_t i = 0; i < kTableSize; ++i) {
    const float linear = static_cast<float>(i) / static_cast<float>(kTableSize - 1);
    srgbTable_[i] = static_cast<std::uint8_t>(std::lround(srgbEncode(linear) * 255.0f));
  }
  glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  // Nearest: a reduced render resolution shows as honest pixels rather than blur.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP);
}

GlDisplay::~GlDisplay() {
  glDeleteTextures(1, &texture_);
}

void GlDisplay::upload(const Image& image) {
  const std::uint32_t w = image.width(), h = image.height(), c = image.channels();
  if (w == 0 || h == 0 || c < 3) return;
  pixels_.resize(static_cast<std::size_t>(w) * h * 3);
  const std::vector<float>& src = image.data();
  constexpr float kScale = static_cast<float>(kTableSize - 1);
  for (std::size_t p = 0, n = static_cast<std::size_t>(w) * h; p < n; ++p)
    for (std::size_t k = 0; k < 3; ++k) {
      const float v = src[p * c + k];
      // !(v > 0) also catches NaN, which writePng maps to 0 as well.
      const float clamped = !(v > 0.0f) ? 0.0f : (v > 1.0f ? 1.0f : v);
      pixels_[p * 3 + k] = srgbTable_[static_cast<std::size_t>(clamped * kScale + 0.5f)];
    }
  glBindTexture(GL_TEXTURE_2D, texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (w != width_ || h != height_) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, static_cast<GLsizei>(w), static_cast<GLsizei>(h), 0,
                 GL_RGB, GL_UNSIGNED_BYTE, pixels_.data());
    width_ = w;
    height_ = h;
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, static_cast<GLsizei>(w), static_cast<GLsizei>(h),
                    GL_RGB, GL_UNSIGNED_BYTE, pixels_.data());
  }
}

void GlDisplay::draw(int framebufferWidth, int framebufferHeight) const {
  glViewport(0, 0, framebufferWidth, framebufferHeight);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (width_ == 0) return;
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_LIGHTING);
  glEnable(GL_TEXTURE_2D);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
  // Row 0 of the image (the top row) is the texture's t = 0, so t runs downwards.
  glBegin(GL_QUADS);
  glTexCoord2f(0.0f, 1.0f);
  glVertex2f(-1.0f, -1.0f);
  glTexCoord2f(1.0f, 1.0f);
  glVertex2f(1.0f, -1.0f);
  glTexCoord2f(1.0f, 0.0f);
  glVertex2f(1.0f, 1.0f);
  glTexCoord2f(0.0f, 0.0f);
  glVertex2f(-1.0f, 1.0f);
  glEnd();
  glDisable(GL_TEXTURE_2D);
}

Image GlDisplay::readBack(int framebufferWidth, int framebufferHeight) {
  const auto w = static_cast<std::uint32_t>(std::max(framebufferWidth, 0));
  const auto h = static_cast<std::uint32_t>(std::max(framebufferHeight, 0));
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(w) * h * 3);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, framebufferWidth, framebufferHeight, GL_RGB, GL_UNSIGNED_BYTE, bytes.data());
  Image image(w, h, 3);
  // OpenGL's row 0 is the bottom row; the image's is the top.
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x)
      for (std::uint32_t k = 0; k < 3; ++k)
        image.at(x, y, k) =
            static_cast<float>(bytes[((static_cast<std::size_t>(h - 1 - y) * w) + x) * 3 + k]) /
            255.0f;
  return image;
}

}  // namespace tg::view_tool
