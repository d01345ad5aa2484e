// A headless OpenGL context through EGL (Mesa llvmpipe on CI), for hosts that
// render offscreen: the atmo CLI, the validator and the GL tests.
#pragma once

#include <memory>
#include <string>

namespace atmo::support {

class HeadlessGl {
 public:
  enum class Profile { Core, Compatibility };

  // Asks for GL 4.5 of the profile, falling back to 3.3; makes the context
  // current on the calling thread and loads glad. On failure returns nullptr
  // and, if error is not null, a message naming the EGL step that failed.
  static std::unique_ptr<HeadlessGl> create(Profile profile, std::string* error);

  ~HeadlessGl();  // destroys the context; terminates the display when no other HeadlessGl uses it
  HeadlessGl(const HeadlessGl&) = delete;
  HeadlessGl& operator=(const HeadlessGl&) = delete;

  void make_current();     // also reloads glad (entry points are process-global)
  void release_current();

  // Matches AtmoGlProcLoader in atmo.h; user is ignored. Uses eglGetProcAddress.
  static void* get_proc_address(void* user, const char* name);

  std::string renderer() const { return renderer_; }  // GL_RENDERER
  std::string version() const { return version_; }    // GL_VERSION
  bool is_core() const { return core_; }
  int major_version() const { return major_; }
  int minor_version() const { return minor_; }
  // How the display was obtained: "surfaceless" or "default".
  std::string platform() const { return platform_; }

 private:
  HeadlessGl() = default;

  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  void* surface_ = nullptr;  // EGLSurface; null (EGL_NO_SURFACE) when surfaceless
  bool core_ = false;
  int major_ = 0, minor_ = 0;
  std::string renderer_, version_, platform_;
};

// Keeps Mesa's loaded DRI/gallium driver mapped until exit (RTLD_NODELETE), so
// LeakSanitizer sees its one-time allocations as reachable instead of leaked
// from an unnamed module no suppression matches. HeadlessGl calls it; a host
// whose GL context comes from elsewhere (GLX under VTK) calls it once the
// context exists.
void pin_gl_drivers();

}  // namespace atmo::support
