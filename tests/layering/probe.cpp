// Compiled with one plugin layer's include roots only (tests/layering/CMakeLists.txt):
// includes the header named by ATMO_PROBE_HEADER, which must or must not be found.
#include ATMO_PROBE_HEADER
int atmo_layering_probe = 0;
