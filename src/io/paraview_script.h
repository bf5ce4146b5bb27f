// The ParaView Python script a run writes beside its series (open_in_paraview.py): it loads
// particles.pvd as spheres of each particle's radius (the Point Gaussian representation, which
// draws 100k particles at once where the Glyph filter takes minutes) and each surface's series
// coloured by wall pressure (the point array pressure_smoothed when the files have it, else the
// cell array pressure). Paths are relative to the script's folder, so the folder can be moved.
#pragma once

#include <string>
#include <vector>

namespace quarry {

inline constexpr const char* kParaviewScript = "open_in_paraview.py";

// The script's text for the surfaces `surface_names` (their series are NAME.pvd).
std::string paraview_script(const std::vector<std::string>& surface_names);

}  // namespace quarry
