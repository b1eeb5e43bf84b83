// Encodes frames to a video by piping raw RGB into ffmpeg, when ffmpeg is installed.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "tracegraph/backend/render/Image.h"

namespace tg::render_tool {

/// An ffmpeg process reading raw 8-bit sRGB frames on its standard input.
class VideoPipe {
 public:
  /// Starts ffmpeg writing `path`; throws tg::Error with a clear message when ffmpeg is missing.
  VideoPipe(const std::string& path, std::uint32_t width, std::uint32_t height, double fps);
  ~VideoPipe();
  VideoPipe(const VideoPipe&) = delete;
  VideoPipe& operator=(const VideoPipe&) = delete;
  /// Appends one frame (linear RGB, encoded to sRGB here).
  void write(const Image& beauty);
  /// Waits for ffmpeg; throws tg::Error when it failed.
  void finish();

 private:
  std::FILE* pipe_ = nullptr;
  std::string path_;
};

}  // namespace tg::render_tool
