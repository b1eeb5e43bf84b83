/// @file Image.h
/// Float framebuffers (beauty and float AOVs) and id buffers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tracegraph/backend/Vec3.h"

namespace tg {

/// A float image with 1 to 4 interleaved channels; row 0 is the top row.
class Image {
 public:
  /// An empty 0 x 0 image.
  Image() = default;
  /// A width x height image of `channels` channels, every value `fill`.
  Image(std::uint32_t width, std::uint32_t height, std::uint32_t channels, float fill = 0.0f);

  /// Width in pixels.
  std::uint32_t width() const { return width_; }
  /// Height in pixels.
  std::uint32_t height() const { return height_; }
  /// Values per pixel (1 to 4).
  std::uint32_t channels() const { return channels_; }
  /// True when the image holds no pixels.
  bool empty() const { return data_.empty(); }

  /// Channel `c` of pixel (x, y); no bounds check.
  float& at(std::uint32_t x, std::uint32_t y, std::uint32_t c = 0) {
    return data_[index(x, y) + c];
  }
  /// Channel `c` of pixel (x, y), read-only; no bounds check.
  float at(std::uint32_t x, std::uint32_t y, std::uint32_t c = 0) const {
    return data_[index(x, y) + c];
  }
  /// The first three channels of pixel (x, y) (the image must have at least three).
  Vec3f rgb(std::uint32_t x, std::uint32_t y) const {
    const float* p = &data_[index(x, y)];
    return {p[0], p[1], p[2]};
  }
  /// Stores the first three channels of pixel (x, y).
  void setRgb(std::uint32_t x, std::uint32_t y, const Vec3f& c) {
    float* p = &data_[index(x, y)];
    p[0] = c.x;
    p[1] = c.y;
    p[2] = c.z;
  }

  /// All values, row by row from the top, channels interleaved.
  const std::vector<float>& data() const { return data_; }
  /// All values, writable (the size must not change).
  std::vector<float>& data() { return data_; }

  /// Bitwise equality of size and every value (NaN payloads and signed zeros included), the
  /// comparison the determinism checks need.
  bool bitwiseEqual(const Image& other) const;

 private:
  std::size_t index(std::uint32_t x, std::uint32_t y) const {
    return (static_cast<std::size_t>(y) * width_ + x) * channels_;
  }

  std::uint32_t width_ = 0, height_ = 0, channels_ = 0;
  std::vector<float> data_;
};

/// One 32-bit id per pixel (instance or primitive ids); kInvalidId where nothing was hit.
class IdImage {
 public:
  /// An empty 0 x 0 buffer.
  IdImage() = default;
  /// A width x height buffer, every id `fill`.
  IdImage(std::uint32_t width, std::uint32_t height, std::uint32_t fill);

  /// Width in pixels.
  std::uint32_t width() const { return width_; }
  /// Height in pixels.
  std::uint32_t height() const { return height_; }
  /// Id of pixel (x, y); no bounds check.
  std::uint32_t& at(std::uint32_t x, std::uint32_t y) {
    return data_[static_cast<std::size_t>(y) * width_ + x];
  }
  /// Id of pixel (x, y), read-only; no bounds check.
  std::uint32_t at(std::uint32_t x, std::uint32_t y) const {
    return data_[static_cast<std::size_t>(y) * width_ + x];
  }
  /// All ids, row by row from the top.
  const std::vector<std::uint32_t>& data() const { return data_; }

  /// The ids as a one-channel float image for PFM output: each id as a float (exact below
  /// 2^24), and -1 where nothing was hit.
  Image toFloat() const;

  /// Equal size and ids.
  bool operator==(const IdImage&) const = default;

 private:
  std::uint32_t width_ = 0, height_ = 0;
  std::vector<std::uint32_t> data_;
};

}  // namespace tg
