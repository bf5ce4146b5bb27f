// ProgressEta: exponentially weighted pace and the time left.
#include "core/progress_eta.h"

#include <cmath>

namespace quarry {

void ProgressEta::add(double simulated, double wall) {
  if (!(wall >= 0.0) || !(simulated >= 0.0)) return;  // a clock step backwards, NaN: ignored
  const double decay = tau_ > 0.0 ? std::exp(-wall / tau_) : 0.0;
  simulated_ = simulated_ * decay + simulated;
  wall_ = wall_ * decay + wall;
}

double ProgressEta::seconds_left(double remaining) const {
  const double p = pace();
  if (!(p > 0.0)) return NAN;
  return remaining > 0.0 ? remaining / p : 0.0;
}

}  // namespace quarry
