/* The ABI header must compile as strict C (C99 and C11, -pedantic-errors -Werror). */
#include "atmo/atmo.h"
#include "atmo/atmo_loader.h"

int atmo_header_compiles(void);
int atmo_header_compiles(void) {
  AtmoFrameState frame = {ATMO_HEADER(ATMO_TYPE_FRAME_STATE, AtmoFrameState), 0, 0.0, 0.0, 0, 0};
  PFN_atmo_negotiate negotiate = 0;
  (void)negotiate;
  return (int)frame.header.struct_size;
}

/* The geodetic helper is strict C too; AtmoPass stays the legacy name of AtmoPassKind. */
#include "atmo/atmo_geodetic.h"
int atmo_geodetic_compiles(void);
int atmo_geodetic_compiles(void) {
  const double origin[3] = {47.0, 8.0, 400.0}, enu[3] = {100.0, 200.0, 30.0};
  double g[3];
  AtmoPass legacy = ATMO_PASS_SKY;
  AtmoPassKind kind = legacy;
  atmo_geodetic_from_enu(origin, enu, g);
  return (int)g[0] + (int)kind;
}
