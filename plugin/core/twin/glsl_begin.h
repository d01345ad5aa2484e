// glsl_begin.h / glsl_end.h — bracket an #include of shared GLSL to compile it
// as C++ (the CPU twin; docs/ARCHITECTURE.md "One source of truth"): the
// qualifier macros the shared sources use, as C++. No include guard: included
// once before each such block, with glsl_end.h after it.
#define ATMO_FN inline
#define IN(T) const T&
#define OUT(T) T&
