// FILTER of the EDEM card (seed 000): the forces the structure imports are the time mean of the
// DEM's nodal forces over the last FILTER seconds, built from the per-period impulses the DEM's
// load window gives at each sync. FILTER = PERIOD: the mean of the last period alone, so the
// structure receives exactly the impulse the particles gave (structure_coupler.h).
#pragma once

#include <deque>
#include <vector>

#include "core/vec3.h"

namespace quarry::fsi {

class ForceFilter {
 public:
  explicit ForceFilter(double window) : window_(window) {}  // window: FILTER (s), > 0
  void set_window(double window) { window_ = window; }

  // One sync period's nodal impulses (N·s) collected over `duration` (s). Pre: same size each time.
  void add(std::vector<Vec3> impulse, double duration);

  // The mean nodal force (N) over the last `window` seconds: the newest periods whole and the
  // oldest that reaches into the window by the fraction inside it (its mean force over that
  // part); while less time than the window has passed, the mean over what there is. Zero
  // before the first period.
  void mean(std::vector<Vec3>& force) const;

  struct Period {
    std::vector<Vec3> impulse;  // N·s
    double duration = 0.0;      // s
  };
  // The window and the periods it holds, oldest first (checkpoints). set_state throws
  // std::invalid_argument, changing nothing, for a window ≤ 0, a duration < 0 or a value that
  // is not finite, or periods of different sizes.
  double window() const { return window_; }
  const std::deque<Period>& periods() const { return periods_; }
  void set_state(double window, std::deque<Period> periods);

 private:
  double window_ = 0.0;
  std::deque<Period> periods_;  // oldest first
};

}  // namespace quarry::fsi
