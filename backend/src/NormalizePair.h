// Two double vectors normalised and rounded to float together, two lanes per SSE2 instruction:
// the hit normals of a packet (Scene.cpp) and the primary rays of two pixels (Camera.cpp).
// Internal header: not installed.
#pragma once

#if defined(__SSE2__)
#include <emmintrin.h>

#include "tracegraph/backend/Vec3.h"

namespace tg::detail {

/// Vec3f(normalize(v)) of the vector whose components are lane k of x, y and z, into out[k],
/// for k = 0, 1, bit for bit: normalize's operations in its order (no fused multiply-add in
/// the baseline units that include this; square root, division and the rounding to float are
/// correctly rounded in vectors as in scalars). Three divisions and a square root per vector
/// would otherwise run one vector after the other.
inline void normalizePair(__m128d x, __m128d y, __m128d z, Vec3f (&out)[2]) {
  const __m128d length =
      _mm_sqrt_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(x, x), _mm_mul_pd(y, y)), _mm_mul_pd(z, z)));
  alignas(16) float fx[4], fy[4], fz[4];
  _mm_store_ps(fx, _mm_cvtpd_ps(_mm_div_pd(x, length)));
  _mm_store_ps(fy, _mm_cvtpd_ps(_mm_div_pd(y, length)));
  _mm_store_ps(fz, _mm_cvtpd_ps(_mm_div_pd(z, length)));
  out[0] = {fx[0], fy[0], fz[0]};
  out[1] = {fx[1], fy[1], fz[1]};
}

}  // namespace tg::detail
#endif
