/// @file Texture.h
/// RGB textures loaded from PPM or PNG, sampled with OpenGL's GL_REPEAT wrapping.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tracegraph/backend/TriangleMesh.h"
#include "tracegraph/backend/Vec3.h"
#include "tracegraph/backend/render/Image.h"

namespace tg {

/// Texture reconstruction filter.
enum class TextureFilter : std::uint8_t {
  Nearest,   ///< the texel containing the sample point
  Bilinear,  ///< weighted mean of the four nearest texel centres (wrapping at the borders)
};

/// How the texel values of a file are encoded.
enum class ColorEncoding : std::uint8_t {
  Srgb,    ///< 8/16-bit values are sRGB-encoded (usual for photos and paintings): decoded to
           ///< linear on load, because the renderer shades in linear RGB
  Linear,  ///< values are linear already (data textures)
};

/// A linear RGB float image used as a texture. Coordinates repeat (GL_REPEAT): u = 0 is the
/// left edge of column 0, v = 0 the top edge of the first image row (the first row stored in
/// the file), and u, v = 1 wrap back to 0.
class Texture {
 public:
  /// An empty texture; sample() returns white.
  Texture() = default;
  /// Wraps a 3-channel linear image; `name` appears in messages. Throws tg::Error for other
  /// channel counts or an empty image.
  explicit Texture(Image rgb, std::string name = {});

  /// Loads a PPM (P6 or P3, maxval up to 65535, header comments, trailing bytes ignored) or,
  /// recognised by content rather than extension, a PNG (or any format stb_image reads).
  /// Throws tg::Error naming the file when it cannot be read or is malformed.
  static Texture load(const std::string& path, ColorEncoding encoding = ColorEncoding::Srgb);

  /// The texel colour at `uv` with the given filter.
  Vec3f sample(const Vec2f& uv, TextureFilter filter) const;
  /// Texel (x, y) with both wrapped into the image (any integers are valid).
  Vec3f texel(long long x, long long y) const;

  /// Width in texels.
  std::uint32_t width() const { return image_.width(); }
  /// Height in texels.
  std::uint32_t height() const { return image_.height(); }
  /// The linear RGB texels, row 0 = v in [0, 1/height).
  const Image& image() const { return image_; }
  /// The file name (or the name given), for messages.
  const std::string& name() const { return name_; }

 private:
  /// Texel (column, row) of the image, from the palette codes when there are some.
  Vec3f at(std::uint32_t column, std::uint32_t row) const {
    if (codes_.empty()) return image_.rgb(column, row);
    const CodeBlock& block = codes_[static_cast<std::size_t>(row >> 2) * blocksX_ + (column >> 2)];
    const std::uint32_t code = block.codes[(row & 3u) * 4u + (column & 3u)];
    return {palette_[code & 0xFFu], palette_[(code >> 8) & 0xFFu], palette_[(code >> 16) & 0xFFu]};
  }
  /// Fills codes_ and palette_ when the image holds at most 256 distinct values.
  void buildPalette();

  Image image_;
  std::string name_;
  /// 4 x 4 texels in one cache line: row-major order, one line per block.
  struct alignas(64) CodeBlock {
    std::array<std::uint32_t, 16> codes;
  };
  /// The image again as one 32-bit word per texel (three 8-bit indices into palette_), when
  /// it holds at most 256 distinct values, as every 8-bit file does; otherwise empty.
  /// Sampling large textures is bound by cache misses: a quarter of the float image's size, in
  /// 4 x 4 blocks so that a bilinear footprint mostly lies in one cache line, and the palette
  /// returns the very same floats.
  std::vector<CodeBlock> codes_;
  std::uint32_t blocksX_ = 0;  ///< blocks per row of blocks
  std::array<float, 256> palette_{};
};

}  // namespace tg
