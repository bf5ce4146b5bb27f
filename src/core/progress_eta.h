// ProgressEta: the time left in a run, from an exponentially weighted pace (simulated seconds
// per wall second). The pace of a DEM run changes (particles are added, a frame or a checkpoint
// is written between two progress lines), and the pace over the last interval alone made the
// ETA jump by 20x between lines (issue 20: 5 min to 1.5 h on the hopper). Both the simulated
// and the wall time of each interval are summed with weights exp(-age / tau), age in wall
// seconds, so the pace is their ratio over about the last tau seconds, each interval weighted
// by its wall time: a short stall moves it by its share of tau, not to its own pace.
#pragma once

namespace quarry {

class ProgressEta {
 public:
  explicit ProgressEta(double tau_seconds = 30.0) : tau_(tau_seconds) {}
  // One interval: `wall` s of wall time advanced the simulation by `simulated` s.
  void add(double simulated, double wall);
  // Simulated s per wall s (0 before any interval with wall time).
  double pace() const { return wall_ > 0.0 ? simulated_ / wall_ : 0.0; }
  // Wall s to simulate `remaining` more simulated s; NaN while the pace is unknown or zero.
  double seconds_left(double remaining) const;

 private:
  double tau_;                            // s of wall time
  double simulated_ = 0.0, wall_ = 0.0;   // weighted sums, s
};

}  // namespace quarry
