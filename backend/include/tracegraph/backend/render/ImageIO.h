/// @file ImageIO.h
/// Writing framebuffers and AOVs: PNG (8-bit, display) and PFM (float, analysis).
///
/// AOV file conventions used by the renderer's tools:
/// - beauty: PNG, sRGB-encoded 8-bit (values clamped to [0, 1]); optionally PFM "PF" (linear).
/// - depth: PFM "Pf", one channel, distance along the unit ray direction, +inf where nothing
///   was hit.
/// - normal: PFM "PF", world-space shading normal, 0 0 0 where nothing was hit.
/// - instance id, primitive id: PFM "Pf", the id as a float (exact up to 2^24 = 16,777,216),
///   -1 where nothing was hit. PFM rather than 16-bit PNG because ids above 65,535 are common
///   (primitive ids of large meshes) and PFM needs no extra library.
#pragma once

#include <string>

#include "tracegraph/backend/render/Image.h"

namespace tg {

/// How writePng maps linear values to 8-bit codes.
enum class PngEncoding {
  Srgb,    ///< sRGB transfer curve (what displays expect of a PNG)
  Linear,  ///< value * 255 as is (for masks and debug images)
};

/// Writes a 1-, 3- or 4-channel image as an 8-bit PNG; values are clamped to [0, 1] and NaN
/// becomes 0. Throws tg::Error naming the file on failure.
void writePng(const Image& image, const std::string& path,
              PngEncoding encoding = PngEncoding::Srgb);

/// Writes a 1-channel ("Pf") or 3-channel ("PF") image as a little-endian PFM: header
/// "PF\n<w> <h>\n-1.0\n", then rows from the bottom row of the image up, as the format
/// specifies. Throws tg::Error naming the file on failure or for other channel counts.
void writePfm(const Image& image, const std::string& path);

/// Writes an id buffer as a one-channel PFM: the id as a float, -1 for kInvalidId (no hit).
void writeIdPfm(const IdImage& ids, const std::string& path);
/// Reads a PFM written by writePfm or any standard writer (either byte order, any positive
/// scale, which is ignored). Row 0 of the result is the top row. Throws tg::Error naming the
/// file for malformed or truncated files.
Image readPfm(const std::string& path);

/// sRGB transfer function, linear [0, 1] -> encoded [0, 1].
float srgbEncode(float linear);
/// Inverse sRGB transfer function, encoded [0, 1] -> linear [0, 1].
float srgbDecode(float encoded);

}  // namespace tg
