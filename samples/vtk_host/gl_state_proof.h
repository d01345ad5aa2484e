// gl_state_proof.h — the GL-contract proof of the VTK host: around every
// [gl-current] plugin call, the real GL state (atmo_support's ~450-value
// snapshot) must be unchanged and VTK's state cache (vtkOpenGLState, plus the
// shader cache's bound program) must still agree with the real GL state, and
// glGetError must be clean.
//
// This file and gl_state_proof.cpp load GL through glad (atmo_support's
// snapshot is written against it); VTK's TUs use GLEW. They never meet in one
// TU: the interface below has no GL types.
#ifndef ATMO_VTK_HOST_GL_STATE_PROOF_H
#define ATMO_VTK_HOST_GL_STATE_PROOF_H

#include <cstddef>
#include <string>
#include <vector>

class vtkOpenGLRenderWindow;

namespace atmo::vtk_host {

class GlStateProof {
 public:
  // [gl-current] Loads glad through glXGetProcAddressARB; false with *error.
  static bool load_gl(std::string* error);

  // Opens a check around one plugin call named `what`.
  void before(vtkOpenGLRenderWindow* window, const std::string& what);
  // Closes it: logs and counts every difference (stderr, "atmo-vtk-host: GL state: ...").
  void after(vtkOpenGLRenderWindow* window);

  size_t calls() const { return calls_; }
  size_t cache_mismatches() const { return cache_mismatches_; }     // VTK's cache vs the real GL state after a call
  size_t state_changes() const { return state_changes_; }           // real GL state, before vs after a call
  size_t gl_errors() const { return gl_errors_; }                   // glGetError after a call
  size_t host_cache_drift() const { return host_cache_drift_; }     // VTK's cache already wrong before a call
  size_t values_compared() const { return values_compared_; }       // cache entries compared per call
  size_t snapshot_values() const { return snapshot_values_; }       // real GL values compared per call

 private:
  std::string what_;
  std::vector<std::string> cache_before_;
  std::vector<std::pair<std::string, std::vector<double>>> snapshot_before_;
  size_t calls_ = 0, cache_mismatches_ = 0, state_changes_ = 0, gl_errors_ = 0, host_cache_drift_ = 0;
  size_t values_compared_ = 0, snapshot_values_ = 0;
};

// glXGetProcAddressARB(name), found in the process (VTK's GLX); nullptr if absent.
void* glx_proc_address(const char* name);

// glGetError until clean; the names of what was pending ("" if nothing). [gl-current]
std::string drain_gl_errors();

}  // namespace atmo::vtk_host

#endif  // ATMO_VTK_HOST_GL_STATE_PROOF_H
