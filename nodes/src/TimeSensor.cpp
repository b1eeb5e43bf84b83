#include "tracegraph/nodes/TimeSensor.h"

#include <cmath>

namespace tg::nodes {

void TimeSensor::evaluate(double now) {
  if (!enabled.getValue()) return;
  time.setValue(now);
  const double cycle = cycleInterval.getValue();
  const double local = now - startTime.getValue();
  double f = 0.0;
  if (cycle > 0.0 && local > 0.0) {
    if (loop.getValue()) {
      f = std::fmod(local, cycle) / cycle;
    } else {
      f = local >= cycle ? 1.0 : local / cycle;
    }
  }
  fraction_changed.setValue(static_cast<float>(f));
}

}  // namespace tg::nodes
