// Tests of the results summary: CSV parsing, medians, Quarry/peer ratios and the bed check.
#include "bench/bench_results.h"

#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>

namespace quarry::bench {
namespace {

std::string row(const std::string& code, int threads, int rep, double pss, double zmax, double floor) {
  // date,machine,size,n,code,threads,rep,steps,loop_s,pss,coordination,neigh_pp,rebuilds,rss_kib,
  // zmax,zmean,floor_force,weight,other_load
  return "2026-11-24,box,10k,10000," + code + "," + std::to_string(threads) + "," + std::to_string(rep) +
         ",2000,1," + std::to_string(pss) + ",4.6,3.44,7,40960," + std::to_string(zmax) + ",0.02," +
         std::to_string(floor) + ",1.0272,0.05\n";
}

TEST(BenchResults, MedianOfOddEvenAndNaN) {
  EXPECT_EQ(median_of({3, 1, 2}), 2);
  EXPECT_EQ(median_of({4, 1, 2, 3}), 2.5);
  EXPECT_EQ(median_of({NAN, 5, 1}), 3);
  EXPECT_TRUE(std::isnan(median_of({})));
}

TEST(BenchResults, ParsesRowsAndRejectsMalformedOnes) {
  const std::string csv = bench_csv_header() + "\n" + row("quarry", 1, 1, 2e7, 0.05, 0.9);
  const auto runs = read_bench_csv(csv);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].code, "quarry");
  EXPECT_EQ(runs[0].particles, 10000);
  EXPECT_EQ(runs[0].particle_steps_per_second, 2e7);
  EXPECT_EQ(runs[0].peak_rss_kib, 40960);
  EXPECT_THROW(read_bench_csv(bench_csv_header() + "\n1,2,3\n"), std::runtime_error);
  EXPECT_THROW(read_bench_csv("date,machine\n"), std::runtime_error);
  std::string bad = row("quarry", 1, 1, 2e7, 0.05, 0.9);
  bad.replace(bad.find("4.6"), 3, "4.x");
  EXPECT_THROW(read_bench_csv(bench_csv_header() + "\n" + bad), std::runtime_error);
}

TEST(BenchResults, RatiosAreOfMediansAndTheBedCheckUsesTheTolerance) {
  std::string csv = bench_csv_header() + "\n";
  for (int rep = 1; rep <= 3; ++rep) {
    csv += row("quarry", 1, rep, 1e7 * rep, 0.0500, 0.900);   // median 2e7
    csv += row("liggghts", 1, rep, 4e6 + rep, 0.0502, 0.950); // median 4e6 + 2
  }
  const auto groups = summarize_runs(read_bench_csv(csv));
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].code, "quarry");
  EXPECT_EQ(groups[0].median_rate, 2e7);
  EXPECT_EQ(groups[0].min_rate, 1e7);
  EXPECT_EQ(groups[0].max_rate, 3e7);
  const std::string md = bench_markdown(read_bench_csv(csv), "# test");
  EXPECT_NE(md.find("**5.00**"), std::string::npos) << md;  // 2e7 / (4e6 + 2) = 5.00
  // z max differs by 0.4 % (inside 1 %), the floor force by 5.3 %: the check fails.
  EXPECT_NE(md.find("-0.40 %"), std::string::npos) << md;
  EXPECT_NE(md.find("**no**"), std::string::npos) << md;
  const PlotSpec plot = throughput_plot(groups, "t");
  ASSERT_EQ(plot.series.size(), 2u);
  EXPECT_EQ(plot.series[0].x[0], 1.0);  // one N: against the thread count
  EXPECT_EQ(plot.series[0].y[0], 20.0);
}

