#include "gl_state_check.h"

#include <algorithm>
#include <cstdio>

#include <osg/BlendEquation>
#include <osg/BlendFunc>
#include <osg/ColorMask>
#include <osg/CullFace>
#include <osg/Depth>
#include <osg/FrontFace>
#include <osg/GLExtensions>
#include <osg/PolygonMode>
#include <osg/Program>
#include <osg/State>
#include <osg/Texture>
#include <osg/VertexArrayState>
#include <osg/Viewport>

namespace atmo::osg_host {

namespace {

struct Comparer {
  StateSnapshot* out;
  void value(const char* what, long long gl, long long osg) { out->push_back({what, gl, osg}); }
};

std::string describe(const std::string& where, const StateEntry& e) {
  char text[512];
  std::snprintf(text, sizeof text, "%s: %s: GL has %lld (0x%llx), osg::State believes %lld (0x%llx)", where.c_str(),
                e.what.c_str(), e.gl, e.gl, e.osg, e.osg);
  return text;
}

GLint get_int(GLenum name) {
  GLint v = 0;
  glGetIntegerv(name, &v);
  return v;
}

GLuint buffer_id(const osg::GLBufferObject* buffer) { return buffer ? buffer->getGLObjectID() : 0; }

// OSG's belief about a mode: its last applied value where it has applied it, else GL's initial value (it
// has never touched it). A mode OSG marked unknown (valid false) is not compared.
bool osg_mode(const osg::State& state, GLenum mode, bool* known) {
  const osg::State::ModeMap& modes = state.getModeMap();
  const auto it = modes.find(mode);
  *known = true;
  if (it == modes.end()) return mode == GL_DITHER || mode == GL_MULTISAMPLE;
  if (!it->second.valid) *known = false;
  return it->second.last_applied_value;
}

template <typename T>
const T* last(const osg::State& state, osg::StateAttribute::Type type) {
  return dynamic_cast<const T*>(state.getLastAppliedAttribute(type));
}

}  // namespace

int tally_call(const StateSnapshot& baseline, const StateSnapshot& after, const std::string& where,
               StateCheckTally* tally) {
  ++tally->checks;
  int mismatches = 0;
  for (size_t i = 0; i < after.size(); ++i) {
    const StateEntry& e = after[i];
    ++tally->values;
    if (e.gl == e.osg) continue;
    const bool already = i < baseline.size() && baseline[i].what == e.what && baseline[i].gl == e.gl;
    if (already) {
      const std::string key = e.what + " = " + std::to_string(e.gl);
      bool seen = false;
      for (const std::string& m : tally->osg_messages) seen = seen || m.find(key) != std::string::npos;
      if (!seen) {
        ++tally->osg_own;
        tally->osg_messages.push_back(key + " (" + describe(where, e) + ")");
      }
      continue;
    }
    ++mismatches;
    tally->messages.push_back(describe(where, e));
  }
  tally->mismatches += mismatches;
  return mismatches;
}

StateSnapshot snapshot_gl_state(osg::RenderInfo& render_info, GLuint expected_draw_fbo, GLuint expected_read_fbo) {
  StateSnapshot snapshot;
  osg::State& state = *render_info.getState();
  const unsigned context = state.getContextID();
  const osg::GLExtensions* ext = state.get<osg::GLExtensions>();
  Comparer c{&snapshot};

  // Program, vertex arrays, buffers.
  const osg::Program::PerContextProgram* program = state.getLastAppliedProgramObject();
  c.value("current program", get_int(GL_CURRENT_PROGRAM), program ? program->getHandle() : 0);
  c.value("vertex array binding", get_int(GL_VERTEX_ARRAY_BINDING), state.getCurrentVertexArrayObject());
  osg::VertexArrayState* vas = state.getCurrentVertexArrayState();
  if (vas) {
    c.value("array buffer binding", get_int(GL_ARRAY_BUFFER_BINDING), buffer_id(vas->getCurrentVertexBufferObject()));
    c.value("element array buffer binding", get_int(GL_ELEMENT_ARRAY_BUFFER_BINDING),
            buffer_id(vas->getCurrentElementBufferObject()));
  }
  c.value("pixel unpack buffer binding", get_int(GL_PIXEL_UNPACK_BUFFER_BINDING),
          buffer_id(state.getCurrentPixelBufferObject()));

  // Framebuffers (the RenderStage's, which OSG's State does not track).
  c.value("draw framebuffer binding", get_int(GL_DRAW_FRAMEBUFFER_BINDING), expected_draw_fbo);
  c.value("read framebuffer binding", get_int(GL_READ_FRAMEBUFFER_BINDING), expected_read_fbo);

  // Viewport.
  if (const osg::Viewport* vp = state.getCurrentViewport()) {
    GLint v[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_VIEWPORT, v);
    c.value("viewport x", v[0], static_cast<long long>(vp->x()));
    c.value("viewport y", v[1], static_cast<long long>(vp->y()));
    c.value("viewport width", v[2], static_cast<long long>(vp->width()));
    c.value("viewport height", v[3], static_cast<long long>(vp->height()));
  }

  // Capabilities.
  static const struct { GLenum mode; const char* name; } kModes[] = {
      {GL_BLEND, "GL_BLEND"},
      {GL_DEPTH_TEST, "GL_DEPTH_TEST"},
      {GL_CULL_FACE, "GL_CULL_FACE"},
      {GL_STENCIL_TEST, "GL_STENCIL_TEST"},
      {GL_SCISSOR_TEST, "GL_SCISSOR_TEST"},
      {GL_POLYGON_OFFSET_FILL, "GL_POLYGON_OFFSET_FILL"},
      {GL_COLOR_LOGIC_OP, "GL_COLOR_LOGIC_OP"},
      {GL_RASTERIZER_DISCARD, "GL_RASTERIZER_DISCARD"},
      {GL_SAMPLE_ALPHA_TO_COVERAGE, "GL_SAMPLE_ALPHA_TO_COVERAGE"},
      {GL_CLIP_DISTANCE0, "GL_CLIP_DISTANCE0"},
      {GL_PROGRAM_POINT_SIZE, "GL_PROGRAM_POINT_SIZE"},
      {GL_FRAMEBUFFER_SRGB, "GL_FRAMEBUFFER_SRGB"},
      {GL_DITHER, "GL_DITHER"},
      {GL_MULTISAMPLE, "GL_MULTISAMPLE"},
      // Compatibility profile (Debian's OSG is a GL2 build): fixed-function state OSG sets per StateSet.
      {GL_ALPHA_TEST, "GL_ALPHA_TEST"},
      {GL_LIGHTING, "GL_LIGHTING"},
      {GL_POINT_SMOOTH, "GL_POINT_SMOOTH"},
      {GL_POLYGON_STIPPLE, "GL_POLYGON_STIPPLE"},
  };
  for (const auto& m : kModes) {
    bool known = true;
    const bool believed = osg_mode(state, m.mode, &known);
    if (known) c.value(m.name, glIsEnabled(m.mode) ? 1 : 0, believed ? 1 : 0);
  }

  // Attributes OSG applies by StateSet; never applied: GL's initial values.
  {
    const osg::Depth* d = last<osg::Depth>(state, osg::StateAttribute::DEPTH);
    GLboolean mask = GL_TRUE;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    c.value("depth func", get_int(GL_DEPTH_FUNC), d ? d->getFunction() : GL_LESS);
    c.value("depth write mask", mask, d ? d->getWriteMask() : GL_TRUE);
  }
  {
    const osg::BlendFunc* b = last<osg::BlendFunc>(state, osg::StateAttribute::BLENDFUNC);
    c.value("blend src rgb", get_int(GL_BLEND_SRC_RGB), b ? b->getSource() : GL_ONE);
    c.value("blend dst rgb", get_int(GL_BLEND_DST_RGB), b ? b->getDestination() : GL_ZERO);
    c.value("blend src alpha", get_int(GL_BLEND_SRC_ALPHA), b ? b->getSourceAlpha() : GL_ONE);
    c.value("blend dst alpha", get_int(GL_BLEND_DST_ALPHA), b ? b->getDestinationAlpha() : GL_ZERO);
    const osg::BlendEquation* e = last<osg::BlendEquation>(state, osg::StateAttribute::BLENDEQUATION);
    c.value("blend equation rgb", get_int(GL_BLEND_EQUATION_RGB), e ? e->getEquationRGB() : GL_FUNC_ADD);
    c.value("blend equation alpha", get_int(GL_BLEND_EQUATION_ALPHA), e ? e->getEquationAlpha() : GL_FUNC_ADD);
  }
  {
    const osg::ColorMask* m = last<osg::ColorMask>(state, osg::StateAttribute::COLORMASK);
    GLboolean v[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
    glGetBooleanv(GL_COLOR_WRITEMASK, v);
    c.value("colour write mask", v[0] | v[1] << 1 | v[2] << 2 | v[3] << 3,
            m ? (m->getRedMask() | m->getGreenMask() << 1 | m->getBlueMask() << 2 | m->getAlphaMask() << 3) : 15);
  }
  {
    const osg::CullFace* f = last<osg::CullFace>(state, osg::StateAttribute::CULLFACE);
    c.value("cull face mode", get_int(GL_CULL_FACE_MODE), f ? f->getMode() : GL_BACK);
    const osg::FrontFace* ff = last<osg::FrontFace>(state, osg::StateAttribute::FRONTFACE);
    c.value("front face", get_int(GL_FRONT_FACE), ff ? ff->getMode() : GL_CCW);
    const osg::PolygonMode* p = last<osg::PolygonMode>(state, osg::StateAttribute::POLYGONMODE);
    GLint mode[2] = {GL_FILL, GL_FILL};
    glGetIntegerv(GL_POLYGON_MODE, mode);
    c.value("polygon mode", mode[0], p ? p->getMode(osg::PolygonMode::FRONT) : GL_FILL);
  }

  // Texture units: the active one, then each unit's bindings against the texture OSG last applied there.
  const GLint active = get_int(GL_ACTIVE_TEXTURE);
  c.value("active texture unit", active, GL_TEXTURE0 + static_cast<long long>(state.getActiveTextureUnit()));
  c.value("client active texture unit", get_int(GL_CLIENT_ACTIVE_TEXTURE),
          GL_TEXTURE0 + static_cast<long long>(state.getClientActiveTextureUnit()));
  const int units = std::min(get_int(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS), 32);
  const int fixed_function_units = get_int(GL_MAX_TEXTURE_UNITS);
  static const struct { GLenum target, binding; const char* name; } kTargets[] = {
      {GL_TEXTURE_1D, GL_TEXTURE_BINDING_1D, "1D"},
      {GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D, "2D"},
      {GL_TEXTURE_3D, GL_TEXTURE_BINDING_3D, "3D"},
      {GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BINDING_2D_ARRAY, "2D array"},
      {GL_TEXTURE_CUBE_MAP, GL_TEXTURE_BINDING_CUBE_MAP, "cube map"},
      {GL_TEXTURE_RECTANGLE, GL_TEXTURE_BINDING_RECTANGLE, "rectangle"},
  };
  for (int unit = 0; unit < units; ++unit) {
    ext->glActiveTexture(GL_TEXTURE0 + unit);
    const osg::Texture* texture =
        dynamic_cast<const osg::Texture*>(state.getLastAppliedTextureAttribute(unit, osg::StateAttribute::TEXTURE));
    const osg::Texture::TextureObject* object = texture ? texture->getTextureObject(context) : nullptr;
    for (const auto& t : kTargets) {
      // OSG binds one texture per unit and believes the other targets untouched (0).
      const GLuint believed = texture && object && texture->getTextureTarget() == t.target ? object->id() : 0;
      char what[64];
      std::snprintf(what, sizeof what, "unit %d texture binding %s", unit, t.name);
      c.value(what, get_int(t.binding), believed);
    }
    char what[64];
    std::snprintf(what, sizeof what, "unit %d sampler binding", unit);
    c.value(what, get_int(GL_SAMPLER_BINDING), 0);  // this host applies no osg::Sampler
    if (unit < fixed_function_units) {
      std::snprintf(what, sizeof what, "unit %d GL_TEXTURE_2D enable", unit);
      c.value(what, glIsEnabled(GL_TEXTURE_2D) ? 1 : 0, state.getLastAppliedTextureMode(unit, GL_TEXTURE_2D) ? 1 : 0);
    }
  }
  ext->glActiveTexture(static_cast<GLenum>(active));
  return snapshot;
}

}  // namespace atmo::osg_host
