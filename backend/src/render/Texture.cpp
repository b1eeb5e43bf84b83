#include "tracegraph/backend/render/Texture.h"

#include <stb_image.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/render/ImageIO.h"

namespace tg {
namespace {

/// Largest accepted texture, in texels: far beyond any real texture, small enough that a
/// corrupt header cannot make us allocate gigabytes.
constexpr std::uint64_t kMaxTexels = 1ull << 28;

/// Reads the header of a PPM and the raster that follows.
class PpmReader {
 public:
  PpmReader(const std::string& path, const std::vector<unsigned char>& bytes)
      : path_(path), bytes_(bytes) {}

  Image read(ColorEncoding encoding) {
    const bool ascii = bytes_[1] == '3';
    pos_ = 2;
    const std::uint64_t w = readNumber("width");
    const std::uint64_t h = readNumber("height");
    const std::uint64_t maxval = readNumber("maxval");
    if (w == 0 || h == 0 || w * h > kMaxTexels)
      fail("bad image size " + std::to_string(w) + " x " + std::to_string(h));
    if (maxval == 0 || maxval > 65535)
      fail("maxval " + std::to_string(maxval) + " not in 1..65535");
    // Exactly one whitespace character separates maxval from a binary raster.
    if (pos_ >= bytes_.size() || !std::isspace(bytes_[pos_])) fail("no whitespace after maxval");
    ++pos_;

    Image image(static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h), 3);
    const std::size_t count = static_cast<std::size_t>(w * h * 3);
    const std::size_t bytesPerSample = maxval < 256 ? 1 : 2;
    if (!ascii && bytes_.size() - pos_ < count * bytesPerSample)
      fail("raster truncated: " + std::to_string(bytes_.size() - pos_) + " bytes for " +
           std::to_string(count * bytesPerSample));
    // A small table for 8-bit data avoids a pow() per texel of large textures.
    std::vector<float> table(static_cast<std::size_t>(maxval) + 1);
    for (std::size_t i = 0; i < table.size(); ++i) {
      const float v = static_cast<float>(i) / static_cast<float>(maxval);
      table[i] = encoding == ColorEncoding::Srgb ? srgbDecode(v) : v;
    }
    float* out = image.data().data();
    for (std::size_t i = 0; i < count; ++i) {
      std::uint64_t value = 0;
      if (ascii) {
        value = readNumber("sample");
      } else if (bytesPerSample == 1) {
        value = bytes_[pos_++];
      } else {  // 16-bit samples are big-endian
        value = (static_cast<std::uint64_t>(bytes_[pos_]) << 8) | bytes_[pos_ + 1];
        pos_ += 2;
      }
      if (value > maxval) fail("sample " + std::to_string(value) + " exceeds maxval");
      out[i] = table[static_cast<std::size_t>(value)];
    }
    // Anything after the raster (a second image, padding, a newline) is ignored.
    return image;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(path_ + ": malformed PPM: " + what);
  }

  void skipSpaceAndComments() {
    while (pos_ < bytes_.size()) {
      if (bytes_[pos_] == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r') ++pos_;
      } else if (std::isspace(bytes_[pos_])) {
        ++pos_;
      } else {
        break;
      }
    }
  }

  std::uint64_t readNumber(const char* what) {
    skipSpaceAndComments();
    if (pos_ >= bytes_.size()) fail(std::string("file ends before ") + what);
    if (!std::isdigit(bytes_[pos_])) fail(std::string("expected a number for ") + what);
    std::uint64_t v = 0;
    while (pos_ < bytes_.size() && std::isdigit(bytes_[pos_])) {
      v = v * 10 + static_cast<std::uint64_t>(bytes_[pos_++] - '0');
      if (v > (1ull << 32)) fail(std::string(what) + " is absurdly large");
    }
    return v;
  }

