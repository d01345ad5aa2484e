#include "gl_state_proof.h"

#include <glad/gl.h>
#include <dlfcn.h>

#include <cstdio>
#include <map>
#include <sstream>

#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLShaderCache.h>
#include <vtkOpenGLState.h>
#include <vtkShaderProgram.h>

#include "atmo_support/gl_state.h"
#include "atmo_support/headless_gl.h"

namespace atmo::vtk_host {

namespace {

// VTK 9.1 keeps its cache in protected members (vtkOpenGLState::Stack.top(), a
// protected GLState) and compiles its own checker, CheckState(), only with
// VTK_REPORT_OPENGL_ERRORS, which Debian's build lacks. A member pointer formed
// in a derived class reads them without an instance of it (this class is never
// constructed).
class StatePeek : public vtkOpenGLState {
 public:
  // Each cached value as (name, values), in the units glGet*v gives.
  static std::vector<std::pair<std::string, std::vector<double>>> cached(vtkOpenGLState* state) {
    const GLState& c = (state->*(&StatePeek::Stack)).top();
    std::vector<std::pair<std::string, std::vector<double>>> v;
    auto add = [&v](const char* name, std::vector<double> values) { v.emplace_back(name, std::move(values)); };
    add("GL_DEPTH_WRITEMASK", {double(c.DepthMask)});
    add("GL_COLOR_WRITEMASK", {double(c.ColorMask[0]), double(c.ColorMask[1]), double(c.ColorMask[2]),
                               double(c.ColorMask[3])});
    add("GL_BLEND", {double(c.Blend)});
    add("GL_DEPTH_TEST", {double(c.DepthTest)});
    add("GL_CULL_FACE", {double(c.CullFace)});
    add("GL_SCISSOR_TEST", {double(c.ScissorTest)});
    add("GL_STENCIL_TEST", {double(c.StencilTest)});
    add("GL_MULTISAMPLE", {double(c.MultiSample)});
    add("GL_TEXTURE_CUBE_MAP_SEAMLESS", {double(c.CubeMapSeamless)});
    add("GL_LINE_SMOOTH", {double(c.LineSmooth)});
    add("GL_VIEWPORT", {double(c.Viewport[0]), double(c.Viewport[1]), double(c.Viewport[2]), double(c.Viewport[3])});
    add("GL_SCISSOR_BOX", {double(c.Scissor[0]), double(c.Scissor[1]), double(c.Scissor[2]), double(c.Scissor[3])});
    add("GL_BLEND_SRC_RGB", {double(c.BlendFunc[0])});
    add("GL_BLEND_DST_RGB", {double(c.BlendFunc[1])});
    add("GL_BLEND_SRC_ALPHA", {double(c.BlendFunc[2])});
    add("GL_BLEND_DST_ALPHA", {double(c.BlendFunc[3])});
    add("GL_BLEND_EQUATION_RGB", {double(c.BlendEquationValue1)});
    add("GL_BLEND_EQUATION_ALPHA", {double(c.BlendEquationValue2)});
    add("GL_DEPTH_FUNC", {double(c.DepthFunc)});
    add("GL_CULL_FACE_MODE", {double(c.CullFaceMode)});
    add("GL_ACTIVE_TEXTURE", {double(c.ActiveTexture)});
    add("GL_COLOR_CLEAR_VALUE", {c.ClearColor[0], c.ClearColor[1], c.ClearColor[2], c.ClearColor[3]});
    add("GL_DEPTH_CLEAR_VALUE", {c.ClearDepth});
    add("GL_POINT_SIZE", {c.PointSize});
    add("GL_LINE_WIDTH", {c.LineWidth});
    add("GL_PACK_ALIGNMENT", {double(c.PackAlignment)});
    add("GL_UNPACK_ALIGNMENT", {double(c.UnpackAlignment)});
    add("GL_UNPACK_ROW_LENGTH", {double(c.UnpackRowLength)});
    add("GL_UNPACK_IMAGE_HEIGHT", {double(c.UnpackImageHeight)});
    add("GL_STENCIL_WRITEMASK", {double(c.StencilMaskFront)});
    add("GL_STENCIL_BACK_WRITEMASK", {double(c.StencilMaskBack)});
    add("GL_STENCIL_FUNC/REF/VALUE_MASK", {double(c.StencilFuncFront[0]), double(c.StencilFuncFront[1]),
                                          double(c.StencilFuncFront[2])});
    add("GL_STENCIL_FAIL/PASS_DEPTH_FAIL/PASS_DEPTH_PASS", {double(c.StencilOpFront[0]),
                                                           double(c.StencilOpFront[1]), double(c.StencilOpFront[2])});
    add("GL_DRAW_FRAMEBUFFER_BINDING", {double(c.DrawBinding.Binding)});
    add("GL_READ_FRAMEBUFFER_BINDING", {double(c.ReadBinding.Binding)});
    add("GL_DRAW_BUFFER0", {double(c.DrawBinding.DrawBuffers[0])});
    add("GL_READ_BUFFER", {double(c.ReadBinding.ReadBuffer)});
    return v;
  }
};

std::vector<double> real_value(const std::string& name) {
  static const std::map<std::string, std::pair<GLenum, int>> kInts = {
      {"GL_VIEWPORT", {GL_VIEWPORT, 4}}, {"GL_SCISSOR_BOX", {GL_SCISSOR_BOX, 4}},
      {"GL_BLEND_SRC_RGB", {GL_BLEND_SRC_RGB, 1}}, {"GL_BLEND_DST_RGB", {GL_BLEND_DST_RGB, 1}},
      {"GL_BLEND_SRC_ALPHA", {GL_BLEND_SRC_ALPHA, 1}}, {"GL_BLEND_DST_ALPHA", {GL_BLEND_DST_ALPHA, 1}},
      {"GL_BLEND_EQUATION_RGB", {GL_BLEND_EQUATION_RGB, 1}}, {"GL_BLEND_EQUATION_ALPHA", {GL_BLEND_EQUATION_ALPHA, 1}},
      {"GL_DEPTH_FUNC", {GL_DEPTH_FUNC, 1}}, {"GL_CULL_FACE_MODE", {GL_CULL_FACE_MODE, 1}},
      {"GL_ACTIVE_TEXTURE", {GL_ACTIVE_TEXTURE, 1}}, {"GL_PACK_ALIGNMENT", {GL_PACK_ALIGNMENT, 1}},
      {"GL_UNPACK_ALIGNMENT", {GL_UNPACK_ALIGNMENT, 1}}, {"GL_UNPACK_ROW_LENGTH", {GL_UNPACK_ROW_LENGTH, 1}},
      {"GL_UNPACK_IMAGE_HEIGHT", {GL_UNPACK_IMAGE_HEIGHT, 1}}, {"GL_STENCIL_WRITEMASK", {GL_STENCIL_WRITEMASK, 1}},
      {"GL_STENCIL_BACK_WRITEMASK", {GL_STENCIL_BACK_WRITEMASK, 1}},
      {"GL_DRAW_FRAMEBUFFER_BINDING", {GL_DRAW_FRAMEBUFFER_BINDING, 1}},
      {"GL_READ_FRAMEBUFFER_BINDING", {GL_READ_FRAMEBUFFER_BINDING, 1}},
      {"GL_DRAW_BUFFER0", {GL_DRAW_BUFFER0, 1}}, {"GL_READ_BUFFER", {GL_READ_BUFFER, 1}}};
  static const std::map<std::string, GLenum> kEnables = {
      {"GL_BLEND", GL_BLEND}, {"GL_DEPTH_TEST", GL_DEPTH_TEST}, {"GL_CULL_FACE", GL_CULL_FACE},
      {"GL_SCISSOR_TEST", GL_SCISSOR_TEST}, {"GL_STENCIL_TEST", GL_STENCIL_TEST}, {"GL_MULTISAMPLE", GL_MULTISAMPLE},
      {"GL_TEXTURE_CUBE_MAP_SEAMLESS", GL_TEXTURE_CUBE_MAP_SEAMLESS}, {"GL_LINE_SMOOTH", GL_LINE_SMOOTH}};
  std::vector<double> out;
  if (auto it = kInts.find(name); it != kInts.end()) {
    GLint v[4] = {0, 0, 0, 0};
    glGetIntegerv(it->second.first, v);
    for (int i = 0; i < it->second.second; ++i) out.push_back(double(v[i]));
  } else if (auto e = kEnables.find(name); e != kEnables.end()) {
    out.push_back(glIsEnabled(e->second) ? 1.0 : 0.0);
  } else if (name == "GL_DEPTH_WRITEMASK" || name == "GL_COLOR_WRITEMASK") {
    GLboolean b[4] = {0, 0, 0, 0};
    glGetBooleanv(name == "GL_DEPTH_WRITEMASK" ? GL_DEPTH_WRITEMASK : GL_COLOR_WRITEMASK, b);
    for (int i = 0; i < (name == "GL_DEPTH_WRITEMASK" ? 1 : 4); ++i) out.push_back(b[i] ? 1.0 : 0.0);
  } else if (name == "GL_COLOR_CLEAR_VALUE" || name == "GL_POINT_SIZE" || name == "GL_LINE_WIDTH") {
    GLfloat f[4] = {0, 0, 0, 0};
    const GLenum pname = name == "GL_COLOR_CLEAR_VALUE" ? GL_COLOR_CLEAR_VALUE
                         : name == "GL_POINT_SIZE"      ? GL_POINT_SIZE
                                                        : GL_LINE_WIDTH;
    glGetFloatv(pname, f);
    for (int i = 0; i < (pname == GL_COLOR_CLEAR_VALUE ? 4 : 1); ++i) out.push_back(double(f[i]));
  } else if (name == "GL_DEPTH_CLEAR_VALUE") {
    GLdouble d = 0;
    glGetDoublev(GL_DEPTH_CLEAR_VALUE, &d);
    out.push_back(d);
  } else if (name == "GL_STENCIL_FUNC/REF/VALUE_MASK") {
    GLint f = 0, r = 0, m = 0;
    glGetIntegerv(GL_STENCIL_FUNC, &f);
    glGetIntegerv(GL_STENCIL_REF, &r);
    glGetIntegerv(GL_STENCIL_VALUE_MASK, &m);
    out = {double(f), double(r), double(static_cast<GLuint>(m))};
  } else if (name == "GL_STENCIL_FAIL/PASS_DEPTH_FAIL/PASS_DEPTH_PASS") {
    GLint a = 0, b = 0, c = 0;
    glGetIntegerv(GL_STENCIL_FAIL, &a);
    glGetIntegerv(GL_STENCIL_PASS_DEPTH_FAIL, &b);
    glGetIntegerv(GL_STENCIL_PASS_DEPTH_PASS, &c);
    out = {double(a), double(b), double(c)};
  }
  return out;
}

// The write masks are GLuint: VTK caches them as unsigned, glGetIntegerv gives a signed int.
std::vector<double> normalised(const std::string& name, std::vector<double> v) {
  if (name == "GL_STENCIL_WRITEMASK" || name == "GL_STENCIL_BACK_WRITEMASK")
    for (double& x : v) x = double(static_cast<GLuint>(static_cast<GLint>(x)));
  return v;
}

std::string format(const std::vector<double>& v) {
  std::ostringstream out;
  for (size_t i = 0; i < v.size(); ++i) out << (i ? "," : "") << v[i];
  return out.str();
}

// Every cache entry that disagrees with GL, as "NAME: VTK caches X, GL has Y".
std::vector<std::string> cache_differences(vtkOpenGLRenderWindow* window, size_t* compared) {
  std::vector<std::string> out;
  const auto cached = StatePeek::cached(window->GetState());
  for (const auto& [name, values] : cached) {
    const std::vector<double> real = normalised(name, real_value(name));
    const std::vector<double> cache = normalised(name, values);
    if (real != cache) out.push_back(name + ": VTK caches " + format(cache) + ", GL has " + format(real));
  }
  // The program: VTK's shader cache skips glUseProgram when it believes its program is bound.
  size_t n = cached.size() + 1;
  GLint program = 0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &program);
  vtkShaderProgram* last = window->GetShaderCache()->GetLastShaderBound();
  const int expected = last ? last->GetHandle() : -1;
  if (last && expected != program)
    out.push_back("GL_CURRENT_PROGRAM: VTK's shader cache holds " + std::to_string(expected) + ", GL has " +
                  std::to_string(program));
  if (compared) *compared = n;
  return out;
}

GLADapiproc glx_proc(const char* name) { return reinterpret_cast<GLADapiproc>(glx_proc_address(name)); }

}  // namespace

