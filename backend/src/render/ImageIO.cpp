#include "tracegraph/backend/render/ImageIO.h"

#include "tracegraph/backend/Ray.h"

#include <stb_image_write.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "tracegraph/backend/Error.h"

namespace tg {
namespace {

std::uint8_t toByte(float v, PngEncoding encoding) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 1.0f) return 255;
  const float e = encoding == PngEncoding::Srgb ? srgbEncode(v) : v;
  return static_cast<std::uint8_t>(std::lround(e * 255.0f));
}

std::uint32_t byteSwap(std::uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xFF00u) | ((v << 8) & 0xFF0000u) | (v << 24);
}

}  // namespace

float srgbEncode(float linear) {
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float srgbDecode(float encoded) {
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

void writePng(const Image& image, const std::string& path, PngEncoding encoding) {
  const std::uint32_t c = image.channels();
  if (c != 1 && c != 3 && c != 4)
    throw Error(path + ": cannot write a " + std::to_string(c) + "-channel image as PNG");
  if (image.empty()) throw Error(path + ": cannot write an empty image as PNG");
  std::vector<std::uint8_t> bytes(image.data().size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    // Alpha is never sRGB-encoded.
    const bool alpha = c == 4 && i % 4 == 3;
    bytes[i] = toByte(image.data()[i], alpha ? PngEncoding::Linear : encoding);
  }
  const int w = static_cast<int>(image.width()), h = static_cast<int>(image.height());
  const int ok = stbi_write_png(path.c_str(), w, h, static_cast<int>(c), bytes.data(),
                                w * static_cast<int>(c));
  if (ok == 0) throw Error(path + ": cannot write PNG");
}

void writePfm(const Image& image, const std::string& path) {
  const std::uint32_t c = image.channels();
  if (c != 1 && c != 3) throw Error(path + ": PFM holds 1 or 3 channels, not " + std::to_string(c));
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(path + ": cannot open for writing");
  // A negative scale declares little-endian data; we write little-endian on every host.
  out << (c == 3 ? "PF" : "Pf") << '\n' << image.width() << ' ' << image.height() << "\n-1.0\n";
  const std::size_t rowValues = static_cast<std::size_t>(image.width()) * c;
  std::vector<std::uint32_t> row(rowValues);
  for (std::uint32_t y = image.height(); y-- > 0;) {  // bottom row first
    std::memcpy(row.data(), image.data().data() + y * rowValues, rowValues * sizeof(float));
    if constexpr (std::endian::native == std::endian::big)
      for (std::uint32_t& v : row) v = byteSwap(v);
    out.write(reinterpret_cast<const char*>(row.data()),
              static_cast<std::streamsize>(rowValues * sizeof(float)));
  }
  if (!out) throw Error(path + ": write failed");
}

Image readPfm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open");
  std::string magic;
  long long w = 0, h = 0;
  double scale = 0.0;
  in >> magic >> w >> h >> scale;
  if (!in || (magic != "PF" && magic != "Pf")) throw Error(path + ": not a PFM file (bad header)");
  if (w <= 0 || h <= 0 || w > (1 << 16) || h > (1 << 16) || scale == 0.0 || !std::isfinite(scale))
    throw Error(path + ": bad PFM size or scale");
  in.get();  // the single whitespace character that ends the header
  const std::uint32_t c = magic == "PF" ? 3 : 1;
  // Check the size before allocating, so that a corrupt header cannot ask for gigabytes.
  const std::streampos dataStart = in.tellg();
  in.seekg(0, std::ios::end);
  const auto available = static_cast<unsigned long long>(in.tellg() - dataStart);
  in.seekg(dataStart);
  const unsigned long long needed =
      static_cast<unsigned long long>(w) * static_cast<unsigned long long>(h) * c * sizeof(float);
  if (available < needed)
    throw Error(path + ": truncated PFM data (" + std::to_string(available) + " bytes for " +
                std::to_string(needed) + ")");
  Image image(static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h), c);
  const std::size_t rowValues = static_cast<std::size_t>(w) * c;
  const bool swap = (scale < 0.0) != (std::endian::native == std::endian::little);
  std::vector<std::uint32_t> row(rowValues);
  for (std::uint32_t y = image.height(); y-- > 0;) {
    in.read(reinterpret_cast<char*>(row.data()),
            static_cast<std::streamsize>(rowValues * sizeof(float)));
    if (!in) throw Error(path + ": truncated PFM data");
    if (swap)
      for (std::uint32_t& v : row) v = byteSwap(v);
    std::memcpy(image.data().data() + y * rowValues, row.data(), rowValues * sizeof(float));
  }
  return image;
}

void writeIdPfm(const IdImage& ids, const std::string& path) {
  Image image(ids.width(), ids.height(), 1);
  for (std::uint32_t y = 0; y < ids.height(); ++y)
    for (std::uint32_t x = 0; x < ids.width(); ++x) {
      const std::uint32_t id = ids.at(x, y);
      image.at(x, y) = id == kInvalidId ? -1.0f : static_cast<float>(id);
    }
  writePfm(image, path);
}

}  // namespace tg
