// Tests for the monitor quantities drawn in the plots: the torque about a rotation axis (the
// drum's drive torque) and the outflow rate -dm/dt (the hopper's discharge rate).
#include "sim/monitors.h"

#include <gtest/gtest.h>

#include <cmath>

namespace quarry::sim {

TEST(Monitors, TorqueAboutAnAxisThroughAPoint) {
  // One force f = (0, 0, -10) N at x = (0.3, 0, 0): T_O = x × f = (0, 3, 0) N m. About the axis
  // through p = (0.1, 0, 0) along y the lever arm is 0.2 m: T = (x - p) × f · ŷ = 0.2 × 10 = 2 N m.
  const Vec3 x{0.3, 0, 0}, f{0, 0, -10};
  const Vec3 t_origin = cross(x, f);
  EXPECT_DOUBLE_EQ(t_origin.y, 3.0);
  EXPECT_NEAR(torque_about_axis(t_origin, f, Vec3{0.1, 0, 0}, Vec3{0, 2, 0}), 2.0, 1e-12);
  // Moving p along the axis changes nothing; reversing the axis flips the sign.
  EXPECT_NEAR(torque_about_axis(t_origin, f, Vec3{0.1, 5, 0}, Vec3{0, 1, 0}), 2.0, 1e-12);
  EXPECT_NEAR(torque_about_axis(t_origin, f, Vec3{0.1, 0, 0}, Vec3{0, -1, 0}), -2.0, 1e-12);
  EXPECT_EQ(torque_about_axis(t_origin, f, Vec3{}, Vec3{}), 0.0);  // no axis: no torque
}

TEST(Monitors, OutflowRateOfALinearDischarge) {
  // m(t) = 2 - 0.5 t kg, sampled every 0.01 s with particle-sized steps of 1 g on top (a
  // saw-tooth): the windowed difference gives 0.5 kg/s within one tooth over the shortest
  // window (1 g over 0.03 s, one-sided next to the ends).
  std::vector<double> t, m;
  for (int k = 0; k <= 100; ++k) {
    t.push_back(0.01 * k);
    m.push_back(2.0 - 0.5 * t.back() + 0.001 * (k % 2));
  }
  const std::vector<double> rate = outflow_rate(t, m, 2);
  ASSERT_EQ(rate.size(), t.size());
  for (double r : rate) EXPECT_NEAR(r, 0.5, 0.001 / 0.03 + 1e-12);
  // Exactly linear: exact everywhere, ends included.
  for (int k = 0; k <= 100; ++k) m[k] = 2.0 - 0.5 * t[k];
  for (double r : outflow_rate(t, m, 2)) EXPECT_NEAR(r, 0.5, 1e-12);
  // Time not advancing: NaN, not a division by zero.
  EXPECT_TRUE(std::isnan(outflow_rate({1.0, 1.0}, {2.0, 1.0}, 1)[0]));
}

}  // namespace quarry::sim
