// open_in_paraview.py: the text, with the run's surface names in a Python list. Property names
// are those of ParaView 5.11's Point Gaussian representation (checked with its pvpython).
#include "io/paraview_script.h"

namespace quarry {

namespace {

// A Python string literal of `text` (names come from the deck: any character is allowed).
std::string python_literal(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\\' || c == '\'') out += '\\';
    if (c == '\n') { out += "\\n"; continue; }
    out += c;
  }
  return out + "'";
}

constexpr const char* kBody = R"PY(
import os
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene, PVDReader, Render,
                             SaveScreenshot, Show)


def script_folder():
    """The folder of this script: from __file__ (pvpython), else from the command line (the
    paraview application runs --script=PATH without __file__), else the working folder."""
    if globals().get("__file__"):
        return os.path.dirname(os.path.abspath(__file__))
    try:
        with open("/proc/self/cmdline", "rb") as cmdline:
            for arg in cmdline.read().decode(errors="replace").split("\0"):
                arg = arg[len("--script="):] if arg.startswith("--script=") else arg
                if arg.endswith(".py") and os.path.isfile(arg):
                    return os.path.dirname(os.path.abspath(arg))
    except OSError:
        pass
    return os.getcwd()


HERE = script_folder()


def show_particles(view):
    reader = PVDReader(registrationName="particles", FileName=os.path.join(HERE, "particles.pvd"))
    shown = Show(reader, view)
    # Spheres of the particle's radius: each splat's radius is GaussianRadius times the radius
    # array, read as it is (no transfer function).
    shown.SetRepresentationType("Point Gaussian")
    shown.ShaderPreset = "Sphere"
    shown.ScaleByArray = 1
    shown.SetScaleArray = ["POINTS", "radius"]
    shown.UseScaleFunction = 0
    shown.GaussianRadius = 1.0
    ColorBy(shown, ("POINTS", "velocity", "Magnitude"))
    return reader, shown


def show_surface(view, name):
    reader = PVDReader(registrationName=name, FileName=os.path.join(HERE, name + ".pvd"))
    reader.UpdatePipelineInformation()
    shown = Show(reader, view)
    shown.SetRepresentationType("Surface")
    # The smoothed (nodal) pressure where the run wrote it, else the per-triangle pressure.
    if "pressure_smoothed" in reader.PointData.keys():
        ColorBy(shown, ("POINTS", "pressure_smoothed"))
    else:
        ColorBy(shown, ("CELLS", "pressure"))
    shown.SetScalarBarVisibility(view, True)
    shown.Opacity = 0.5  # the particles inside a closed surface stay visible
    return reader, shown


def main(argv):
    screenshot = argv[argv.index("--screenshot") + 1] if "--screenshot" in argv[:-1] else None
    view = GetActiveViewOrCreate("RenderView")
    shown = [("particles",) + show_particles(view)]
    for name in SURFACES:
        if os.path.exists(os.path.join(HERE, name + ".pvd")):
            shown.append((name,) + show_surface(view, name))
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.GoToLast()
    # Looking down at the material from the side, z up (the examples' gravity is along -z).
    view.CameraPosition = [1.0, -1.5, 1.0]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera()
    for name, reader, rep in shown:
        colour = rep.ColorArrayName
        print("open_in_paraview: {}: {} representation, coloured by {} {}{}".format(
            name, rep.Representation, colour[0], colour[1],
            ", radius from array " + rep.SetScaleArray[1] if rep.ScaleByArray else ""))
    if screenshot:
        SaveScreenshot(screenshot, view, ImageResolution=[1200, 800])
        print("open_in_paraview: wrote " + screenshot)
    else:
        Render(view)


main(sys.argv)
)PY";

}  // namespace

std::string paraview_script(const std::vector<std::string>& surface_names) {
  std::string text =
      "# This run's output in ParaView (written by Quarry): particles as spheres of their radius,\n"
      "# surfaces coloured by wall pressure, at the last frame. Paths are relative to this file.\n"
      "#   paraview --script=open_in_paraview.py\n"
      "#   pvpython open_in_paraview.py --screenshot view.png    (a picture, no window;\n"
      "#   xvfb-run -a pvpython ... on a machine without a display)\n"
      "SURFACES = [";
  for (std::size_t k = 0; k < surface_names.size(); ++k)
    text += (k ? ", " : "") + python_literal(surface_names[k]);
  return text + "]\n" + kBody;
}

}  // namespace quarry
