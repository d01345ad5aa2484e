// glsl_end.h — closes a block opened by glsl_begin.h.
#undef ATMO_FN
#undef IN
#undef OUT
