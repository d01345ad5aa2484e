// Lets Debian's VTK 9.1 (GLEW, X only) draw into a headless EGL context.
//
// VTK's vtkOpenGLRenderWindow::OpenGLInitContext calls glewInit() and gives up
// unless it returns GLEW_OK. GLEW 2.2's glewInit() first loads every GL entry
// point (glewContextInit, which works for any current context: libglvnd
// dispatches by the current context whatever made it current), then calls
// glxewInit(), which returns GLEW_ERROR_NO_GLX_DISPLAY when the current
// context is not a GLX one, as ours (EGL) is not. glewInit reaches glxewInit
// through the PLT, so this definition in the executable (exported with
// --export-dynamic-symbol, see CMakeLists.txt) is the one it calls: it runs
// GLEW's own glxewInit and reports success when the only problem is that
// there is no GLX display. With an X display (the fallback path) GLEW's result
// is passed through unchanged.
#include <GL/glew.h>
#include <dlfcn.h>

extern "C" GLenum glxewInit(void) {
  using Fn = GLenum (*)(void);
  static const Fn glew_glxewInit = reinterpret_cast<Fn>(dlsym(RTLD_NEXT, "glxewInit"));
  if (!glew_glxewInit) return GLEW_OK;  // a GLEW without GLX (EGL build): nothing to initialise
  const GLenum result = glew_glxewInit();
  return result == GLEW_ERROR_NO_GLX_DISPLAY ? GLEW_OK : result;
}
