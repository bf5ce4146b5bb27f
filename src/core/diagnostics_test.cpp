// Tests for diagnostics formatting and "did you mean" suggestions.
#include "core/diagnostics.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

namespace quarry {

TEST(Diagnostics, EditDistanceAndSuggestion) {
  EXPECT_EQ(edit_distance("hertz_mindln", "hertz_mindlin"), 1);
  EXPECT_EQ(closest_match("hertz_mindln", {"linear", "hertz_mindlin"}), "hertz_mindlin");
  EXPECT_EQ(closest_match("banana", {"linear", "hertz_mindlin"}), "");
  EXPECT_EQ(did_you_mean("densty", {"density", "radius"}), "did you mean \"density\"?");
}

TEST(Diagnostics, FormatEchoesLineWithCaret) {
  const std::string path = testing::TempDir() + "diag_deck.yaml";
  {
    std::ofstream out(path);
    out << "materials:\n  - name: ore\n    densty: 2500\n";
  }
  Diagnostics d;
  d.error({path, 3, 5}, "unknown key \"densty\"", "did you mean \"density\"?");
  EXPECT_TRUE(d.has_errors());
  const std::string text = d.format();
  EXPECT_NE(text.find(path + ":3:5: error: unknown key \"densty\""), std::string::npos) << text;
  EXPECT_NE(text.find("    3 |     densty: 2500"), std::string::npos) << text;
  EXPECT_NE(text.find("      |     ^"), std::string::npos) << text;
  EXPECT_NE(text.find("  hint: did you mean \"density\"?"), std::string::npos) << text;
  std::remove(path.c_str());
}

// A note (e.g. a card a model reader ignored) is printed as such and never fails a read.
TEST(Diagnostics, NoteIsNotAnError) {
  Diagnostics d;
  d.note({"model.bdf", 4, 1}, "PARAM ignored (2 cards)", "parameters of OptiStruct's own solution");
  EXPECT_FALSE(d.has_errors());
  const std::string text = d.format();
  EXPECT_NE(text.find("model.bdf:4:1: note: PARAM ignored (2 cards)"), std::string::npos) << text;
  EXPECT_NE(text.find("  hint: parameters of OptiStruct's own solution"), std::string::npos)
      << text;
}

}  // namespace quarry
