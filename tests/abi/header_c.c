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
