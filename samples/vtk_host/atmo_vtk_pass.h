// atmo_vtk_pass.h — the plugin's passes inside VTK's render pipeline.
//
// Why a vtkRenderPass and not render-event observers: the aerial-perspective
// pass needs the scene's depth as a texture, and VTK 9.1 gives none to an
// observer (StartEvent/EndEvent see the window's framebuffer, whose depth is a
// renderbuffer or multisampled). A pass owns where its delegate draws, so the
// opaque scene goes into this pass's framebuffer with colour and depth
// textures (as vtkSSAOPass and vtkDepthOfFieldPass do), the plugin reads the
// depth texture, and the result is copied, colour and depth, into whatever
// target VTK gave the pass (the window's, or vtkToneMappingPass's float FBO).
//
// Order within Render():
//   1. clear colour and depth of the pass's framebuffer;
//   2. ATMO_PASS_SKY: the depth is cleared, so the sky fills the viewport;
//   3. the delegate (camera, lights, opaque props) with the renderer's
//      PreserveColorBuffer on, so VTK's clear keeps the sky;
//   4. ATMO_PASS_AERIAL_PERSPECTIVE, ATMO_PASS_NIGHT_SKY, ATMO_PASS_CLOUDS;
//   5. a full-screen quad copies colour and depth (gl_FragDepth) into the
//      outer target, at the renderer's tiled viewport.
// The plugin draws into a second framebuffer holding the colour texture
// only, so the depth texture it reads is never attached to the framebuffer it
// draws into (docs/ABI.md, "The host's depth texture").
//
// Without an atmosphere (--no-atmo) steps 1, 2 and 4 are skipped: VTK clears
// to its background and the same copy runs, so the two frames differ only by
// the plugin's calls.
#ifndef ATMO_VTK_HOST_ATMO_VTK_PASS_H
#define ATMO_VTK_HOST_ATMO_VTK_PASS_H

#include <functional>
#include <memory>
#include <string>

#include <vtkRenderPass.h>
#include <vtkSmartPointer.h>

class vtkOpenGLFramebufferObject;
class vtkOpenGLQuadHelper;
class vtkTextureObject;

namespace atmo::vtk_host {

class VtkAtmosphere;

class AtmoVtkPass : public vtkRenderPass {
 public:
  static AtmoVtkPass* New();
  vtkTypeMacro(AtmoVtkPass, vtkRenderPass);

  // The opaque scene (e.g. vtkCameraPass over vtkLightsPass + vtkOpaquePass).
  void SetDelegatePass(vtkRenderPass* pass) { delegate_ = pass; }
  // nullptr: no plugin calls. Not owned.
  void SetAtmosphere(VtkAtmosphere* atmosphere) { atmosphere_ = atmosphere; }
  // Called after the plugin's set_view / get_lighting and before the
  // delegate draws: the host sets VTK's lights from the plugin's Sun.
  void SetLightingCallback(std::function<void()> callback) { on_lighting_ = std::move(callback); }

  void Render(const vtkRenderState* s) override;
  void ReleaseGraphicsResources(vtkWindow* w) override;

  // The first failure (GL set-up or the plugin's gl_init), "" if none.
  const std::string& error() const { return error_; }

 protected:
  AtmoVtkPass();
  ~AtmoVtkPass() override;

 private:
  AtmoVtkPass(const AtmoVtkPass&) = delete;
  void operator=(const AtmoVtkPass&) = delete;

  bool ensure_targets(vtkRenderer* renderer, int width, int height);
  void release_targets(vtkWindow* w);  // the pass's own textures, framebuffers and copy program
  void composite(vtkRenderer* renderer, int x, int y, int width, int height);

  vtkSmartPointer<vtkRenderPass> delegate_;
  VtkAtmosphere* atmosphere_ = nullptr;
  std::function<void()> on_lighting_;
  vtkSmartPointer<vtkTextureObject> color_, depth_;
  vtkSmartPointer<vtkOpenGLFramebufferObject> scene_fbo_, atmo_fbo_;
  std::unique_ptr<vtkOpenGLQuadHelper> copy_;
  int width_ = 0, height_ = 0;
  std::string error_;
};

}  // namespace atmo::vtk_host

#endif  // ATMO_VTK_HOST_ATMO_VTK_PASS_H
