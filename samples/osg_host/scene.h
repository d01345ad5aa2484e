// scene.h — atmo-osg-host's own OpenSceneGraph content: the terrain (host_scene's heightfield as an
// osg::Geometry), a few models (osg::ShapeDrawable: a hangar, a control tower, fuel tanks), the shader that
// lights them in linear cd/m^2 times the exposure from the plugin's Sun and sky, the tone-map camera and a
// HUD camera drawn by OSG after the plugin's passes.
#pragma once

#include <array>

#include <osg/Camera>
#include <osg/Program>
#include <osg/Texture2D>
#include <osg/Uniform>

#include "atmo/atmo.h"
#include "atmo_host_scene/terrain.h"

namespace atmo::osg_host {

// Everything in the world is in the ENU frame of the airfield datum (x east, y north, z up: OSG's own
// up axis), metres.
osg::ref_ptr<osg::Node> make_terrain(const host_scene::Terrain& terrain);
osg::ref_ptr<osg::Node> make_models(const host_scene::Terrain& terrain);

// The surfaces' program: Lambertian albedo (the vertex colour) lit by the Sun and the sky's SH9
// irradiance, in ENU. Its uniforms, set each frame from get_lighting (or a fixed light without the plugin).
class SceneLighting {
 public:
  SceneLighting();
  void attach(osg::StateSet* stateset) const;
  // The plugin's light (lighting != nullptr) or a fixed noon-like light; view: OSG's view matrix (ENU to eye).
  void set(const AtmoLighting* lighting, const osg::Matrixd& view, double exposure_scale);

 private:
  osg::ref_ptr<osg::Program> program_;
  osg::ref_ptr<osg::Uniform> sun_direction_, sun_lux_, sh9_, exposure_, enu_from_view_;
};

// A full-viewport quad that tone-maps the linear HDR colour texture to the window (atmo_tone_map.glsl):
// a POST_RENDER camera of the window's framebuffer.
osg::ref_ptr<osg::Camera> make_tone_map_camera(osg::Texture2D* hdr_color, int width, int height, GLenum buffer);

// The HUD, drawn by OSG after the tone map: a panel of text-free quads that uses what a plugin could
// leave wrong behind OSG's back: two textures on units 0 and 1 through a program, a fixed-function quad
// (program 0), a blended quad, and a quad behind the panel that the depth test must hide. Its pixels are
// the same whatever was drawn before it. panel: x, y, width, height in pixels from the lower left.
osg::ref_ptr<osg::Camera> make_hud_camera(int width, int height, GLenum buffer, std::array<int, 4>* panel);

}  // namespace atmo::osg_host
