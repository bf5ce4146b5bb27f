// `quarry udf build SOURCE.c`: compiles a user-defined drag function's C source into a shared
// library beside it (AcuSolve's `acuMakeLib -src usrStokesDrag.c`, seed 001), against the
// quarry/drag_udf.h of this Quarry, then loads it once to check it as a run would.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace quarry::cli {

struct UdfBuildOptions {
  std::string source;               // the C source (required)
  std::string output;               // the library; empty: the source's name with .so
  std::vector<std::string> cflags;  // extra compiler arguments, each string split at spaces
};

// Prints the compiler command on `out`, runs it, passes the compiler's messages on to `err`,
// and loads the library written (cfd::open_drag_udf_library: it resolves, has the ABI function
// of this major). Returns 0 when it was written and loads, 2 when the compiler could not be run
// or failed, or the library does not load (the loader's error on `err`). The compiler is
// $QUARRY_UDF_CC if set, else `cc` from PATH; the header's folder is $QUARRY_UDF_INCLUDE_DIR
// if set, else <prefix>/include beside an installed <prefix>/bin/quarry, else the source tree's.
// Throws UserError (exit 2 in the CLI) for a source that does not exist or is not a file, and
// when no drag_udf.h is found. Cost: one compiler run and one dlopen.
int udf_build(const UdfBuildOptions& options, std::ostream& out, std::ostream& err);

}  // namespace quarry::cli
