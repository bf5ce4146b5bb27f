// Tests for open_in_paraview.py's text: the surfaces' series named in a Python list whatever
// the characters of their names, relative paths only, the Point Gaussian settings. (The CLI
// test cli.paraview_script runs the script in ParaView's pvpython.)
#include "io/paraview_script.h"

#include <gtest/gtest.h>

namespace quarry {

TEST(ParaviewScript, NamesTheSurfacesInAPythonList) {
  const std::string text = paraview_script({"truck_bed", "it's\\odd"});
  EXPECT_NE(text.find("SURFACES = ['truck_bed', 'it\\'s\\\\odd']\n"), std::string::npos) << text;
  EXPECT_NE(paraview_script({}).find("SURFACES = []\n"), std::string::npos);
}

TEST(ParaviewScript, SpheresOfTheRadiusAndRelativePaths) {
  const std::string text = paraview_script({"drum"});
  for (const char* expected : {"SetRepresentationType(\"Point Gaussian\")", "ShaderPreset = \"Sphere\"",
                               "ScaleByArray = 1", "SetScaleArray = [\"POINTS\", \"radius\"]", "UseScaleFunction = 0",
                               "GaussianRadius = 1.0", "os.path.join(HERE, \"particles.pvd\")", "pressure_smoothed",
                               "(\"CELLS\", \"pressure\")", "--screenshot"})
    EXPECT_NE(text.find(expected), std::string::npos) << expected;
  EXPECT_EQ(text.find("/home/"), std::string::npos);
  EXPECT_EQ(text.find("/tmp/"), std::string::npos);
}

}  // namespace quarry
