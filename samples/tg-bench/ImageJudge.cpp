#include "ImageJudge.h"

#include <cmath>

#include "ReferenceJudge.h"
#include "SuiteCommon.h"

namespace tg::bench {

PixelGrid makePixelGrid(ImageSize image, std::size_t maxPixels) {
  PixelGrid grid;
  const auto cells = [](int extent, std::size_t stride) {
    return static_cast<int>((static_cast<std::size_t>(extent) + stride - 1) / stride);
  };
  // The smallest stride that fits; starting from the square-root estimate keeps this short.
  const double ratio = static_cast<double>(image.pixels()) / static_cast<double>(maxPixels);
  grid.stride = std::max<std::size_t>(1, static_cast<std::size_t>(std::floor(std::sqrt(ratio))));
  while (static_cast<std::size_t>(cells(image.width, grid.stride)) *
             cells(image.height, grid.stride) >
         std::max<std::size_t>(maxPixels, 1))
    ++grid.stride;
  grid.size = {cells(image.width, grid.stride), cells(image.height, grid.stride)};
  for (std::size_t y = 0; y < static_cast<std::size_t>(image.height); y += grid.stride)
    for (std::size_t x = 0; x < static_cast<std::size_t>(image.width); x += grid.stride)
      grid.pixels.push_back(y * static_cast<std::size_t>(image.width) + x);
  return grid;
}

namespace {

/// The eye-light image of answers on the grid's rays.
LinearImage eyeLightImage(const Scene& scene, const PixelGrid& grid, std::span<const Ray> rays,
                          std::span<const RayOutcome> answers) {
  std::vector<double> values(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
    values[i] = eyeLight(scene, rays[i], answers[i].instance, answers[i].prim);
  return LinearImage::grey(grid.size.width, grid.size.height, values);
}

}  // namespace

ReferenceImage::ReferenceImage(const Scene& scene, const ReferenceIntersector& reference,
                               std::span<const Ray> rays, ImageSize size, std::size_t maxPixels)
    : scene_(scene), grid_(makePixelGrid(size, maxPixels)) {
  for (const std::size_t p : grid_.pixels) rays_.push_back(rays[p]);
  std::vector<RayOutcome> answers;
  for (const ReferenceHit& h : referenceHits(reference, rays_))
    answers.push_back(h.hit ? RayOutcome{h.instanceId, h.primId} : RayOutcome{});
  expected_ = eyeLightImage(scene_, grid_, rays_, answers);
}

double ReferenceImage::flipMean(std::span<const RayOutcome> outcomes) const {
  std::vector<RayOutcome> answers;
  for (const std::size_t p : grid_.pixels) answers.push_back(outcomes[p]);
  return tg::bench::flipMean(expected_, eyeLightImage(scene_, grid_, rays_, answers),
                             kFlipDefaultPixelsPerDegree / static_cast<double>(grid_.stride));
}

PrimaryImageJudge::PrimaryImageJudge(const Scene& scene, std::span<const Ray> rays, ImageSize size,
                                     std::size_t judgedRays)
    : scene_(scene),
      judgedRays_(judgedRays),
      reference_(scene),
      judged_(subsampleRays(rays, judgedRays)),
      expected_(referenceHits(reference_, judged_)),
      image_(scene, reference_, rays, size, judgedRays) {}

void PrimaryImageJudge::judge(BenchRow& row, std::span<const RayOutcome> outcomes) const {
  const std::vector<RayOutcome> sub = subsampleOutcomes(outcomes, judgedRays_);
  row.extra.push_back(intField(
      "ref_mismatches", static_cast<std::int64_t>(judgeOutcomes(expected_, sub).mismatches)));
  row.extra.push_back(intField("judged", static_cast<std::int64_t>(judged_.size())));
  row.extra.push_back(realField("psnr_db", eyeLightPsnr(scene_, judged_, expected_, sub)));
  row.extra.push_back(realField("flip_mean", image_.flipMean(outcomes)));
}

}  // namespace tg::bench
