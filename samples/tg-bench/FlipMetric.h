/// @file FlipMetric.h
/// A compact perceptual image difference after FLIP (Andersson et al. 2020, "FLIP: A Difference
/// Evaluator for Alternating Images"). PSNR weighs every wrong pixel alike; FLIP weighs an error
/// by what a viewer notices at a given viewing distance: colours are compared in an opponent
/// space after the eye's contrast sensitivity has blurred them, and edges and points that
/// appear or vanish count extra. This is the LDR variant without FLIP's pooling options.
#pragma once

#include <span>
#include <vector>

namespace tg::bench {

/// A linear-RGB image, row-major from the top row, three floats a pixel, values in [0, 1].
struct LinearImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  ///< 3 * width * height values: r, g, b of each pixel

  /// A grey image of `width` x `height` pixels with r = g = b = values[i] (clamped to [0, 1]).
  static LinearImage grey(int width, int height, std::span<const double> values);
};

/// FLIP's default observer: a 0.7 m wide monitor of 3840 pixels seen from 0.7 m, about 67 pixels
/// per degree of visual angle.
inline constexpr double kFlipDefaultPixelsPerDegree = 3840.0 * 3.14159265358979323846 / 180.0;

/// Per-pixel error in [0, 1] of `test` against `reference` seen at `pixelsPerDegree`, row-major.
/// Throws std::invalid_argument when the sizes differ or pixelsPerDegree is not positive.
std::vector<float> flipErrorMap(const LinearImage& reference, const LinearImage& test,
                                double pixelsPerDegree);

/// Mean of flipErrorMap: 0 for identical images, at most 1; 0 for empty images.
double flipMean(const LinearImage& reference, const LinearImage& test,
                double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

}  // namespace tg::bench