void* glx_proc_address(const char* name) {
  using Loader = void* (*)(const unsigned char*);
  static const Loader loader = reinterpret_cast<Loader>(dlsym(RTLD_DEFAULT, "glXGetProcAddressARB"));
  return loader ? loader(reinterpret_cast<const unsigned char*>(name)) : nullptr;
}

bool GlStateProof::load_gl(std::string* error) {
  if (!dlsym(RTLD_DEFAULT, "glXGetProcAddressARB")) {
    if (error) *error = "glXGetProcAddressARB is not in the process (VTK without GLX?)";
    return false;
  }
  if (gladLoadGL(glx_proc) == 0) {
    if (error) *error = "glad could not load GL through glXGetProcAddressARB (no current context?)";
    return false;
  }
  support::pin_gl_drivers();  // Mesa's one-time allocations stay reachable for LeakSanitizer
  return true;
}

std::string drain_gl_errors() {
  std::string out;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    char text[16];
    std::snprintf(text, sizeof text, "%s0x%04x", out.empty() ? "" : " ", e);
    out += text;
  }
  return out;
}

void GlStateProof::before(vtkOpenGLRenderWindow* window, const std::string& what) {
  what_ = what;
  const std::string pending = drain_gl_errors();
  if (!pending.empty()) std::fprintf(stderr, "atmo-vtk-host: GL errors pending before %s (VTK's): %s\n", what.c_str(),
                                     pending.c_str());
  cache_before_ = cache_differences(window, nullptr);
  for (const std::string& d : cache_before_) {
    ++host_cache_drift_;
    std::fprintf(stderr, "atmo-vtk-host: GL state: VTK's cache already differs before %s: %s\n", what.c_str(),
                 d.c_str());
  }
  snapshot_before_ = support::capture_gl_state().values;
}

