// The ABI header and the C++ wrapper must compile as strict C++17.
#include "atmo/atmo.h"
#include "atmo/atmo.hpp"

int atmo_header_compiles_cpp() {
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  return static_cast<int>(frame.header.struct_size);
}
