#include "atmo_vtk_pass.h"

#include <vtkObjectFactory.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLQuadHelper.h>
#include <vtkOpenGLRenderUtilities.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLShaderCache.h>
#include <vtkOpenGLState.h>
#include <vtkRenderState.h>
#include <vtkRenderer.h>
#include <vtkShaderProgram.h>
#include <vtkTextureObject.h>

#include "vtk_atmosphere.h"

namespace atmo::vtk_host {

vtkStandardNewMacro(AtmoVtkPass);

AtmoVtkPass::AtmoVtkPass() = default;
AtmoVtkPass::~AtmoVtkPass() = default;

bool AtmoVtkPass::ensure_targets(vtkRenderer* renderer, int width, int height) {
  auto* window = static_cast<vtkOpenGLRenderWindow*>(renderer->GetRenderWindow());
  if (color_ && width == width_ && height == height_) return true;
  release_targets(window);
  color_ = vtkSmartPointer<vtkTextureObject>::New();
  color_->SetContext(window);
  // Float: the plugin's LINEAR_HDR radiance (--tone-map) and its blending need more than 8 bits.
  if (!color_->Allocate2D(width, height, 4, VTK_FLOAT)) return false;
  depth_ = vtkSmartPointer<vtkTextureObject>::New();
  depth_->SetContext(window);
  if (!depth_->AllocateDepth(width, height, vtkTextureObject::Float32)) return false;

  vtkOpenGLState* state = window->GetState();
  state->PushFramebufferBindings();
  scene_fbo_ = vtkSmartPointer<vtkOpenGLFramebufferObject>::New();
  scene_fbo_->SetContext(window);
  scene_fbo_->Bind();
  scene_fbo_->AddColorAttachment(0, color_);
  scene_fbo_->AddDepthAttachment(depth_);
  scene_fbo_->ActivateDrawBuffers(1);
  const bool scene_ok = scene_fbo_->CheckFrameBufferStatus(GL_FRAMEBUFFER) != 0;
  atmo_fbo_ = vtkSmartPointer<vtkOpenGLFramebufferObject>::New();
  atmo_fbo_->SetContext(window);
  atmo_fbo_->Bind();
  atmo_fbo_->AddColorAttachment(0, color_);
  atmo_fbo_->ActivateDrawBuffers(1);
  const bool atmo_ok = atmo_fbo_->CheckFrameBufferStatus(GL_FRAMEBUFFER) != 0;
  state->PopFramebufferBindings();
  if (!scene_ok || !atmo_ok) return false;
  width_ = width;
  height_ = height;
  return true;
}

void AtmoVtkPass::Render(const vtkRenderState* s) {
  NumberOfRenderedProps = 0;
  vtkRenderer* renderer = s->GetRenderer();
  auto* window = static_cast<vtkOpenGLRenderWindow*>(renderer->GetRenderWindow());
  vtkOpenGLState* state = window->GetState();
  if (!delegate_) {
    if (error_.empty()) error_ = "AtmoVtkPass: no delegate pass";
    return;
  }
  int width = 0, height = 0, x = 0, y = 0;
  renderer->GetTiledSizeAndOrigin(&width, &height, &x, &y);
  if (width <= 0 || height <= 0) return;
  if (!ensure_targets(renderer, width, height)) {
    if (error_.empty()) error_ = "AtmoVtkPass: could not make the float colour + depth framebuffer";
    return;
  }
  std::string gl_error;
  VtkAtmosphere* atmosphere = atmosphere_;
  if (atmosphere && !atmosphere->ensure_gl(window, &gl_error)) {
    if (error_.empty()) error_ = "gl_init: " + gl_error;
    atmosphere = nullptr;
  }

  vtkOpenGLState::ScopedglViewport viewport_saver(state);
  vtkOpenGLState::ScopedglScissor scissor_saver(state);
  state->PushFramebufferBindings();
  scene_fbo_->Bind();
  state->vtkglViewport(0, 0, width, height);
  state->vtkglScissor(0, 0, width, height);

  const bool atmo = atmosphere && atmosphere->begin_frame(renderer, width, height, depth_->GetHandle());
  if (atmo) {
    if (on_lighting_) on_lighting_();
    {
      vtkOpenGLState::ScopedglClearColor clear_saver(state);
      vtkOpenGLState::ScopedglColorMask color_mask_saver(state);
      vtkOpenGLState::ScopedglDepthMask depth_mask_saver(state);
      state->vtkglClearColor(0.0f, 0.0f, 0.0f, 0.0f);
      state->vtkglClearDepth(1.0);
      state->vtkglColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      state->vtkglDepthMask(GL_TRUE);
      state->vtkglClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    atmo_fbo_->Bind();
    atmosphere->draw(ATMO_PASS_SKY, window);
    scene_fbo_->Bind();
  }

  // The delegate draws into scene_fbo_ at (0, 0); VTK's clear keeps the sky.
  vtkRenderState inner(renderer);
  inner.SetPropArrayAndCount(s->GetPropArray(), s->GetPropArrayCount());
  inner.SetFrameBuffer(scene_fbo_);
  const int preserve = renderer->GetPreserveColorBuffer();
  if (atmo) renderer->SetPreserveColorBuffer(1);
  delegate_->Render(&inner);
  renderer->SetPreserveColorBuffer(preserve);
  NumberOfRenderedProps = delegate_->GetNumberOfRenderedProps();

  if (atmo) {
    atmo_fbo_->Bind();
    state->vtkglViewport(0, 0, width, height);
    state->vtkglScissor(0, 0, width, height);
    // atmo.h's order: aerial perspective over the opaques, the stars and
    // planets, then the clouds (which hide the stars).
    atmosphere->draw(ATMO_PASS_AERIAL_PERSPECTIVE, window);
    atmosphere->draw(ATMO_PASS_NIGHT_SKY, window);
    atmosphere->draw(ATMO_PASS_CLOUDS, window);
  }
  state->PopFramebufferBindings();
  composite(renderer, x, y, width, height);
}

void AtmoVtkPass::composite(vtkRenderer* renderer, int x, int y, int width, int height) {
  auto* window = static_cast<vtkOpenGLRenderWindow*>(renderer->GetRenderWindow());
  vtkOpenGLState* state = window->GetState();
  if (!copy_) {
    std::string fs = vtkOpenGLRenderUtilities::GetFullScreenQuadFragmentShaderTemplate();
    vtkShaderProgram::Substitute(fs, "//VTK::FSQ::Decl",
                                 "uniform sampler2D colorTexture;\n"
                                 "uniform sampler2D depthTexture;\n"
                                 "//VTK::FSQ::Decl");
    vtkShaderProgram::Substitute(fs, "//VTK::FSQ::Impl",
                                 "  gl_FragData[0] = texture(colorTexture, texCoord);\n"
                                 "  gl_FragDepth = texture(depthTexture, texCoord).r;\n"
                                 "//VTK::FSQ::Impl");
    copy_ = std::make_unique<vtkOpenGLQuadHelper>(
        window, vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(), fs.c_str(), "");
  } else {
    window->GetShaderCache()->ReadyShaderProgram(copy_->Program);
  }
  if (!copy_->Program || !copy_->Program->GetCompiled()) {
    if (error_.empty()) error_ = "AtmoVtkPass: the copy shader did not compile";
    return;
  }
  vtkOpenGLState::ScopedglEnableDisable blend_saver(state, GL_BLEND);
  vtkOpenGLState::ScopedglEnableDisable depth_test_saver(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglDepthFunc depth_func_saver(state);
  vtkOpenGLState::ScopedglDepthMask depth_mask_saver(state);
  state->vtkglDisable(GL_BLEND);
  state->vtkglEnable(GL_DEPTH_TEST);  // depth writes need the test on; ALWAYS passes every fragment
  state->vtkglDepthFunc(GL_ALWAYS);
  state->vtkglDepthMask(GL_TRUE);
  state->vtkglViewport(x, y, width, height);
  state->vtkglScissor(x, y, width, height);
  color_->Activate();
  depth_->Activate();
  copy_->Program->SetUniformi("colorTexture", color_->GetTextureUnit());
  copy_->Program->SetUniformi("depthTexture", depth_->GetTextureUnit());
  copy_->Render();
  depth_->Deactivate();
  color_->Deactivate();
}

void AtmoVtkPass::ReleaseGraphicsResources(vtkWindow* w) {
  if (delegate_) delegate_->ReleaseGraphicsResources(w);
  release_targets(w);
}

void AtmoVtkPass::release_targets(vtkWindow* w) {
  if (copy_) copy_->ReleaseGraphicsResources(w);
  copy_.reset();
  scene_fbo_ = nullptr;
  atmo_fbo_ = nullptr;
  if (color_) color_->ReleaseGraphicsResources(w);
  if (depth_) depth_->ReleaseGraphicsResources(w);
  color_ = nullptr;
  depth_ = nullptr;
  width_ = height_ = 0;
}

}  // namespace atmo::vtk_host