void GlStateProof::after(vtkOpenGLRenderWindow* window) {
  ++calls_;
  const std::string errors = drain_gl_errors();
  if (!errors.empty()) {
    ++gl_errors_;
    std::fprintf(stderr, "atmo-vtk-host: GL error after %s: %s\n", what_.c_str(), errors.c_str());
  }
  support::GlStateSnapshot before, after = support::capture_gl_state();
  before.values = snapshot_before_;
  snapshot_values_ = after.values.size();
  for (const std::string& d : support::diff_gl_state(before, after)) {
    ++state_changes_;
    std::fprintf(stderr, "atmo-vtk-host: GL state changed by %s: %s\n", what_.c_str(), d.c_str());
  }
  for (const std::string& q : after.query_errors)
    std::fprintf(stderr, "atmo-vtk-host: GL state query failed: %s\n", q.c_str());
  for (const std::string& d : cache_differences(window, &values_compared_)) {
    bool was_there = false;
    for (const std::string& b : cache_before_) was_there = was_there || b == d;
    if (was_there) continue;  // counted as the host's own drift in before()
    ++cache_mismatches_;
    std::fprintf(stderr, "atmo-vtk-host: GL state: after %s, %s\n", what_.c_str(), d.c_str());
  }
}

}  // namespace atmo::vtk_host
