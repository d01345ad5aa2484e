#include "atmo_support/headless_gl.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>
#include <glad/gl.h>
#include <link.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <type_traits>

#include "atmo/atmo.h"

namespace atmo::support {

static_assert(std::is_same_v<decltype(&HeadlessGl::get_proc_address), AtmoGlProcLoader>,
              "get_proc_address must match AtmoGlProcLoader");

namespace {

const char* egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "unknown EGL error";
  }
}

std::string egl_failure(const char* step) {
  EGLint e = eglGetError();
  char code[16];
  std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(e));
  return std::string(step) + " failed (" + egl_error_name(e) + ", " + code + ")";
}

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

// EGL displays are per process, not per caller: eglTerminate would pull the
// display from under another live HeadlessGl, so count our users.
std::mutex g_display_mutex;
std::map<EGLDisplay, int> g_display_users;

bool acquire_display(EGLDisplay display, std::string* why) {
  std::lock_guard<std::mutex> lock(g_display_mutex);
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    *why = egl_failure("eglInitialize");
    return false;
  }
  ++g_display_users[display];
  return true;
}

void release_display(EGLDisplay display) {
  std::lock_guard<std::mutex> lock(g_display_mutex);
  auto it = g_display_users.find(display);
  if (it == g_display_users.end()) return;
  if (--it->second == 0) {
    g_display_users.erase(it);
    eglTerminate(display);
  }
}

// glad's entry points are process-global; reload only when a different
// context becomes current (its version flags may differ).
EGLContext g_glad_loaded_for = EGL_NO_CONTEXT;

GLADapiproc load_proc(const char* name) { return reinterpret_cast<GLADapiproc>(eglGetProcAddress(name)); }

struct Attempt {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  EGLSurface surface = EGL_NO_SURFACE;
  int major = 0, minor = 0;
};

// Builds a context on an initialised display; on failure cleans up what it made.
bool make_context(EGLDisplay display, bool prefer_pbuffer, HeadlessGl::Profile profile, Attempt* out,
                  std::string* why) {
  const char* exts = eglQueryString(display, EGL_EXTENSIONS);
  const bool surfaceless_ctx = has_extension(exts, "EGL_KHR_surfaceless_context");
  const bool create_ctx = has_extension(exts, "EGL_KHR_create_context");
  bool use_pbuffer = prefer_pbuffer || !surfaceless_ctx;

  if (!eglBindAPI(EGL_OPENGL_API)) {
    *why = egl_failure("eglBindAPI(EGL_OPENGL_API)");
    return false;
  }

  EGLConfig config = nullptr;
  EGLint count = 0;
  auto choose = [&](bool pbuffer) {
    const EGLint attribs[] = {EGL_SURFACE_TYPE, pbuffer ? EGL_PBUFFER_BIT : 0, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                              EGL_NONE};
    return eglChooseConfig(display, attribs, &config, 1, &count) == EGL_TRUE;
  };
  if (!choose(use_pbuffer)) {
    *why = egl_failure("eglChooseConfig");
    return false;
  }
  if (count == 0 && use_pbuffer && surfaceless_ctx) {
    use_pbuffer = false;  // no pbuffer config, but a surfaceless context needs none
    if (!choose(false)) {
      *why = egl_failure("eglChooseConfig");
      return false;
    }
  }
  if (count == 0) {
    *why = std::string("eglChooseConfig found no config with EGL_OPENGL_BIT") +
           (use_pbuffer ? " and EGL_PBUFFER_BIT" : "");
    return false;
  }

  const EGLint profile_bit = profile == HeadlessGl::Profile::Core ? EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR
                                                                  : EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT_KHR;
  static const int kVersions[2][2] = {{4, 5}, {3, 3}};
  EGLContext context = EGL_NO_CONTEXT;
  std::string ctx_errors;
  for (const auto& v : kVersions) {
    const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION_KHR, v[0], EGL_CONTEXT_MINOR_VERSION_KHR, v[1],
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR, profile_bit, EGL_NONE};
    // Without EGL 1.5 / KHR_create_context only the version-less form is valid.
    const EGLint plain_attribs[] = {EGL_NONE};
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, create_ctx ? ctx_attribs : plain_attribs);
    if (context != EGL_NO_CONTEXT) {
      out->major = v[0];
      out->minor = v[1];
      break;
    }
    char what[64];
    std::snprintf(what, sizeof what, "eglCreateContext(GL %d.%d)", v[0], v[1]);
    ctx_errors += (ctx_errors.empty() ? "" : "; ") + egl_failure(what);
    if (!create_ctx) break;
  }
  if (context == EGL_NO_CONTEXT) {
    *why = ctx_errors;
    return false;
  }

  EGLSurface surface = EGL_NO_SURFACE;
  if (use_pbuffer) {
    const EGLint pb_attribs[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
    surface = eglCreatePbufferSurface(display, config, pb_attribs);
    if (surface == EGL_NO_SURFACE) {
      *why = egl_failure("eglCreatePbufferSurface(16x16)");
      eglDestroyContext(display, context);
      return false;
    }
  }
  if (!eglMakeCurrent(display, surface, surface, context)) {
    *why = egl_failure(use_pbuffer ? "eglMakeCurrent(pbuffer)" : "eglMakeCurrent(EGL_NO_SURFACE)");
    if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
    eglDestroyContext(display, context);
    return false;
  }
  out->display = display;
  out->context = context;
  out->surface = surface;
  return true;
}

}  // namespace

