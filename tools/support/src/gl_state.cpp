#include "atmo_support/gl_state.h"

#include <glad/gl.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>

namespace atmo::support {

namespace {

enum class Method { Integer, Boolean, Float, Double, Enabled, EnabledI, IntegerI, BooleanI, Unit, VertexAttrib };
enum class Kind { Enum, Int, Bool, Float, Mask };
enum class Ext { None, ClipControl, Debug, Compatibility };  // Compatibility: only in a compatibility context

struct Query {
  std::string name;
  GLenum pname;
  Method method;
  Kind kind;
  int count;
  int index;        // indexed queries, texture unit, vertex attribute
  int min_version;  // major * 10 + minor
  Ext ext;
};

constexpr int kTextureUnits = 16;
constexpr int kVertexAttribs = 16;

std::string indexed(const char* name, int i) { return std::string(name) + "[" + std::to_string(i) + "]"; }

// Built once; order matters: GL_ACTIVE_TEXTURE is read before the per-unit
// queries switch units.
const std::vector<Query>& queries() {
  static const std::vector<Query> table = [] {
    std::vector<Query> q;
    auto add = [&q](const char* name, GLenum pname, Method m, Kind k, int count = 1, int version = 33,
                    Ext ext = Ext::None) { q.push_back({name, pname, m, k, count, 0, version, ext}); };
    auto addi = [&q](const std::string& name, GLenum pname, Method m, Kind k, int index, int count = 1,
                     int version = 33) { q.push_back({name, pname, m, k, count, index, version, Ext::None}); };
    using M = Method;
    using K = Kind;
#define ATMO_Q(pname, ...) add(#pname, pname, __VA_ARGS__)
    // Program and vertex input.
    ATMO_Q(GL_CURRENT_PROGRAM, M::Integer, K::Int);
    ATMO_Q(GL_PROGRAM_PIPELINE_BINDING, M::Integer, K::Int, 1, 41);
    ATMO_Q(GL_VERTEX_ARRAY_BINDING, M::Integer, K::Int);
    // Buffer bindings.
    ATMO_Q(GL_ARRAY_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_ELEMENT_ARRAY_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_UNIFORM_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_PIXEL_PACK_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_PIXEL_UNPACK_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_COPY_READ_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_COPY_WRITE_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_TEXTURE_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_DRAW_INDIRECT_BUFFER_BINDING, M::Integer, K::Int, 1, 40);
    ATMO_Q(GL_ATOMIC_COUNTER_BUFFER_BINDING, M::Integer, K::Int, 1, 42);
    ATMO_Q(GL_DISPATCH_INDIRECT_BUFFER_BINDING, M::Integer, K::Int, 1, 43);
    ATMO_Q(GL_SHADER_STORAGE_BUFFER_BINDING, M::Integer, K::Int, 1, 43);
    ATMO_Q(GL_QUERY_BUFFER_BINDING, M::Integer, K::Int, 1, 44);
    for (int i = 0; i < 16; ++i)
      addi(indexed("GL_UNIFORM_BUFFER_BINDING", i), GL_UNIFORM_BUFFER_BINDING, M::IntegerI, K::Int, i);
    for (int i = 0; i < 4; ++i)
      addi(indexed("GL_TRANSFORM_FEEDBACK_BUFFER_BINDING", i), GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, M::IntegerI,
           K::Int, i);
    for (int i = 0; i < 8; ++i)
      addi(indexed("GL_SHADER_STORAGE_BUFFER_BINDING", i), GL_SHADER_STORAGE_BUFFER_BINDING, M::IntegerI, K::Int, i,
           1, 43);
    for (int i = 0; i < 8; ++i)
      addi(indexed("GL_IMAGE_BINDING_NAME", i), GL_IMAGE_BINDING_NAME, M::IntegerI, K::Int, i, 1, 42);
    ATMO_Q(GL_TRANSFORM_FEEDBACK_BINDING, M::Integer, K::Int, 1, 40);
    // Framebuffers.
    ATMO_Q(GL_DRAW_FRAMEBUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_READ_FRAMEBUFFER_BINDING, M::Integer, K::Int);
    ATMO_Q(GL_RENDERBUFFER_BINDING, M::Integer, K::Int);
    for (int i = 0; i < 8; ++i)
      addi("GL_DRAW_BUFFER" + std::to_string(i), GL_DRAW_BUFFER0 + i, M::Integer, K::Enum, 0);
    ATMO_Q(GL_READ_BUFFER, M::Integer, K::Enum);
    ATMO_Q(GL_FRAMEBUFFER_SRGB, M::Enabled, K::Bool);
    // Viewport, scissor, clipping.
    ATMO_Q(GL_VIEWPORT, M::Integer, K::Int, 4);
    ATMO_Q(GL_SCISSOR_TEST, M::Enabled, K::Bool);
    ATMO_Q(GL_SCISSOR_BOX, M::Integer, K::Int, 4);
    ATMO_Q(GL_DEPTH_RANGE, M::Double, K::Float, 2);
    ATMO_Q(GL_DEPTH_CLAMP, M::Enabled, K::Bool);
    ATMO_Q(GL_CLIP_ORIGIN, M::Integer, K::Enum, 1, 45, Ext::ClipControl);
    ATMO_Q(GL_CLIP_DEPTH_MODE, M::Integer, K::Enum, 1, 45, Ext::ClipControl);
    for (int i = 0; i < 8; ++i)
      addi("GL_CLIP_DISTANCE" + std::to_string(i), GL_CLIP_DISTANCE0 + i, M::Enabled, K::Bool, 0);
    ATMO_Q(GL_RASTERIZER_DISCARD, M::Enabled, K::Bool);
    // Depth.
    ATMO_Q(GL_DEPTH_TEST, M::Enabled, K::Bool);
    ATMO_Q(GL_DEPTH_FUNC, M::Integer, K::Enum);
    ATMO_Q(GL_DEPTH_WRITEMASK, M::Boolean, K::Bool);
    // Blending and colour output.
    for (int i = 0; i < 8; ++i) addi(indexed("GL_BLEND", i), GL_BLEND, M::EnabledI, K::Bool, i);
    ATMO_Q(GL_BLEND_SRC_RGB, M::Integer, K::Enum);
    ATMO_Q(GL_BLEND_DST_RGB, M::Integer, K::Enum);
    ATMO_Q(GL_BLEND_SRC_ALPHA, M::Integer, K::Enum);
    ATMO_Q(GL_BLEND_DST_ALPHA, M::Integer, K::Enum);
    ATMO_Q(GL_BLEND_EQUATION_RGB, M::Integer, K::Enum);
    ATMO_Q(GL_BLEND_EQUATION_ALPHA, M::Integer, K::Enum);
    // Per-draw-buffer blend state (glBlendFunci, GL 4.0); buffer 0 is above.
    for (int i = 1; i < 8; ++i) {
      const std::pair<const char*, GLenum> blend[] = {
          {"GL_BLEND_SRC_RGB", GL_BLEND_SRC_RGB},           {"GL_BLEND_DST_RGB", GL_BLEND_DST_RGB},
          {"GL_BLEND_SRC_ALPHA", GL_BLEND_SRC_ALPHA},       {"GL_BLEND_DST_ALPHA", GL_BLEND_DST_ALPHA},
          {"GL_BLEND_EQUATION_RGB", GL_BLEND_EQUATION_RGB}, {"GL_BLEND_EQUATION_ALPHA", GL_BLEND_EQUATION_ALPHA}};
      for (const auto& b : blend) addi(indexed(b.first, i), b.second, M::IntegerI, K::Enum, i, 1, 40);
    }
    ATMO_Q(GL_BLEND_COLOR, M::Float, K::Float, 4);
    for (int i = 0; i < 8; ++i)
      addi(indexed("GL_COLOR_WRITEMASK", i), GL_COLOR_WRITEMASK, M::BooleanI, K::Bool, i, 4);
    ATMO_Q(GL_COLOR_LOGIC_OP, M::Enabled, K::Bool);
    ATMO_Q(GL_LOGIC_OP_MODE, M::Integer, K::Enum);
    ATMO_Q(GL_DITHER, M::Enabled, K::Bool);
    // Rasterisation.
    ATMO_Q(GL_CULL_FACE, M::Enabled, K::Bool);
    ATMO_Q(GL_CULL_FACE_MODE, M::Integer, K::Enum);
    ATMO_Q(GL_FRONT_FACE, M::Integer, K::Enum);
    ATMO_Q(GL_POLYGON_MODE, M::Integer, K::Enum, 2);
    ATMO_Q(GL_POLYGON_OFFSET_FILL, M::Enabled, K::Bool);
    ATMO_Q(GL_POLYGON_OFFSET_LINE, M::Enabled, K::Bool);
    ATMO_Q(GL_POLYGON_OFFSET_POINT, M::Enabled, K::Bool);
    ATMO_Q(GL_POLYGON_OFFSET_FACTOR, M::Float, K::Float);
    ATMO_Q(GL_POLYGON_OFFSET_UNITS, M::Float, K::Float);
    ATMO_Q(GL_LINE_WIDTH, M::Float, K::Float);
    ATMO_Q(GL_LINE_SMOOTH, M::Enabled, K::Bool);
    ATMO_Q(GL_POLYGON_SMOOTH, M::Enabled, K::Bool);
    ATMO_Q(GL_PROGRAM_POINT_SIZE, M::Enabled, K::Bool);
    ATMO_Q(GL_CLAMP_READ_COLOR, M::Integer, K::Enum);
    // Fixed-function state of a compatibility context that still acts on a
    // program's fragments (GL_INVALID_ENUM in a core context, so not queried there).
    const std::pair<const char*, GLenum> compatibility[] = {
        {"GL_ALPHA_TEST", 0x0BC0},        {"GL_ALPHA_TEST_FUNC", 0x0BC1}, {"GL_ALPHA_TEST_REF", 0x0BC2},
        {"GL_CLAMP_VERTEX_COLOR", 0x891A}, {"GL_CLAMP_FRAGMENT_COLOR", 0x891B}, {"GL_POLYGON_STIPPLE", 0x0B42},
        {"GL_POINT_SMOOTH", 0x0B10},      {"GL_POINT_SPRITE", 0x8861},    {"GL_LINE_STIPPLE", 0x0B24},
        {"GL_INDEX_LOGIC_OP", 0x0BF1},    {"GL_SHADE_MODEL", 0x0B54},     {"GL_MAP_COLOR", 0x0D10},
        {"GL_RED_SCALE", 0x0D14},         {"GL_RED_BIAS", 0x0D15},        {"GL_ALPHA_SCALE", 0x0D1C}};
    for (const auto& c : compatibility) add(c.first, c.second, M::Float, K::Float, 1, 33, Ext::Compatibility);
    ATMO_Q(GL_POINT_SIZE, M::Float, K::Float);
    ATMO_Q(GL_POINT_SPRITE_COORD_ORIGIN, M::Integer, K::Enum);
    ATMO_Q(GL_PROVOKING_VERTEX, M::Integer, K::Enum);
    ATMO_Q(GL_PRIMITIVE_RESTART, M::Enabled, K::Bool);
    ATMO_Q(GL_PRIMITIVE_RESTART_INDEX, M::Integer, K::Mask);
    ATMO_Q(GL_PRIMITIVE_RESTART_FIXED_INDEX, M::Enabled, K::Bool, 1, 43);
    ATMO_Q(GL_PATCH_VERTICES, M::Integer, K::Int, 1, 40);
    // Multisampling.
    ATMO_Q(GL_MULTISAMPLE, M::Enabled, K::Bool);
    ATMO_Q(GL_SAMPLE_ALPHA_TO_COVERAGE, M::Enabled, K::Bool);
    ATMO_Q(GL_SAMPLE_ALPHA_TO_ONE, M::Enabled, K::Bool);
    ATMO_Q(GL_SAMPLE_COVERAGE, M::Enabled, K::Bool);
    ATMO_Q(GL_SAMPLE_COVERAGE_VALUE, M::Float, K::Float);
    ATMO_Q(GL_SAMPLE_COVERAGE_INVERT, M::Boolean, K::Bool);
    ATMO_Q(GL_SAMPLE_MASK, M::Enabled, K::Bool);
    addi(indexed("GL_SAMPLE_MASK_VALUE", 0), GL_SAMPLE_MASK_VALUE, M::IntegerI, K::Mask, 0);
    ATMO_Q(GL_SAMPLE_SHADING, M::Enabled, K::Bool, 1, 40);
    ATMO_Q(GL_MIN_SAMPLE_SHADING_VALUE, M::Float, K::Float, 1, 40);
    // Stencil.
    ATMO_Q(GL_STENCIL_TEST, M::Enabled, K::Bool);
    ATMO_Q(GL_STENCIL_FUNC, M::Integer, K::Enum);
    ATMO_Q(GL_STENCIL_REF, M::Integer, K::Int);
    ATMO_Q(GL_STENCIL_VALUE_MASK, M::Integer, K::Mask);
    ATMO_Q(GL_STENCIL_FAIL, M::Integer, K::Enum);
    ATMO_Q(GL_STENCIL_PASS_DEPTH_FAIL, M::Integer, K::Enum);
    ATMO_Q(GL_STENCIL_PASS_DEPTH_PASS, M::Integer, K::Enum);
    ATMO_Q(GL_STENCIL_WRITEMASK, M::Integer, K::Mask);
    ATMO_Q(GL_STENCIL_BACK_FUNC, M::Integer, K::Enum);
    ATMO_Q(GL_STENCIL_BACK_REF, M::Integer, K::Int);
    ATMO_Q(GL_STENCIL_BACK_VALUE_MASK, M::Integer, K::Mask);
    ATMO_Q(GL_STENCIL_BACK_FAIL, M::Integer, K::Enum);
    ATMO_Q(GL_STENCIL_BACK_PASS_DEPTH_FAIL, M::Integer, K::Enum);
    ATMO_Q(GL_STENCIL_BACK_PASS_DEPTH_PASS, M::Integer, K::Enum);
    ATMO_Q(GL_STENCIL_BACK_WRITEMASK, M::Integer, K::Mask);
    // Clear values.
    ATMO_Q(GL_COLOR_CLEAR_VALUE, M::Float, K::Float, 4);
    ATMO_Q(GL_DEPTH_CLEAR_VALUE, M::Double, K::Float);
    ATMO_Q(GL_STENCIL_CLEAR_VALUE, M::Integer, K::Int);
    // Pixel store.
    ATMO_Q(GL_PACK_ALIGNMENT, M::Integer, K::Int);
    ATMO_Q(GL_PACK_ROW_LENGTH, M::Integer, K::Int);
    ATMO_Q(GL_PACK_IMAGE_HEIGHT, M::Integer, K::Int);
    ATMO_Q(GL_PACK_SKIP_ROWS, M::Integer, K::Int);
    ATMO_Q(GL_PACK_SKIP_PIXELS, M::Integer, K::Int);
    ATMO_Q(GL_PACK_SKIP_IMAGES, M::Integer, K::Int);
    ATMO_Q(GL_PACK_SWAP_BYTES, M::Boolean, K::Bool);
    ATMO_Q(GL_PACK_LSB_FIRST, M::Boolean, K::Bool);
    ATMO_Q(GL_UNPACK_ALIGNMENT, M::Integer, K::Int);
    ATMO_Q(GL_UNPACK_ROW_LENGTH, M::Integer, K::Int);
    ATMO_Q(GL_UNPACK_IMAGE_HEIGHT, M::Integer, K::Int);
    ATMO_Q(GL_UNPACK_SKIP_ROWS, M::Integer, K::Int);
    ATMO_Q(GL_UNPACK_SKIP_PIXELS, M::Integer, K::Int);
    ATMO_Q(GL_UNPACK_SKIP_IMAGES, M::Integer, K::Int);
    ATMO_Q(GL_UNPACK_SWAP_BYTES, M::Boolean, K::Bool);
    ATMO_Q(GL_UNPACK_LSB_FIRST, M::Boolean, K::Bool);
    // Misc.
    ATMO_Q(GL_TEXTURE_CUBE_MAP_SEAMLESS, M::Enabled, K::Bool);
    ATMO_Q(GL_LINE_SMOOTH_HINT, M::Integer, K::Enum);
    ATMO_Q(GL_POLYGON_SMOOTH_HINT, M::Integer, K::Enum);
    ATMO_Q(GL_TEXTURE_COMPRESSION_HINT, M::Integer, K::Enum);
    ATMO_Q(GL_FRAGMENT_SHADER_DERIVATIVE_HINT, M::Integer, K::Enum);
    ATMO_Q(GL_DEBUG_OUTPUT, M::Enabled, K::Bool, 1, 43, Ext::Debug);
    ATMO_Q(GL_DEBUG_OUTPUT_SYNCHRONOUS, M::Enabled, K::Bool, 1, 43, Ext::Debug);
    // Textures: the active unit first, then every unit's bindings.
    ATMO_Q(GL_ACTIVE_TEXTURE, M::Integer, K::Enum);
#undef ATMO_Q
    const std::pair<const char*, GLenum> targets[] = {
        {"GL_TEXTURE_BINDING_1D", GL_TEXTURE_BINDING_1D},
        {"GL_TEXTURE_BINDING_2D", GL_TEXTURE_BINDING_2D},
        {"GL_TEXTURE_BINDING_3D", GL_TEXTURE_BINDING_3D},
        {"GL_TEXTURE_BINDING_1D_ARRAY", GL_TEXTURE_BINDING_1D_ARRAY},
        {"GL_TEXTURE_BINDING_2D_ARRAY", GL_TEXTURE_BINDING_2D_ARRAY},
        {"GL_TEXTURE_BINDING_RECTANGLE", GL_TEXTURE_BINDING_RECTANGLE},
        {"GL_TEXTURE_BINDING_CUBE_MAP", GL_TEXTURE_BINDING_CUBE_MAP},
        {"GL_TEXTURE_BINDING_BUFFER", GL_TEXTURE_BINDING_BUFFER},
        {"GL_TEXTURE_BINDING_2D_MULTISAMPLE", GL_TEXTURE_BINDING_2D_MULTISAMPLE},
        {"GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY", GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY},
        {"GL_SAMPLER_BINDING", GL_SAMPLER_BINDING}};
    for (int u = 0; u < kTextureUnits; ++u) {
      for (const auto& t : targets)
        addi(std::string(t.first) + "[unit " + std::to_string(u) + "]", t.second, M::Unit, K::Int, u);
      addi("GL_TEXTURE_BINDING_CUBE_MAP_ARRAY[unit " + std::to_string(u) + "]", GL_TEXTURE_BINDING_CUBE_MAP_ARRAY,
           M::Unit, K::Int, u, 1, 40);
    }
    // Vertex attributes of the bound VAO (only read when one is bound).
    for (int i = 0; i < kVertexAttribs; ++i) {
      addi(indexed("GL_VERTEX_ATTRIB_ARRAY_ENABLED", i), GL_VERTEX_ATTRIB_ARRAY_ENABLED, M::VertexAttrib, K::Bool, i);
      addi(indexed("GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING", i), GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING,
           M::VertexAttrib, K::Int, i);
    }
    return q;
  }();
  return table;
}

const std::map<std::string, Kind>& kinds() {
  static const std::map<std::string, Kind> map = [] {
    std::map<std::string, Kind> m;
    for (const auto& q : queries()) m[q.name] = q.kind;
    return m;
  }();
  return map;
}

void clear_gl_errors() {
  // Bounded: a lost context may report GL_CONTEXT_LOST forever.
  for (int i = 0; i < 64 && glGetError() != GL_NO_ERROR; ++i) {
  }
}

std::string format_value(Kind kind, double v) {
  char buf[64];
  switch (kind) {
    case Kind::Enum:
      std::snprintf(buf, sizeof buf, "0x%04" PRIX64, static_cast<uint64_t>(static_cast<int64_t>(v)));
      break;
    case Kind::Mask:
      std::snprintf(buf, sizeof buf, "0x%" PRIX32, static_cast<uint32_t>(static_cast<int64_t>(v)));
      break;
    case Kind::Bool:
      return v != 0.0 ? "true" : "false";
    case Kind::Int:
      std::snprintf(buf, sizeof buf, "%" PRId64, static_cast<int64_t>(v));
      break;
    case Kind::Float:
    default:
      std::snprintf(buf, sizeof buf, "%.9g", v);
      break;
  }
  return buf;
}

std::string format_values(Kind kind, const std::vector<double>* values) {
  if (!values) return "<absent>";
  if (values->size() == 1) return format_value(kind, (*values)[0]);
  std::string s = "(";
  for (size_t i = 0; i < values->size(); ++i) s += (i ? ", " : "") + format_value(kind, (*values)[i]);
  return s + ")";
}

bool same(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i] && !(a[i] != a[i] && b[i] != b[i])) return false;  // NaN equals NaN here
  }
  return true;
}

}  // namespace

