/* A drag UDF with a syntax error (a missing semicolon): `quarry udf build` must exit 2 and show
 * the compiler's message (tests/CMakeLists.txt, cli.udf_build_broken). */
#include <quarry/drag_udf.h>

QUARRY_DRAG_UDF_EXPORT_ABI()

QUARRY_DRAG_UDF_PROTOTYPE(usrBroken);

int usrBroken(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)in;
  (void)user;
  out->force[0] = 1.0 return 0;
}
