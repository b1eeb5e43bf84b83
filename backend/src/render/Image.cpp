#include "tracegraph/backend/render/Image.h"

#include <cstring>

#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/Ray.h"

namespace tg {

Image::Image(std::uint32_t width, std::uint32_t height, std::uint32_t channels, float fill)
    : width_(width), height_(height), channels_(channels) {
  if (channels < 1 || channels > 4)
    throw Error("Image: " + std::to_string(channels) + " channels (1 to 4 supported)");
  data_.assign(static_cast<std::size_t>(width) * height * channels, fill);
}

bool Image::bitwiseEqual(const Image& other) const {
  if (width_ != other.width_ || height_ != other.height_ || channels_ != other.channels_)
    return false;
  // memcmp, not ==: NaN != NaN and -0 == +0 would both hide or invent differences.
  return data_.empty() ||
         std::memcmp(data_.data(), other.data_.data(), data_.size() * sizeof(float)) == 0;
}

IdImage::IdImage(std::uint32_t width, std::uint32_t height, std::uint32_t fill)
    : width_(width), height_(height), data_(static_cast<std::size_t>(width) * height, fill) {}

Image IdImage::toFloat() const {
  Image out(width_, height_, 1);
  for (std::size_t i = 0; i < data_.size(); ++i)
    out.data()[i] = data_[i] == kInvalidId ? -1.0f : static_cast<float>(data_[i]);
  return out;
}

}  // namespace tg