const std::vector<double>* GlStateSnapshot::find(const std::string& name) const {
  for (const auto& v : values)
    if (v.first == name) return &v.second;
  return nullptr;
}

GlStateSnapshot capture_gl_state() {
  GlStateSnapshot snap;
  if (!glGetIntegerv) return snap;  // GL not loaded
  clear_gl_errors();

  GLint major = 0, minor = 0, profile = 0, vao = 0, active = GL_TEXTURE0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  const int version = major * 10 + minor;
  if (version >= 32) glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  const bool core = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  clear_gl_errors();

  int current_unit = -1;
  snap.values.reserve(queries().size());
  for (const Query& q : queries()) {
    if (q.ext == Ext::Compatibility && core) continue;
    if (version < q.min_version) {
      const bool ext_ok = (q.ext == Ext::ClipControl && GLAD_GL_ARB_clip_control) ||
                          (q.ext == Ext::Debug && GLAD_GL_KHR_debug);
      if (!ext_ok) continue;
    }
    // Core profile has no default VAO whose attributes could be read.
    if (q.method == Method::VertexAttrib && vao == 0 && core) continue;
    if (q.method == Method::Unit && q.index != current_unit) {
      glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(q.index));
      current_unit = q.index;
    }
    // Oversized buffers: some queries return more values than we keep.
    GLint ints[16] = {};
    GLfloat floats[16] = {};
    GLdouble doubles[16] = {};
    GLboolean bools[16] = {};
    std::vector<double> v(static_cast<size_t>(q.count), 0.0);
    const GLuint idx = static_cast<GLuint>(q.index);
    switch (q.method) {
      case Method::Integer:
      case Method::Unit:
        glGetIntegerv(q.pname, ints);
        for (int i = 0; i < q.count; ++i) v[i] = ints[i];
        break;
      case Method::IntegerI:
        glGetIntegeri_v(q.pname, idx, ints);
        for (int i = 0; i < q.count; ++i) v[i] = ints[i];
        break;
      case Method::Boolean:
        glGetBooleanv(q.pname, bools);
        for (int i = 0; i < q.count; ++i) v[i] = bools[i] ? 1.0 : 0.0;
        break;
      case Method::BooleanI:
        glGetBooleani_v(q.pname, idx, bools);
        for (int i = 0; i < q.count; ++i) v[i] = bools[i] ? 1.0 : 0.0;
        break;
      case Method::Float:
        glGetFloatv(q.pname, floats);
        for (int i = 0; i < q.count; ++i) v[i] = floats[i];
        break;
      case Method::Double:
        glGetDoublev(q.pname, doubles);
        for (int i = 0; i < q.count; ++i) v[i] = doubles[i];
        break;
      case Method::Enabled:
        v[0] = glIsEnabled(q.pname) ? 1.0 : 0.0;
        break;
      case Method::EnabledI:
        v[0] = glIsEnabledi(q.pname, idx) ? 1.0 : 0.0;
        break;
      case Method::VertexAttrib:
        glGetVertexAttribiv(idx, q.pname, ints);
        v[0] = ints[0];
        break;
    }
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) {
      char code[16];
      std::snprintf(code, sizeof code, "0x%04X", err);
      snap.query_errors.push_back(q.name + ": GL error " + code);
      clear_gl_errors();
      continue;
    }
    snap.values.emplace_back(q.name, std::move(v));
  }
  if (current_unit >= 0) glActiveTexture(static_cast<GLenum>(active));
  clear_gl_errors();
  return snap;
}

