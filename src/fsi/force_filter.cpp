// Moving time mean of the imported nodal forces over FILTER (force_filter.h).
#include "fsi/force_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace quarry::fsi {

void ForceFilter::add(std::vector<Vec3> impulse, double duration) {
  periods_.push_back({std::move(impulse), duration});
  // Keep the periods that still reach into the window, newest back.
  double newer = 0.0;  // s covered by the periods after the one looked at
  std::size_t keep = 0;
  for (auto p = periods_.rbegin(); p != periods_.rend() && newer < window_; ++p) {
    newer += p->duration;
    ++keep;
  }
  while (periods_.size() > keep) periods_.pop_front();
}

void ForceFilter::mean(std::vector<Vec3>& force) const {
  if (periods_.empty()) {
    std::fill(force.begin(), force.end(), Vec3{});
    return;
  }
  force.assign(periods_.back().impulse.size(), Vec3{});
  double covered = 0.0;  // s
  for (auto p = periods_.rbegin(); p != periods_.rend(); ++p) {
    // The share of this period inside the window (the oldest may stick out of it).
    const double inside = std::min(p->duration, window_ - covered);
    const double weight = p->duration > 0.0 ? inside / p->duration : 0.0;
    for (std::size_t n = 0; n < force.size(); ++n) force[n] += weight * p->impulse[n];
    covered += inside;
  }
  if (covered > 0.0)
    for (Vec3& f : force) f = f / covered;
}

void ForceFilter::set_state(double window, std::deque<Period> periods) {
  if (!(window > 0.0) || !std::isfinite(window))
    throw std::invalid_argument(fmt::format("the force filter's window {} s is not a time > 0", window));
  for (std::size_t k = 0; k < periods.size(); ++k) {
    const Period& p = periods[k];
    if (!(p.duration >= 0.0) || !std::isfinite(p.duration) || p.impulse.size() != periods.front().impulse.size())
      throw std::invalid_argument(fmt::format("the force filter's period {} lasts {} s over {} nodes (the first: {})", k,
                                              p.duration, p.impulse.size(), periods.front().impulse.size()));
    for (const Vec3& j : p.impulse)
      if (!std::isfinite(j.x) || !std::isfinite(j.y) || !std::isfinite(j.z))
        throw std::invalid_argument(fmt::format("the force filter's period {} holds an impulse that is not finite", k));
  }
  window_ = window;
  periods_ = std::move(periods);
}

}  // namespace quarry::fsi