  const std::string& path_;
  const std::vector<unsigned char>& bytes_;
  std::size_t pos_ = 0;
};

std::string stbReason() {
  const char* reason = stbi_failure_reason();
  return reason ? reason : "unknown reason";
}

Image loadWithStb(const std::string& path, ColorEncoding encoding) {
  int w = 0, h = 0, n = 0;
  if (!stbi_info(path.c_str(), &w, &h, &n))
    throw Error(path + ": not a PPM, PNG or other readable image (" + stbReason() + ")");
  if (w <= 0 || h <= 0 ||
      static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > kMaxTexels)
    throw Error(path + ": bad image size");
  const bool sixteen = stbi_is_16_bit(path.c_str()) != 0;
  const float maxval = sixteen ? 65535.0f : 255.0f;
  // Always ask stb for 3 channels: grey is expanded and alpha dropped.
  std::unique_ptr<void, void (*)(void*)> pixels(
      sixteen ? static_cast<void*>(stbi_load_16(path.c_str(), &w, &h, &n, 3))
              : static_cast<void*>(stbi_load(path.c_str(), &w, &h, &n, 3)),
      stbi_image_free);
  if (!pixels) throw Error(path + ": cannot decode image (" + stbReason() + ")");
  Image image(static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h), 3);
  for (std::size_t i = 0; i < image.data().size(); ++i) {
    const float raw = sixteen
                          ? static_cast<float>(static_cast<const std::uint16_t*>(pixels.get())[i])
                          : static_cast<float>(static_cast<const std::uint8_t*>(pixels.get())[i]);
    const float v = raw / maxval;
    image.data()[i] = encoding == ColorEncoding::Srgb ? srgbDecode(v) : v;
  }
  return image;
}

/// Wraps i into [0, n) for any integer i (GL_REPEAT).
std::uint32_t wrap(long long i, std::uint32_t n) {
  // Nearly every index sample() asks for lies in the image already; the 64-bit division is
  // then skipped (it cost more than the rest of a bilinear lookup).
  const auto size = static_cast<long long>(n);
  if (i >= 0 && i < size) return static_cast<std::uint32_t>(i);
  // One side beyond: the neighbour of a border texel in a bilinear lookup (every lookup near
  // the border of a small tiled texture), again without the division.
  if (i < 0 && i >= -size) return static_cast<std::uint32_t>(i + size);
  if (i >= size && i < 2 * size) return static_cast<std::uint32_t>(i - size);
  const long long m = i % size;
  return static_cast<std::uint32_t>(m < 0 ? m + n : m);
}

/// Largest texture side for which a float coordinate times the side is exact in double: a
/// 24-bit significand times at most 29 bits.
constexpr std::uint32_t kExactScaleLimit = 1u << 29;

/// std::fmod(c * n, n) in double, for a texture side n > 0. Within (-n, n), fmod returns its
/// argument itself (signed zero included), so the common case needs no library call. Beyond,
/// fmod(c n, n) = (c - trunc(c)) n exactly when c n is exact (n <= kExactScaleLimit): the
/// fraction of a float is a float, and it times n is exact again. fmod gives a zero the sign of
/// its argument, hence the copysign. NaN, infinities and larger sides go through fmod.
double wrapCoordinate(float c, std::uint32_t n) {
  const double x = static_cast<double>(c) * n;
  if (std::abs(x) < n) return x;
  if (n > kExactScaleLimit || !std::isfinite(c)) return std::fmod(x, static_cast<double>(n));
  // From 2^23 on every float is an integer (and too large for the int32 conversion).
  const float whole =
      std::abs(c) < 8388608.0f ? static_cast<float>(static_cast<std::int32_t>(c)) : c;
  return std::copysign(static_cast<double>(c - whole), static_cast<double>(c)) * n;
}

}  // namespace

Texture::Texture(Image rgb, std::string name) : image_(std::move(rgb)), name_(std::move(name)) {
  if (image_.channels() != 3 || image_.empty())
    throw Error("Texture " + name_ + ": needs a non-empty 3-channel image");
  buildPalette();
  buildMips();
}

