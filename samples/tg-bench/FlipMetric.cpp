// FLIP after Andersson et al. (2020): a colour pipeline (opponent space, contrast-sensitivity
// blur, Hunt-adjusted L*a*b*, HyAB distance) and a feature pipeline (edge and point detectors on
// luminance), combined per pixel. The constants are the paper's.
#include "FlipMetric.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace tg::bench {
namespace {

using Colour = std::array<double, 3>;
/// One channel of an image, row-major.
using Plane = std::vector<double>;

/// D65 reference white of the sRGB primaries (the matrices below).
constexpr Colour kWhite = {0.95047, 1.0, 1.08883};

Colour linearRgbToXyz(const Colour& c) {
  return {0.4124564 * c[0] + 0.3575761 * c[1] + 0.1804375 * c[2],
          0.2126729 * c[0] + 0.7151522 * c[1] + 0.0721750 * c[2],
          0.0193339 * c[0] + 0.1191920 * c[1] + 0.9503041 * c[2]};
}

Colour xyzToLinearRgb(const Colour& c) {
  return {3.2404542 * c[0] - 1.5371385 * c[1] - 0.4985314 * c[2],
          -0.9692660 * c[0] + 1.8760108 * c[1] + 0.0415560 * c[2],
          0.0556434 * c[0] - 0.2040259 * c[1] + 1.0572252 * c[2]};
}

/// YCxCz: a linear opponent space (luminance, red-green, blue-yellow) in which FLIP blurs,
/// since the contrast sensitivity functions are defined per opponent channel.
Colour xyzToYcxcz(const Colour& c) {
  const double x = c[0] / kWhite[0], y = c[1] / kWhite[1], z = c[2] / kWhite[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Colour ycxczToXyz(const Colour& c) {
  const double y = (c[0] + 16.0) / 116.0;
  return {kWhite[0] * (y + c[1] / 500.0), kWhite[1] * y, kWhite[2] * (y - c[2] / 200.0)};
}

/// CIELAB with the Hunt adjustment (chroma scaled by 0.01 L): dark colours differ less.
Colour linearRgbToHuntLab(const Colour& rgb) {
  const Colour xyz = linearRgbToXyz(rgb);
  constexpr double delta = 6.0 / 29.0;
  const auto f = [&](double t) {
    return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / kWhite[0]), fy = f(xyz[1] / kWhite[1]), fz = f(xyz[2] / kWhite[2]);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

/// HyAB: city-block in lightness, Euclidean in chroma, which matches large colour differences
/// better than the Euclidean ΔE.
double hyab(const Colour& a, const Colour& b) {
  return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]);
}

/// A square kernel of (2 radius + 1)^2 weights, row-major.
struct Kernel {
  int radius = 0;
  std::vector<double> w;
  double at(int x, int y) const { return w[(y + radius) * (2 * radius + 1) + (x + radius)]; }
};

/// Convolution with clamp-to-edge borders.
Plane convolve(const Plane& in, int width, int height, const Kernel& k) {
  Plane out(in.size(), 0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int dy = -k.radius; dy <= k.radius; ++dy) {
        const int sy = std::clamp(y + dy, 0, height - 1);
        for (int dx = -k.radius; dx <= k.radius; ++dx) {
          const int sx = std::clamp(x + dx, 0, width - 1);
          sum += k.at(dx, dy) * in[static_cast<std::size_t>(sy) * width + sx];
        }
      }
      out[static_cast<std::size_t>(y) * width + x] = sum;
    }
  return out;
}

/// The spatial contrast-sensitivity filter of one opponent channel: a sum of two Gaussians in
/// degrees of visual angle, normalised to unit sum. All channels share the radius of the widest.
Kernel csfKernel(double a1, double b1, double a2, double b2, double ppd) {
  constexpr double kWidestB = 0.04;
  constexpr double pi = std::numbers::pi;
  Kernel k;
  k.radius = static_cast<int>(std::ceil(3.0 * std::sqrt(kWidestB / (2.0 * pi * pi)) * ppd));
  double sum = 0.0;
  for (int y = -k.radius; y <= k.radius; ++y)
    for (int x = -k.radius; x <= k.radius; ++x) {
      const double d2 = (x * x + y * y) / (ppd * ppd);
      const double w = a1 * std::sqrt(pi / b1) * std::exp(-pi * pi * d2 / b1) +
                       a2 * std::sqrt(pi / b2) * std::exp(-pi * pi * d2 / b2);
      k.w.push_back(w);
      sum += w;
    }
  for (double& w : k.w) w /= sum;
  return k;
}

/// First (edges) or second (points) derivative of a Gaussian along x whose peak-to-trough width
/// is 0.082 degrees, positive weights scaled to sum 1 and negative ones to sum -1.
Kernel featureKernel(bool point, double ppd, bool transpose) {
  const double sd = 0.5 * 0.082 * ppd;
  Kernel k;
  k.radius = std::max(1, static_cast<int>(std::ceil(3.0 * sd)));
  double positive = 0.0, negative = 0.0;
  for (int y = -k.radius; y <= k.radius; ++y)
    for (int x = -k.radius; x <= k.radius; ++x) {
      const double g = std::exp(-(x * x + y * y) / (2.0 * sd * sd));
      const double w = point ? (x * x / (sd * sd) - 1.0) * g : -x * g;
      k.w.push_back(w);
      (w > 0.0 ? positive : negative) += w;
    }
  for (double& w : k.w) {
    // A side that underflowed to zero (a tiny sd) stays zero rather than dividing by it.
    if (w > 0.0 && positive > 0.0) w /= positive;
    if (w < 0.0 && negative < 0.0) w /= -negative;
  }
  if (transpose) {
    const int n = 2 * k.radius + 1;
    for (int y = 0; y < n; ++y)
      for (int x = y + 1; x < n; ++x) std::swap(k.w[y * n + x], k.w[x * n + y]);
  }
  return k;
}

/// Magnitude of the feature response (x and y filters) of a plane.
Plane featureMagnitude(const Plane& in, int width, int height, bool point, double ppd) {
  const Plane fx = convolve(in, width, height, featureKernel(point, ppd, false));
  const Plane fy = convolve(in, width, height, featureKernel(point, ppd, true));
  Plane out(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = std::hypot(fx[i], fy[i]);
  return out;
}

/// What both images go through: the opponent planes blurred by the CSFs and turned back into
/// Hunt-adjusted L*a*b*, and the luminance the feature detectors look at.
struct Perceived {
  std::vector<Colour> lab;
  Plane edges, points;
};

Perceived perceive(const LinearImage& image, double ppd) {
  const int w = image.width, h = image.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::array<Plane, 3> opponent;
  for (Plane& p : opponent) p.resize(n);
  Plane luminance(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Colour c =
        xyzToYcxcz(linearRgbToXyz({image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]}));
    for (int ch = 0; ch < 3; ++ch) opponent[ch][i] = c[ch];
    // Normalised to [0, 1] for the detectors, whose weights assume that range.
    luminance[i] = (c[0] + 16.0) / 116.0;
  }
  // Achromatic, red-green and blue-yellow contrast sensitivities (the FLIP paper's fits).
  const std::array<Kernel, 3> csf = {csfKernel(1.0, 0.0047, 0.0, 1e-5, ppd),
                                     csfKernel(1.0, 0.0053, 0.0, 1e-5, ppd),
                                     csfKernel(34.1, 0.04, 13.5, 0.025, ppd)};
  for (int ch = 0; ch < 3; ++ch) opponent[ch] = convolve(opponent[ch], w, h, csf[ch]);
  Perceived p;
  p.lab.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Colour rgb = xyzToLinearRgb(ycxczToXyz({opponent[0][i], opponent[1][i], opponent[2][i]}));
    for (double& v : rgb) v = std::clamp(v, 0.0, 1.0);
    p.lab[i] = linearRgbToHuntLab(rgb);
  }
  p.edges = featureMagnitude(luminance, w, h, false, ppd);
  p.points = featureMagnitude(luminance, w, h, true, ppd);
  return p;
}