// Mesa unloads its DRI driver at exit, before LeakSanitizer scans: its
// one-time allocations then look leaked from an unnamed module, which no
// suppression can match. Keeping the driver mapped keeps them reachable.
void pin_gl_drivers() {
  static std::once_flag once;
  std::call_once(once, [] {
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void*) {
          const char* n = info->dlpi_name;
          if (n && (std::strstr(n, "_dri.so") || std::strstr(n, "libgallium"))) {
            dlopen(n, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);  // handle kept on purpose
          }
          return 0;
        },
        nullptr);
  });
}

std::unique_ptr<HeadlessGl> HeadlessGl::create(Profile profile, std::string* error) {
  std::string log;
  auto note = [&log](const std::string& platform, const std::string& why) {
    log += "\n  " + platform + ": " + why;
  };

  Attempt attempt;
  std::string platform;

  // 1. Mesa's surfaceless platform: needs no X/Wayland server nor a GPU.
  const char* client_exts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!client_exts) eglGetError();  // EGL 1.4 without client extensions: not an error for us
  if (has_extension(client_exts, "EGL_MESA_platform_surfaceless") &&
      has_extension(client_exts, "EGL_EXT_platform_base")) {
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) {
      note("surfaceless platform", "eglGetProcAddress(\"eglGetPlatformDisplayEXT\") returned null");
    } else {
      EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      std::string why;
      if (d == EGL_NO_DISPLAY) {
        note("surfaceless platform", egl_failure("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)"));
      } else if (!acquire_display(d, &why)) {
        note("surfaceless platform", why);
      } else if (!make_context(d, false, profile, &attempt, &why)) {
        note("surfaceless platform", why);
        release_display(d);
      } else {
        platform = "surfaceless";
      }
    }
  } else {
    note("surfaceless platform", "EGL client extension EGL_MESA_platform_surfaceless not available");
  }

  // 2. The default display with a 16x16 pbuffer.
  if (platform.empty()) {
    EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    std::string why;
    if (d == EGL_NO_DISPLAY) {
      note("default display", egl_failure("eglGetDisplay(EGL_DEFAULT_DISPLAY)"));
    } else if (!acquire_display(d, &why)) {
      note("default display", why);
    } else if (!make_context(d, true, profile, &attempt, &why)) {
      note("default display", why);
      release_display(d);
    } else {
      platform = "default";
    }
  }

  const char* profile_name = profile == Profile::Core ? "core" : "compatibility";
  if (platform.empty()) {
    if (error) {
      *error = std::string("HeadlessGl: could not create a headless OpenGL 4.5 (or 3.3) ") + profile_name +
               " context through EGL:" + log +
               "\n  Install Mesa's EGL and GL drivers (Debian: apt-get install libegl-mesa0 libgl1-mesa-dri).";
    }
    return nullptr;
  }

  pin_gl_drivers();
  std::unique_ptr<HeadlessGl> gl(new HeadlessGl());
  gl->display_ = attempt.display;
  gl->context_ = attempt.context;
  gl->surface_ = attempt.surface;
  gl->platform_ = platform;

  if (gladLoadGL(load_proc) == 0) {
    if (error) {
      *error = std::string("HeadlessGl: EGL made a ") + profile_name + " context (" + platform +
               ") but glad could not load GL entry points through eglGetProcAddress."
               "\n  Install Mesa's EGL and GL drivers (Debian: apt-get install libegl-mesa0 libgl1-mesa-dri).";
    }
    return nullptr;  // the destructor cleans up
  }
  g_glad_loaded_for = attempt.context;

  auto str = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
  };
  gl->renderer_ = str(GL_RENDERER);
  gl->version_ = str(GL_VERSION);
  GLint major = 0, minor = 0, mask = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  gl->major_ = major;
  gl->minor_ = minor;
  if (major > 3 || (major == 3 && minor >= 2)) glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
  gl->core_ = (mask & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  while (glGetError() != GL_NO_ERROR) {
  }
  return gl;
}

HeadlessGl::~HeadlessGl() {
  if (display_ == nullptr) return;
  if (eglGetCurrentContext() == context_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  if (g_glad_loaded_for == context_) g_glad_loaded_for = EGL_NO_CONTEXT;
  if (context_) eglDestroyContext(display_, context_);
  if (surface_) eglDestroySurface(display_, surface_);
  release_display(display_);
}

void HeadlessGl::make_current() {
  eglMakeCurrent(display_, surface_, surface_, context_);
  if (g_glad_loaded_for != context_) {
    gladLoadGL(load_proc);
    g_glad_loaded_for = context_;
  }
}

void HeadlessGl::release_current() {
  if (eglGetCurrentContext() == context_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
}

void* HeadlessGl::get_proc_address(void* /*user*/, const char* name) {
  return reinterpret_cast<void*>(eglGetProcAddress(name));
}

}  // namespace atmo::support
