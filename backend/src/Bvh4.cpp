// Constants of the BVH4 box tests that must stay out of sight of the walks (Bvh4.h).
#include "Bvh4.h"

namespace tg::detail {

alignas(32) const float kBvhWidenFactors[2][8] = {
    {1.0f - kBvhIntervalSlack, 1.0f - kBvhIntervalSlack, 1.0f - kBvhIntervalSlack,
     1.0f - kBvhIntervalSlack, 1.0f - kBvhIntervalSlack, 1.0f - kBvhIntervalSlack,
     1.0f - kBvhIntervalSlack, 1.0f - kBvhIntervalSlack},
    {1.0f + kBvhIntervalSlack, 1.0f + kBvhIntervalSlack, 1.0f + kBvhIntervalSlack,
     1.0f + kBvhIntervalSlack, 1.0f + kBvhIntervalSlack, 1.0f + kBvhIntervalSlack,
     1.0f + kBvhIntervalSlack, 1.0f + kBvhIntervalSlack}};

}  // namespace tg::detail