void Texture::buildMips() {
  std::uint32_t w = image_.width(), h = image_.height();
  const MipLevel* above = nullptr;
  while (w > 1 || h > 1) {
    MipLevel level;
    level.width = std::max(w / 2, 1u);
    level.height = std::max(h / 2, 1u);
    level.texels.resize(static_cast<std::size_t>(level.width) * level.height);
    // Texels of the level above; an odd last column or row is left out, and a side of one
    // texel wraps onto itself.
    const auto source = [&](std::uint32_t x, std::uint32_t y) {
      x %= w;
      y %= h;
      return above ? above->at(x, y) : at(x, y);
    };
    for (std::uint32_t y = 0; y < level.height; ++y)
      for (std::uint32_t x = 0; x < level.width; ++x)
        level.texels[static_cast<std::size_t>(y) * level.width + x] =
            (source(2 * x, 2 * y) + source(2 * x + 1, 2 * y) + source(2 * x, 2 * y + 1) +
             source(2 * x + 1, 2 * y + 1)) *
            0.25f;
    mips_.push_back(std::move(level));
    above = &mips_.back();
    w = above->width;
    h = above->height;
  }
}

void Texture::buildPalette() {
  // Distinct values by bit pattern (so -0 and NaN payloads keep theirs), in an open-addressing
  // table with room for 256 of them.
  constexpr std::uint32_t kSlots = 1024;
  std::vector<std::uint32_t> keys(kSlots);
  std::vector<std::int16_t> slotCode(kSlots, -1);
  std::uint32_t distinct = 0;
  const std::vector<float>& values = image_.data();
  const std::uint32_t w = image_.width(), h = image_.height();
  blocksX_ = (w + 3) / 4;
  codes_.assign(static_cast<std::size_t>(blocksX_) * ((h + 3) / 4), CodeBlock{});
  for (std::size_t i = 0; i < values.size(); ++i) {
    const auto bits = std::bit_cast<std::uint32_t>(values[i]);
    std::uint32_t slot = (bits * 2654435761u) >> 22;  // Fibonacci hashing into kSlots
    while (slotCode[slot] >= 0 && keys[slot] != bits) slot = (slot + 1) % kSlots;
    if (slotCode[slot] < 0) {
      if (distinct == palette_.size()) {  // more than 256 values: keep the float image only
        codes_.clear();
        codes_.shrink_to_fit();
        return;
      }
      keys[slot] = bits;
      slotCode[slot] = static_cast<std::int16_t>(distinct);
      palette_[distinct++] = values[i];
    }
    const std::size_t texel = i / 3;
    const auto column = static_cast<std::uint32_t>(texel % w),
               row = static_cast<std::uint32_t>(texel / w);
    codes_[static_cast<std::size_t>(row >> 2) * blocksX_ + (column >> 2)]
        .codes[(row & 3u) * 4u + (column & 3u)] |= static_cast<std::uint32_t>(slotCode[slot])
                                                   << (8 * (i % 3));
  }
}

Texture Texture::load(const std::string& path, ColorEncoding encoding) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open texture");
  char magic[2] = {0, 0};
  in.read(magic, 2);
  if (in.gcount() == 2 && magic[0] == 'P' && (magic[1] == '6' || magic[1] == '3')) {
    in.seekg(0);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                           std::istreambuf_iterator<char>());
    PpmReader reader(path, bytes);
    return Texture(reader.read(encoding), path);
  }
  return Texture(loadWithStb(path, encoding), path);
}

Vec3f Texture::texel(long long x, long long y) const {
  return at(wrap(x, image_.width()), wrap(y, image_.height()));
}

