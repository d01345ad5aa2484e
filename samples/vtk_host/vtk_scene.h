// vtk_scene.h — the VTK host's scene in VTK's world = the plugin's ENU frame
// (x east, y north, z up, metres; the Earth's curvature dropped in): the
// host-scene terrain as vtkPolyData, a coloured isosurface hovering over it and a
// row of glyph masts at increasing distances (the haze shows on them); and an
// overlay renderer on layer 1 whose pixels the plugin must not change.
#ifndef ATMO_VTK_HOST_VTK_SCENE_H
#define ATMO_VTK_HOST_VTK_SCENE_H

#include <array>
#include <vector>

#include <vtkActor.h>
#include <vtkLight.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include "atmo/atmo.h"
#include "atmo_host_scene/terrain.h"

namespace atmo::vtk_host {

struct Scene {
  std::vector<vtkSmartPointer<vtkActor>> actors;  // lit by `sun`
  vtkSmartPointer<vtkLight> sun;
  std::array<double, 3> camera_position{}, camera_focal_point{};
};

// The terrain, the isosurface and the masts, and a scene light; the camera
// looks north across the terrain from its south edge, a few hundred metres up.
Scene build_scene(const host_scene::Terrain& terrain);

// VTK's light and the actors' ambient term from the plugin's lighting: the Sun
// (or no light below the horizon) and its colour; linear: the light's
// intensity in the plugin's output units (illuminance x exposure / pi, what a
// white Lambertian surface sends), for --tone-map with LINEAR_HDR.
void apply_lighting(Scene& scene, const AtmoLighting& lighting, bool linear, double exposure_scale);
// A fixed Sun (no plugin: --no-atmo).
void apply_default_lighting(Scene& scene);

// The overlay: a renderer on layer 1 over `fraction` of the window (x0, y0,
// x1, y1 in [0, 1], VTK's lower-left origin) that clears to its own opaque
// background and draws a lit 3D glyph, a gradient 2D polygon and a caption.
vtkSmartPointer<vtkRenderer> build_overlay(const std::array<double, 4>& fraction);

}  // namespace atmo::vtk_host

#endif  // ATMO_VTK_HOST_VTK_SCENE_H
