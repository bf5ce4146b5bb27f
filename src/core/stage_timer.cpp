// Stage timers: accumulation and the end-of-run table.
#include "core/stage_timer.h"

#include <fmt/format.h>

namespace quarry {

int StageTimers::stage(const std::string& name) {
  for (std::size_t k = 0; k < names_.size(); ++k)
    if (names_[k] == name) return static_cast<int>(k);
  names_.push_back(name);
  seconds_.push_back(0.0);
  return static_cast<int>(names_.size() - 1);
}

double StageTimers::total() const {
  double sum = 0.0;
  for (double s : seconds_) sum += s;
  return sum;
}

std::string StageTimers::table() const {
  const double sum = total();
  std::string out = fmt::format("{:<24} {:>12} {:>8}\n", "stage", "time (s)", "share");
  for (std::size_t k = 0; k < names_.size(); ++k)
    out += fmt::format("{:<24} {:>12.3f} {:>7.1f}%\n", names_[k], seconds_[k],
                       sum > 0.0 ? 100.0 * seconds_[k] / sum : 0.0);
  out += fmt::format("{:<24} {:>12.3f} {:>7.1f}%\n", "total", sum, 100.0);
  return out;
}

void StageTimers::reset() {
  for (auto& s : seconds_) s = 0.0;
}

}  // namespace quarry