// The pour's summary: its columns read (absent ones NaN in a settled-bed file), groups per
// skin, each code's best skin, and the check judged on the mean height alone.
TEST(BenchResults, PourGroupsBySkinAndChecksTheMeanHeight) {
  EXPECT_TRUE(std::isnan(read_bench_csv(bench_csv_header() + "\n" + row("quarry", 1, 1, 2e7, 0.05, 0.9))[0].skin));
  const auto pour_row = [](const std::string& code, double skin, double pss, double zmean, double ke) {
    std::string r = row(code, 1, 1, pss, 0.06, 0.9);
    r.replace(r.find(",0.02,"), 6, fmt::format(",{},", zmean));
    r.pop_back();  // the newline
    return r + fmt::format(",{},{},0.19\n", skin, ke);
  };
  const std::string csv = bench_csv_header(BenchKind::pour) + "\n" +
                          pour_row("quarry", 0.0004, 1.5e7, 0.02950, 4e-8) +
                          pour_row("quarry", 0.0008, 1.2e7, 0.02950, 4e-8) +
                          pour_row("liggghts", 0.0004, 5e6, 0.02960, 5e-8) +
                          pour_row("liggghts", 0.0008, 6e6, 0.03000, 5e-8);
  const auto runs = read_bench_csv(csv);
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[0].skin, 0.0004);
  EXPECT_EQ(runs[0].kinetic_energy, 4e-8);
  EXPECT_EQ(runs[0].neighbor_share, 0.19);
  EXPECT_EQ(summarize_runs(runs).size(), 4u);
  const std::string md = bench_markdown(runs, "# pour", 0.01, BenchKind::pour);
  EXPECT_NE(md.find("**3.00**"), std::string::npos) << md;  // same skin 0.4 mm: 1.5e7 / 5e6
  EXPECT_NE(md.find("**2.50**"), std::string::npos) << md;  // best against best: 1.5e7 / 6e6
  EXPECT_NE(md.find("19.0 %"), std::string::npos) << md;    // the neighbour share
  // Mean height 29.50 against 29.60 mm (−0.34 %) passes; against 30.00 mm (−1.67 %) does not.
  EXPECT_NE(md.find("-0.34 %"), std::string::npos) << md;
  EXPECT_NE(md.find("-1.67 %"), std::string::npos) << md;
  EXPECT_NE(md.find("| yes |"), std::string::npos) << md;
  EXPECT_NE(md.find("**no**"), std::string::npos) << md;
  // One N: throughput against threads, a line per code and skin.
  const PlotSpec plot = throughput_plot(summarize_runs(runs), "t");
  EXPECT_EQ(plot.series.size(), 4u);
  EXPECT_EQ(plot.series[0].x[0], 1.0);
}

// The scenes' summary: rows named by scene, the hopper judged on its discharge rate and the drum
// on its rising share within the tolerance, the peer's own 1- against 2-rank spread beside.
TEST(BenchResults, ScenesCheckTheDischargeRateAndTheRisingShare) {
  const auto scene_row = [](const std::string& scene, double n, const std::string& code, int threads, double pss,
                            double rate, double rising) {
    return fmt::format("2026-12-04,box,{},{},{},{},1,20000,10,{},nan,nan,4000,40960,nan,nan,nan,nan,0.01,0.0006,"
                       "1.4e-6,0.45,{},{}\n",
                       scene, n, code, threads, pss, rate, rising);
  };
  const std::string csv = bench_csv_header(BenchKind::scene) + "\n" +
                          scene_row("hopper", 10164, "quarry", 1, 4e6, 0.410, NAN) +
                          scene_row("hopper", 10164, "liggghts", 1, 3.2e6, 0.400, NAN) +
                          scene_row("hopper", 10164, "liggghts", 2, 6e6, 0.404, NAN) +
                          scene_row("drum", 11280, "quarry", 1, 5e6, NAN, 0.560) +
                          scene_row("drum", 11280, "liggghts", 1, 4e6, NAN, 0.600);
  const auto runs = read_bench_csv(csv);
  ASSERT_EQ(runs.size(), 5u);
  EXPECT_EQ(runs[0].discharge_rate, 0.410);
  EXPECT_TRUE(std::isnan(runs[0].rising_fraction));
  EXPECT_EQ(runs[3].rising_fraction, 0.560);
  const std::string md = bench_markdown(runs, "# scenes", 0.05, BenchKind::scene);
  EXPECT_NE(md.find("| hopper 10164 | Quarry |"), std::string::npos) << md;
  EXPECT_NE(md.find("**1.25**"), std::string::npos) << md;  // hopper: 4e6 / 3.2e6
  // Hopper 0.410 against 0.400 kg/s (+2.50 %) passes, the peer's 2 / 1 ranks +1.00 %; drum 0.56
  // against 0.60 (−6.67 %) does not.
  EXPECT_NE(md.find("| +2.50 % | +1.00 % |"), std::string::npos) << md;
  EXPECT_NE(md.find("-6.67 %"), std::string::npos) << md;
  EXPECT_NE(md.find("| yes |"), std::string::npos) << md;
  EXPECT_NE(md.find("**no**"), std::string::npos) << md;
  // Against the thread count, a line per scene and code.
  const PlotSpec plot = throughput_plot(summarize_runs(runs), "t", BenchKind::scene);
  EXPECT_EQ(plot.series.size(), 4u);
  EXPECT_EQ(plot.series[0].x[0], 1.0);
}

}  // namespace
}  // namespace quarry::bench