std::vector<std::string> diff_gl_state(const GlStateSnapshot& before, const GlStateSnapshot& after) {
  std::vector<std::string> lines;
  auto kind_of = [](const std::string& name) {
    auto it = kinds().find(name);
    return it == kinds().end() ? Kind::Float : it->second;
  };
  for (const auto& [name, vb] : before.values) {
    const std::vector<double>* va = after.find(name);
    if (va && same(vb, *va)) continue;
    const Kind k = kind_of(name);
    lines.push_back(name + ": before " + format_values(k, &vb) + ", after " + format_values(k, va));
  }
  for (const auto& [name, va] : after.values) {
    if (before.find(name)) continue;
    const Kind k = kind_of(name);
    lines.push_back(name + ": before <absent>, after " + format_values(k, &va));
  }
  return lines;
}

// ---------------------------------------------------------------------------
// UnusualGlState

namespace {

GLuint compile(GLenum type, const char* src) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  return s;
}

}  // namespace

UnusualGlState::UnusualGlState() {
  glGetIntegerv(GL_VIEWPORT, viewport_);
  glGetIntegerv(GL_SCISSOR_BOX, scissor_);
  // Mesa's initial masks are 0xFF, not the spec's all ones: keep what is there.
  glGetIntegerv(GL_STENCIL_VALUE_MASK, &stencil_masks_[0]);
  glGetIntegerv(GL_STENCIL_BACK_VALUE_MASK, &stencil_masks_[1]);
  glGetIntegerv(GL_STENCIL_WRITEMASK, &stencil_masks_[2]);
  glGetIntegerv(GL_STENCIL_BACK_WRITEMASK, &stencil_masks_[3]);

  // A tiny valid program (GLSL 330 works on 3.3 fallbacks too).
  const GLuint vs = compile(GL_VERTEX_SHADER,
                            "#version 330 core\nlayout(location = 0) in vec4 p;\nvoid main() { gl_Position = p; }\n");
  const GLuint fs = compile(GL_FRAGMENT_SHADER,
                            "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(1.0, 0.0, 1.0, 1.0); }\n");
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDetachShader(program_, vs);
  glDetachShader(program_, fs);
  glDeleteShader(vs);
  glDeleteShader(fs);
  glUseProgram(program_);

  // VAO with its own vertex and index buffers, attribute 0 enabled.
  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  glGenBuffers(4, buffers_);
  const float vertices[] = {-1, -1, 0, 1, 3, -1, 0, 1, -1, 3, 0, 1};
  const unsigned short indices[] = {0, 1, 2};
  glBindBuffer(GL_ARRAY_BUFFER, buffers_[0]);
  glBufferData(GL_ARRAY_BUFFER, sizeof vertices, vertices, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers_[1]);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof indices, indices, GL_STATIC_DRAW);
  glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  const float ubo_data[16] = {};
  for (int i = 0; i < 2; ++i) {
    glBindBuffer(GL_UNIFORM_BUFFER, buffers_[2 + i]);
    glBufferData(GL_UNIFORM_BUFFER, sizeof ubo_data, ubo_data, GL_STATIC_DRAW);
  }
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, buffers_[2]);
  glBindBufferBase(GL_UNIFORM_BUFFER, 2, buffers_[3]);  // also the generic binding

  // Textures on units 0..7, four targets each; a sampler on unit 3.
  glGenTextures(32, textures_);
  const GLenum targets[4] = {GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_2D_ARRAY, GL_TEXTURE_CUBE_MAP};
  for (int u = 0; u < 8; ++u) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
    for (int t = 0; t < 4; ++t) glBindTexture(targets[t], textures_[u * 4 + t]);
  }
  glGenSamplers(1, &sampler_);
  glBindSampler(3, sampler_);
  glActiveTexture(GL_TEXTURE5);

  // Its own 64x64 framebuffer, colour + depth/stencil.
  glGenRenderbuffers(1, &color_rb_);
  glBindRenderbuffer(GL_RENDERBUFFER, color_rb_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 64, 64);
  glGenRenderbuffers(1, &depth_rb_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, 64, 64);
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);

  glViewport(3, 5, 50, 40);
  glEnable(GL_SCISSOR_TEST);
  glScissor(2, 4, 30, 20);

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_FALSE);
  glDepthRange(0.1, 0.9);

  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_COLOR, GL_ONE_MINUS_DST_ALPHA, GL_ZERO, GL_SRC_ALPHA);
  glBlendEquationSeparate(GL_FUNC_REVERSE_SUBTRACT, GL_MAX);
  glBlendColor(0.1f, 0.2f, 0.3f, 0.4f);

  glEnable(GL_CULL_FACE);
  glCullFace(GL_FRONT);
  glFrontFace(GL_CW);

  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_NOTEQUAL, 3, 0x0F);
  glStencilOp(GL_INCR, GL_DECR, GL_INVERT);
  glStencilMask(0x0F);

  glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_TRUE);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
  glClearDepth(0.5);
  glClearStencil(7);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glEnable(GL_PRIMITIVE_RESTART);
  glPrimitiveRestartIndex(7);
  glDisable(GL_DITHER);
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  glEnable(GL_FRAMEBUFFER_SRGB);
  glProvokingVertex(GL_FIRST_VERTEX_CONVENTION);
}

