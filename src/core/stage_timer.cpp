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

std::string StageTimers::table(double wall_seconds) const {
  const double timed = total();
  const double sum = wall_seconds > 0.0 ? wall_seconds : timed;
  const auto line = [sum](const std::string& name, double seconds) {
    return fmt::format("{:<24} {:>12.3f} {:>7.1f}%\n", name, seconds, sum > 0.0 ? 100.0 * seconds / sum : 0.0);
  };
  std::string out = fmt::format("{:<24} {:>12} {:>8}\n", "stage", "time (s)", "share");
  for (std::size_t k = 0; k < names_.size(); ++k) out += line(names_[k], seconds_[k]);
  if (wall_seconds > 0.0) out += line("untimed", wall_seconds - timed);
  out += line(wall_seconds > 0.0 ? "total (wall)" : "total", sum);
  return out;
}

void StageTimers::reset() {
  for (auto& s : seconds_) s = 0.0;
}

}  // namespace quarry
