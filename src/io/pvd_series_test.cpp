// Tests of PvdSeries: the collection file's entries, exact times after reload, escaping of
// file names, and continuing a series after a restart.
#include "io/pvd_series.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.h"

namespace quarry {
namespace {

namespace fs = std::filesystem;

fs::path temporary_file(const std::string& name) {
  const fs::path path = fs::path(testing::TempDir()) / "quarry_pvd_series" / name;
  fs::remove(path);
  return path;
}

std::string read_all(const fs::path& path) {
  return read_file(path).value_or("");
}

std::size_t count_of(const std::string& text, const std::string& needle) {
  std::size_t count = 0;
  for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
    ++count;
  return count;
}

TEST(PvdSeries, EachAddRewritesTheCollection) {
  const fs::path path = temporary_file("particles.pvd");
  PvdSeries series(path);
  EXPECT_FALSE(fs::exists(path)) << "nothing is written before the first add";
  series.add(0.0, "particles_0.vtu");
  EXPECT_EQ(count_of(read_all(path), "<DataSet "), 1u);
  series.add(1e-3, "particles_1.vtu");
  const std::string text = read_all(path);
  EXPECT_EQ(count_of(text, "<DataSet "), 2u);
  EXPECT_NE(text.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("timestep=\"0.001\" group=\"\" part=\"0\" file=\"particles_1.vtu\""),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("</Collection>\n</VTKFile>"), std::string::npos);
}

TEST(PvdSeries, ReloadGivesExactTimesAndEscapedNames) {
  const fs::path path = temporary_file("exact.pvd");
  PvdSeries series(path);
  const double awkward_time = 0.1 + 0.2;  // not 0.3: needs all 17 digits to round-trip
  series.add(awkward_time, "out/a&b <1>.vtu");
  series.add(1.0 / 3.0, "out/\"quoted\".vtu");
  EXPECT_EQ(read_all(path).find("a&b <1>"), std::string::npos) << "XML special characters escaped";

  PvdSeries reloaded(path);
  reloaded.load_existing(1.0);
  ASSERT_EQ(reloaded.entries().size(), 2u);
  EXPECT_EQ(reloaded.entries()[0].time, awkward_time);
  EXPECT_EQ(reloaded.entries()[0].file, "out/a&b <1>.vtu");
  EXPECT_EQ(reloaded.entries()[1].time, 1.0 / 3.0);
  EXPECT_EQ(reloaded.entries()[1].file, "out/\"quoted\".vtu");
}

TEST(PvdSeries, ResumeKeepsEntriesUpToTheRestartTimeAndContinues) {
  const fs::path path = temporary_file("restart.pvd");
  {
    PvdSeries series(path);
    for (int k = 0; k < 6; ++k) series.add(0.01 * k, "p_" + std::to_string(k) + ".vtu");
  }
  PvdSeries series = PvdSeries::resume(path, 0.01 * 3);  // checkpoint at t = 0.03 s
  ASSERT_EQ(series.entries().size(), 4u);
  EXPECT_EQ(series.entries().back().file, "p_3.vtu");
  series.add(0.035, "p_restart.vtu");
  PvdSeries reloaded(path);
  reloaded.load_existing(1e300);
  ASSERT_EQ(reloaded.entries().size(), 5u);
  EXPECT_EQ(reloaded.entries()[3].time, 0.01 * 3);
  EXPECT_EQ(reloaded.entries()[4].file, "p_restart.vtu");
}

TEST(PvdSeries, MissingFileIsAnEmptySeries) {
  const PvdSeries series = PvdSeries::resume(temporary_file("absent.pvd"), 1.0);
  EXPECT_TRUE(series.entries().empty());
}

TEST(PvdSeries, MalformedFileThrowsNamingIt) {
  const fs::path path = temporary_file("broken.pvd");
  write_file_atomically(path,
                        "<VTKFile type=\"Collection\">\n<Collection>\n"
                        "<DataSet timestep=\"abc\" file=\"x.vtu\"/>\n");
  try {
    (void)PvdSeries::resume(path, 1.0);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path.string() + ":3:"), std::string::npos)
        << error.what();
  }
  write_file_atomically(path, "not xml at all");
  EXPECT_THROW((void)PvdSeries::resume(path, 1.0), std::runtime_error);
}

}  // namespace
}  // namespace quarry