UnusualGlState::~UnusualGlState() {
  // Unbind first: deleting a program in use only flags it.
  glUseProgram(0);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, 2, 0);
  glBindBuffer(GL_UNIFORM_BUFFER, 0);
  const GLenum targets[4] = {GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_2D_ARRAY, GL_TEXTURE_CUBE_MAP};
  for (int u = 0; u < 8; ++u) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
    for (GLenum t : targets) glBindTexture(t, 0);
  }
  glActiveTexture(GL_TEXTURE0);
  glBindSampler(3, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);

  glDeleteProgram(program_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteBuffers(4, buffers_);
  glDeleteTextures(32, textures_);
  glDeleteSamplers(1, &sampler_);
  glDeleteFramebuffers(1, &fbo_);
  const GLuint rbs[2] = {color_rb_, depth_rb_};
  glDeleteRenderbuffers(2, rbs);

  // GL defaults; viewport, scissor box and stencil masks as found.
  glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
  glDisable(GL_SCISSOR_TEST);
  glScissor(scissor_[0], scissor_[1], scissor_[2], scissor_[3]);
  glDisable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDepthRange(0.0, 1.0);
  glDisable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ZERO);
  glBlendEquation(GL_FUNC_ADD);
  glBlendColor(0.0f, 0.0f, 0.0f, 0.0f);
  glDisable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glDisable(GL_STENCIL_TEST);
  glStencilFuncSeparate(GL_FRONT, GL_ALWAYS, 0, static_cast<GLuint>(stencil_masks_[0]));
  glStencilFuncSeparate(GL_BACK, GL_ALWAYS, 0, static_cast<GLuint>(stencil_masks_[1]));
  glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  glStencilMaskSeparate(GL_FRONT, static_cast<GLuint>(stencil_masks_[2]));
  glStencilMaskSeparate(GL_BACK, static_cast<GLuint>(stencil_masks_[3]));
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(0.0f, 0.0f);
  glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  glClearDepth(1.0);
  glClearStencil(0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glDisable(GL_PROGRAM_POINT_SIZE);
  glDisable(GL_PRIMITIVE_RESTART);
  glPrimitiveRestartIndex(0);
  glEnable(GL_DITHER);
  glDisable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  glDisable(GL_FRAMEBUFFER_SRGB);
  glProvokingVertex(GL_LAST_VERTEX_CONVENTION);
}

}  // namespace atmo::support