Vec3f Texture::mipTexel(std::size_t level, long long x, long long y) const {
  if (level == 0 || level > mips_.size())
    throw Error("Texture::mipTexel: level " + std::to_string(level) + " of " + name_ +
                " is not in 1.." + std::to_string(mips_.size()));
  const MipLevel& m = mips_[level - 1];
  return m.at(wrap(x, m.width), wrap(y, m.height));
}

namespace {

/// std::floor(v) as an integer, for finite |v| < 2^53 (wrapped coordinates lie within a side
/// of the level, below 2^32): the truncation, one lower where it rounded up. x86-64's baseline
/// has no rounding instruction, and std::floor took a sixth of a bilinear lookup's instructions
/// (Callgrind, a BART kitchen `opengl` frame: lookups 1285M -> 1097M, the frame 1.8% fewer).
long long floorToInteger(double v) {
  const auto i = static_cast<long long>(v);
  return static_cast<double>(i) > v ? i - 1 : i;
}

/// The four texels and weights of a bilinear lookup in a width x height level.
struct BilinearFootprint {
  std::uint32_t c0, c1, r0, r1;  ///< columns and rows, wrapped
  float ax, ay;                  ///< weights of c1 and r1
};

/// The four texels of `f` weighed: along the rows first, then between them.
template <class TexelAt>
Vec3f blend(const BilinearFootprint& f, const TexelAt& texelAt) {
  const Vec3f top = texelAt(f.c0, f.r0) * (1.0f - f.ax) + texelAt(f.c1, f.r0) * f.ax;
  const Vec3f bottom = texelAt(f.c0, f.r1) * (1.0f - f.ax) + texelAt(f.c1, f.r1) * f.ax;
  return top * (1.0f - f.ay) + bottom * f.ay;
}

}  // namespace

template <class TexelAt>
Vec3f Texture::bilinear(const Vec2f& uv, std::uint32_t width, std::uint32_t height,
                        const TexelAt& texelAt) const {
  // Work in double: u * width for u of a few thousand repeats must still pick the right texel.
  // The (exact) remainder keeps huge coordinates from overflowing the integer conversion below.
  const double x = wrapCoordinate(uv.u, width);
  const double y = wrapCoordinate(uv.v, height);
  if (!std::isfinite(x) || !std::isfinite(y)) return texelAt(0, 0);
  // Texel centres sit at half-integers; interpolate between the four around (x, y).
  const double fx = x - 0.5, fy = y - 0.5;
  const long long ix = floorToInteger(fx), iy = floorToInteger(fy);
  const auto x0 = static_cast<double>(ix), y0 = static_cast<double>(iy);
  // Each column and row wrapped once, shared by the two texels that use it.
  const BilinearFootprint f{.c0 = wrap(ix, width),
                            .c1 = wrap(ix + 1, width),
                            .r0 = wrap(iy, height),
                            .r1 = wrap(iy + 1, height),
                            .ax = static_cast<float>(fx - x0),
                            .ay = static_cast<float>(fy - y0)};
  return blend(f, texelAt);
}

Vec3f Texture::sample(const Vec2f& uv, TextureFilter filter) const {
  if (image_.empty()) return {1.0f, 1.0f, 1.0f};
  if (filter == TextureFilter::Nearest) {
    const double x = wrapCoordinate(uv.u, image_.width());
    const double y = wrapCoordinate(uv.v, image_.height());
    if (!std::isfinite(x) || !std::isfinite(y)) return texel(0, 0);
    return texel(floorToInteger(x), floorToInteger(y));
  }
  return bilinear(uv, image_.width(), image_.height(),
                  [this](std::uint32_t c, std::uint32_t r) { return at(c, r); });
}

