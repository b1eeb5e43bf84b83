// Known cases of the FLIP metric: it must be zero for equal images, small for what a viewer
// barely sees, large for what anyone sees, and grow with the error.
#define BOOST_TEST_MODULE tg_bench_flip
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "FlipMetric.h"

namespace {

using tg::bench::flipMean;
using tg::bench::LinearImage;

constexpr int kSize = 48;

/// A smooth pattern with a few sharp edges, as a rendered image has: a horizontal gradient
/// with a darker square in the middle.
std::vector<double> pattern(int shiftX = 0) {
  std::vector<double> v;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const int sx = x - shiftX;
      const bool square = sx >= 16 && sx < 32 && y >= 16 && y < 32;
      v.push_back(square ? 0.1 : 0.3 + 0.5 * (sx + 0.5) / kSize);
    }
  return v;
}

LinearImage image(const std::vector<double>& values) {
  return LinearImage::grey(kSize, kSize, values);
}

/// `base` plus uniform noise of amplitude `amount`, the same noise pattern for every amount.
LinearImage noisy(const std::vector<double>& base, double amount) {
  std::mt19937 random(7);
  std::vector<double> v = base;
  for (double& x : v) x += amount * (static_cast<double>(random()) / random.max() * 2.0 - 1.0);
  return image(v);
}

}  // namespace

BOOST_AUTO_TEST_CASE(identical_images_score_zero) {
  const LinearImage a = image(pattern());
  BOOST_TEST(flipMean(a, a) == 0.0);
  BOOST_TEST(flipMean(a, a, 2.0) == 0.0);
}

BOOST_AUTO_TEST_CASE(a_one_pixel_shift_scores_small) {
  const double shifted = flipMean(image(pattern()), image(pattern(1)));
  BOOST_TEST(shifted > 0.0);
  BOOST_TEST(shifted < 0.1);
}

BOOST_AUTO_TEST_CASE(an_inverted_image_scores_large) {
  // Blocks of 8 pixels, dark and bright: inverting them swaps black and white almost everywhere.
  std::vector<double> blocks, inverted;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      blocks.push_back((x / 8 + y / 8) % 2 == 0 ? 0.05 : 0.95);
      inverted.push_back(1.0 - blocks.back());
    }
  BOOST_TEST(flipMean(image(blocks), image(inverted)) > 0.7);
}

BOOST_AUTO_TEST_CASE(the_score_grows_with_noise) {
  const std::vector<double> base = pattern();
  double previous = 0.0;
  for (const double amount : {0.01, 0.03, 0.1, 0.3}) {
    const double e = flipMean(image(base), noisy(base, amount));
    BOOST_TEST_INFO("noise " << amount);
    BOOST_TEST(e > previous);
    BOOST_TEST(e <= 1.0);
    previous = e;
  }
}

BOOST_AUTO_TEST_CASE(a_colour_error_counts) {
  // Same luminance would hide a hue change from a grey metric; FLIP sees it.
  LinearImage red = image(std::vector<double>(kSize * kSize, 0.5));
  const LinearImage grey = red;
  for (std::size_t i = 0; i < red.rgb.size(); i += 3) red.rgb[i + 1] = red.rgb[i + 2] = 0.2f;
  BOOST_TEST(flipMean(grey, red) > 0.3);
}

BOOST_AUTO_TEST_CASE(mismatched_sizes_are_rejected) {
  const LinearImage a = image(pattern());
  const LinearImage b = LinearImage::grey(1, 1, std::vector<double>{0.5});
  BOOST_CHECK_THROW(flipMean(a, b), std::invalid_argument);
  BOOST_CHECK_THROW(flipMean(a, a, 0.0), std::invalid_argument);
}
