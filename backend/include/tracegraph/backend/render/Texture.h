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
  Nearest,    ///< the texel containing the sample point
  Bilinear,   ///< weighted mean of the four nearest texel centres (wrapping at the borders)
  Trilinear,  ///< mip-mapped: Bilinear in the two levels around the footprint, blended
              ///< (OpenGL's GL_LINEAR_MIPMAP_LINEAR); Bilinear where the footprint is unknown
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

  /// The texel colour at `uv` with the given filter, from the full-resolution image
  /// (Trilinear reads level 0, as Bilinear does).
  Vec3f sample(const Vec2f& uv, TextureFilter filter) const;
  /// The colour at `uv` over a footprint `lod` = log2(footprint width in texels of the full
  /// image). Trilinear blends the bilinear lookups of levels floor(lod) and floor(lod) + 1 of
  /// the mip chain (clamped to its last level); lod <= 0 and NaN read level 0, so that the
  /// result is then sample(uv, Bilinear) exactly. Nearest and Bilinear ignore `lod`.
  Vec3f sample(const Vec2f& uv, TextureFilter filter, float lod) const;
  /// Asks the cache for the stored 4 x 4 block of full-resolution texels that holds `uv`, in
  /// which a Bilinear or Nearest sample() there finds all or most of what it reads. Only a
  /// hint: changes no result, and any `uv` (NaN and huge ones included) is valid. Renderers
  /// call it for a group of hits before sampling any of them, so that their misses overlap.
  void prefetch(const Vec2f& uv) const;
  /// Levels of the mip chain, the full image included: 1 + floor(log2(max(width, height))).
  std::size_t levelCount() const { return 1 + mips_.size(); }
  /// Texel (x, y) of mip level `level` (1 to levelCount() - 1), both wrapped into the level:
  /// the mean of the 2 x 2 texels (2x, 2y) to (2x + 1, 2y + 1) of the level above, wrapped.
  Vec3f mipTexel(std::size_t level, long long x, long long y) const;
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
  /// Fills mips_ by 2 x 2 box filtering, level after level, down to one texel.
  void buildMips();
  /// Bilinear lookup at `uv` in a width x height image whose texel (column, row) is
  /// texelAt(column, row).
  template <class TexelAt>
  Vec3f bilinear(const Vec2f& uv, std::uint32_t width, std::uint32_t height,
                 const TexelAt& texelAt) const;

  /// bilinear in float arithmetic (exact but for the rounding of u * width and v * height),
  /// falling back to bilinear for coordinates of 2^22 and beyond.
  template <class TexelAt>
  Vec3f bilinearFloat(const Vec2f& uv, std::uint32_t width, std::uint32_t height,
                      const TexelAt& texelAt) const;

  /// One level of the mip chain below the full image.
  struct MipLevel {
    std::uint32_t width = 0, height = 0;
    std::vector<Vec3f> texels;  ///< row-major
    Vec3f at(std::uint32_t column, std::uint32_t row) const {
      return texels[static_cast<std::size_t>(row) * width + column];
    }
  };
  /// Levels 1, 2, ... (each half the size of the one above, at least 1 x 1).
  std::vector<MipLevel> mips_;

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