/// Maps a colour difference (HyAB^0.7) to [0, 1]: differences up to 40 % of the largest one
/// (green against blue) take up 95 % of the range, so that small errors stay visible.
double redistribute(double difference) {
  constexpr double qc = 0.7, pc = 0.4, pt = 0.95;
  static const double cmax =
      std::pow(hyab(linearRgbToHuntLab({0.0, 1.0, 0.0}), linearRgbToHuntLab({0.0, 0.0, 1.0})), qc);
  const double e = std::pow(difference, qc);
  if (e < pc * cmax) return pt * e / (pc * cmax);
  return std::min(1.0, pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt));
}

}  // namespace

LinearImage LinearImage::grey(int width, int height, std::span<const double> values) {
  LinearImage image;
  image.width = width;
  image.height = height;
  image.rgb.reserve(3 * values.size());
  for (const double v : values)
    for (int ch = 0; ch < 3; ++ch) image.rgb.push_back(static_cast<float>(std::clamp(v, 0.0, 1.0)));
  return image;
}

std::vector<float> flipErrorMap(const LinearImage& reference, const LinearImage& test,
                                double pixelsPerDegree) {
  if (reference.width != test.width || reference.height != test.height ||
      reference.rgb.size() != test.rgb.size() ||
      reference.rgb.size() != 3 * static_cast<std::size_t>(reference.width) * reference.height)
    throw std::invalid_argument("flipErrorMap: images of different or inconsistent sizes");
  if (!(pixelsPerDegree > 0.0))
    throw std::invalid_argument("flipErrorMap: pixels per degree must be positive");
  const Perceived r = perceive(reference, pixelsPerDegree);
  const Perceived t = perceive(test, pixelsPerDegree);
  std::vector<float> error(r.lab.size());
  for (std::size_t i = 0; i < error.size(); ++i) {
    const double colour = redistribute(hyab(r.lab[i], t.lab[i]));
    const double feature =
        std::sqrt(std::max(std::abs(r.edges[i] - t.edges[i]), std::abs(r.points[i] - t.points[i])) /
                  std::numbers::sqrt2);
    // A feature difference raises the colour error towards 1 (the exponent shrinks towards 0).
    error[i] = static_cast<float>(std::pow(colour, 1.0 - std::min(feature, 1.0)));
  }
  return error;
}

double flipMean(const LinearImage& reference, const LinearImage& test, double pixelsPerDegree) {
  const std::vector<float> error = flipErrorMap(reference, test, pixelsPerDegree);
  if (error.empty()) return 0.0;
  double sum = 0.0;
  for (const float e : error) sum += static_cast<double>(e);
  return sum / static_cast<double>(error.size());
}

}  // namespace tg::bench
