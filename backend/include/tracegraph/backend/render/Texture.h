/// @file Texture.h
/// RGB textures loaded from PPM or PNG, sampled with OpenGL's GL_REPEAT wrapping.
#pragma once

#include <string>

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
  Image image_;
  std::string name_;
};

}  // namespace tg