void Texture::prefetch(const Vec2f& uv) const {
  const std::uint32_t w = image_.width(), h = image_.height();
  // The fraction of each coordinate, in float: a hint needs the block, not the exact texel.
  // Coordinates beyond 2^22, NaN and sides of 2^24 texels or more would take conversions
  // that are not defined for every value; those are left alone.
  if (w == 0 || w >= (1u << 24) || h >= (1u << 24) || !(std::abs(uv.u) < 0x1p22f) ||
      !(std::abs(uv.v) < 0x1p22f))
    return;
  const auto fraction = [](float c) {
    const float f = c - static_cast<float>(static_cast<std::int32_t>(c));
    return f < 0.0f ? f + 1.0f : f;
  };
  const auto x =
      std::min(static_cast<std::uint32_t>(fraction(uv.u) * static_cast<float>(w)), w - 1);
  const auto y =
      std::min(static_cast<std::uint32_t>(fraction(uv.v) * static_cast<float>(h)), h - 1);
  if (!codes_.empty()) {
    __builtin_prefetch(&codes_[static_cast<std::size_t>(y >> 2) * blocksX_ + (x >> 2)]);
  } else {
    __builtin_prefetch(&image_.data()[(static_cast<std::size_t>(y) * w + x) * 3]);
  }
}

namespace {

/// Where coordinate c falls in a level side of n texels, in float: the fraction of c is exact,
/// so that only the product with n rounds (by at most 2^-24 relative, a tiny part of a texel).
/// Returns false for |c| >= 2^22, NaN and sides of 2^24 texels or more (not every such side is
/// a float), which the double path handles.
bool footprintAxis(float c, std::uint32_t n, std::uint32_t& lo, std::uint32_t& hi, float& a) {
  if (!(std::abs(c) < 0x1p22f) || n >= (1u << 24)) return false;
  float f = c - static_cast<float>(static_cast<std::int32_t>(c));
  if (f < 0.0f) f += 1.0f;  // [0, 1]: 1 only for a tiny negative c, wrapped below
  const float x = f * static_cast<float>(n) - 0.5f;  // texel centres at integers: [-0.5, n - 0.5]
  const std::int32_t i = x < 0.0f ? -1 : static_cast<std::int32_t>(x);
  a = x - static_cast<float>(i);
  lo = i < 0 ? n - 1 : static_cast<std::uint32_t>(i);
  hi = static_cast<std::uint32_t>(i + 1) >= n ? static_cast<std::uint32_t>(i + 1) - n
                                              : static_cast<std::uint32_t>(i + 1);
  return true;
}

}  // namespace

template <class TexelAt>
Vec3f Texture::bilinearFloat(const Vec2f& uv, std::uint32_t width, std::uint32_t height,
                             const TexelAt& texelAt) const {
  BilinearFootprint f;
  if (!footprintAxis(uv.u, width, f.c0, f.c1, f.ax) ||
      !footprintAxis(uv.v, height, f.r0, f.r1, f.ay))
    return bilinear(uv, width, height, texelAt);
  return blend(f, texelAt);
}

Vec3f Texture::sample(const Vec2f& uv, TextureFilter filter, float lod) const {
  if (filter != TextureFilter::Trilinear || !(lod > 0.0f) || mips_.empty())
    return sample(uv, filter);
  const auto last = static_cast<float>(mips_.size());
  const float level = std::min(lod, last);
  const auto upper = static_cast<std::size_t>(level);  // floor: level > 0
  const float blend = level - static_cast<float>(upper);
  // Minified lookups in float (bilinearFloat): the double arithmetic of the full-resolution
  // path cost more than the rest of the lookup, for nothing visible at these sizes.
  const auto lookup = [&](std::size_t l) {
    if (l == 0)
      return bilinearFloat(uv, image_.width(), image_.height(),
                           [this](std::uint32_t c, std::uint32_t r) { return at(c, r); });
    const MipLevel& m = mips_[l - 1];
    return bilinearFloat(uv, m.width, m.height,
                         [&m](std::uint32_t c, std::uint32_t r) { return m.at(c, r); });
  };
  const Vec3f a = lookup(upper);
  if (blend == 0.0f) return a;
  return a * (1.0f - blend) + lookup(upper + 1) * blend;
}

}  // namespace tg
