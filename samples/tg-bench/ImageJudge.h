/// @file ImageJudge.h
/// Primary-ray images judged against the double-precision reference render: mismatching hits,
/// eye-light PSNR and the perceptual FLIP error (FlipMetric.h) of the same traced answers.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "BenchReport.h"
#include "FlipMetric.h"
#include "HitComparison.h"
#include "RayGenerators.h"
#include "tracegraph/backend/ReferenceIntersector.h"
#include "tracegraph/backend/Scene.h"

namespace tg::bench {

/// Every `stride`-th pixel of an image in both directions, from the first one.
struct PixelGrid {
  ImageSize size;                   ///< the grid's own width and height
  std::size_t stride = 1;           ///< image pixels between two grid pixels
  std::vector<std::size_t> pixels;  ///< row-major indices into the image, grid order
};

/// The finest grid (smallest stride) of `image` with at most `maxPixels` pixels (at least one).
PixelGrid makePixelGrid(ImageSize image, std::size_t maxPixels);

/// The reference's eye-light image on a pixel grid of a primary-ray image, against which traced
/// answers are scored with FLIP. The brute-force reference is too slow for every pixel, so it
/// renders a regular grid: a FLIP image needs neighbouring pixels, which a strided subsample of
/// the row-major rays does not keep. The grid is viewed as the whole image would be at FLIP's
/// default 67 pixels per degree, i.e. at 67 / stride pixels per degree.
class ReferenceImage {
 public:
  /// Renders the reference answers of the grid's rays (in parallel in the calling task arena).
  /// `scene` (committed) must outlive this object; `rays` are the image's primary rays,
  /// row-major.
  ReferenceImage(const Scene& scene, const ReferenceIntersector& reference,
                 std::span<const Ray> rays, ImageSize size, std::size_t maxPixels);

  /// FLIP mean error of the eye-light image of `outcomes` (one per ray of the whole image, ids
  /// of `scene`) against the reference's.
  double flipMean(std::span<const RayOutcome> outcomes) const;

 private:
  const Scene& scene_;
  PixelGrid grid_;
  std::vector<Ray> rays_;
  LinearImage expected_;
};

/// Subsampled rays judged by the brute-force reference (mismatches, PSNR) and its FLIP image,
/// for suites that trace a primary-ray image several ways and judge each trace alike.
class PrimaryImageJudge {
 public:
  /// Builds the reference from `scene` (committed; must outlive this object) and renders what
  /// it judges with: `judgedRays` of `rays` and a FLIP grid of as many pixels.
  PrimaryImageJudge(const Scene& scene, std::span<const Ray> rays, ImageSize size,
                    std::size_t judgedRays);

  /// Adds ref_mismatches, judged, psnr_db and flip_mean for `outcomes` (one per ray, ids of
  /// `scene`) to `row`.
  void judge(BenchRow& row, std::span<const RayOutcome> outcomes) const;

 private:
  const Scene& scene_;
  std::size_t judgedRays_;
  ReferenceIntersector reference_;
  std::vector<Ray> judged_;
  std::vector<ReferenceHit> expected_;
  ReferenceImage image_;
};

}  // namespace tg::bench
