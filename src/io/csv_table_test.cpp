// Tests of CsvTable: exact text, bit-exact round trip of doubles, quoting, restart
// truncation, and errors that point at file:line.
#include "io/csv_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "io/atomic_file.h"

namespace quarry {
namespace {

namespace fs = std::filesystem;

fs::path temporary_file(const std::string& name) {
  const fs::path path = fs::path(testing::TempDir()) / "quarry_csv_table" / name;
  fs::remove(path);
  return path;
}

std::string read_all(const fs::path& path) {
  return read_file(path).value_or("");
}

TEST(CsvTable, WritesHeaderAndShortestNumbers) {
  const fs::path path = temporary_file("simple.csv");
  CsvTable table(path, {"time", "force_z"});
  table.add_row(std::vector<double>{0.0, 1.5});
  table.add_row(std::vector<double>{0.1, -2e-7});
  table.flush();
  EXPECT_EQ(read_all(path), "time,force_z\n0,1.5\n0.1,-2e-07\n");
}

TEST(CsvTable, RoundTripsEveryDoubleBitExactly) {
  const fs::path path = temporary_file("round_trip.csv");
  const std::vector<double> awkward = {1.0 / 3.0,
                                       0.1 + 0.2,
                                       6.02214076e23,
                                       std::numeric_limits<double>::denorm_min(),
                                       std::numeric_limits<double>::max(),
                                       -0.0,
                                       std::numeric_limits<double>::infinity(),
                                       -std::numeric_limits<double>::infinity(),
                                       std::numeric_limits<double>::quiet_NaN()};
  CsvTable table(path, {"value", "negated"});
  for (const double value : awkward) table.add_row(std::vector<double>{value, -value});
  table.flush();

  const CsvTable loaded = CsvTable::load(path);
  ASSERT_EQ(loaded.columns(), table.columns());
  ASSERT_EQ(loaded.rows().size(), awkward.size());
  for (std::size_t r = 0; r < awkward.size(); ++r) {
    for (std::size_t c = 0; c < 2; ++c) {
      const double expected = table.rows()[r][c];
      const double actual = loaded.rows()[r][c];
      if (std::isnan(expected)) {
        EXPECT_TRUE(std::isnan(actual)) << "row " << r;
      } else {
        EXPECT_EQ(actual, expected) << "row " << r;
        EXPECT_EQ(std::signbit(actual), std::signbit(expected)) << "row " << r;
      }
    }
  }
}

TEST(CsvTable, QuotesHeaderFieldsThatNeedIt) {
  const fs::path path = temporary_file("quoted.csv");
  CsvTable table(path, {"time", "force, total (N)", "say \"hi\""});
  table.add_row(std::vector<double>{1, 2, 3});
  table.flush();
  EXPECT_EQ(read_all(path), "time,\"force, total (N)\",\"say \"\"hi\"\"\"\n1,2,3\n");
  EXPECT_EQ(CsvTable::load(path).columns(), table.columns());
}

TEST(CsvTable, RestartTruncatesRowsAfterTheCheckpointTime) {
  const fs::path path = temporary_file("restart.csv");
  {
    CsvTable table(path, {"time", "mass"});
    for (int step = 0; step <= 10; ++step)
      table.add_row(std::vector<double>{0.1 * step, 2.0 * step});
    table.flush();
  }
  // Restart from the checkpoint at t = 0.5 s: rows with t > 0.5 s were computed after it.
  CsvTable table = CsvTable::load(path);
  table.truncate_after(0.1 * 5);
  ASSERT_EQ(table.rows().size(), 6u);
  EXPECT_EQ(table.rows().back()[1], 10.0);
  EXPECT_EQ(CsvTable::load(path).rows().size(), 11u) << "file must change only at flush()";
  table.add_row(std::vector<double>{0.55, 11.0});
  table.flush();
  const CsvTable reloaded = CsvTable::load(path);
  ASSERT_EQ(reloaded.rows().size(), 7u);
  EXPECT_EQ(reloaded.rows()[6][0], 0.55);
  EXPECT_EQ(reloaded.rows()[5][0], 0.1 * 5);
}

TEST(CsvTable, RejectsWrongRowLengthAndNoColumns) {
  CsvTable table(temporary_file("wrong.csv"), {"a", "b"});
  EXPECT_THROW(table.add_row(std::vector<double>{1.0}), std::invalid_argument);
  EXPECT_THROW(CsvTable(temporary_file("none.csv"), {}), std::invalid_argument);
}

TEST(CsvTable, LoadReportsFileAndLineOfBadContent) {
  const fs::path path = temporary_file("bad.csv");
  write_file_atomically(path, "time,force\n0,1\n0.1,oops\n");
  try {
    (void)CsvTable::load(path);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path.string() + ":3:"), std::string::npos)
        << error.what();
  }
  write_file_atomically(path, "time,force\n0,1,2\n");
  EXPECT_THROW((void)CsvTable::load(path), std::runtime_error);
  EXPECT_THROW((void)CsvTable::load(temporary_file("missing.csv")), std::runtime_error);
}

}  // namespace
}  // namespace quarry
