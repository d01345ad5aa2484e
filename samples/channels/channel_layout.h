// channel_layout.h — the geometry of display channels side by side (the "wrap"
// layout of a scenario's "channels" section, docs/MULTI_CHANNEL.md): each
// channel's yaw from the eye's heading, its camera, its frustum, and the
// columns of the edge-blend band it shares with its neighbour. Pure functions
// (no GL, no MPI), shared by atmo-channels and its tests.
#pragma once

#include <string>

#include <glm/glm.hpp>

namespace atmo::channels {

// The run's channels: N of them, each hfov x vfov degrees on width x height pixels.
struct Layout {
  int count = 3;
  double horizontal_fov_deg = 60.0;
  double vertical_fov_deg = 40.0;
  double overlap_deg = 0.0;  // the band adjacent channels share, [0, horizontal_fov_deg)
  int width = 160;
  int height = 90;
  double near_m = 1.0;
  double far_m = 100000.0;
};

// "" when the layout can be drawn, else what is wrong with it (a channel count below 1, an overlap as wide as
// a channel, a wrap past 360 degrees: count * (hfov - overlap) > 360, a band narrower than one column).
std::string layout_error(const Layout& layout);

// Channel i's centre, degrees to the right of the eye's heading: (i - (N - 1) / 2) * (hfov - overlap).
double channel_yaw_deg(const Layout& layout, int channel);

// Columns of a channel's image inside the band it shares with a neighbour: the pixels whose centres lie
// within overlap_deg of the channel's edge, round(W / 2 * (1 - tan(hfov / 2 - overlap) / tan(hfov / 2))),
// the same at the left and the right edge (the frustum is symmetric). 0 without overlap.
int band_columns(const Layout& layout);

// The rotation from a channel's camera axes (x right, y up, z back; it looks down -z) to ENU: the eye's
// heading (clockwise from north) and pitch (up), then the channel's yaw about the eye's own up axis, so the
// channels of a pitched eye still share their edges (a channel's pitch is the eye's, about the eye's right axis).
glm::dmat3 enu_from_channel_camera(double heading_deg, double pitch_deg, double channel_yaw_deg);

// OpenGL view matrix (ENU world -> camera) of that rotation at eye_enu_m.
glm::dmat4 view_from_enu(const glm::dmat3& enu_from_camera, const glm::dvec3& eye_enu_m);

// The channel's symmetric frustum: x scaled by 1 / tan(hfov / 2), y by 1 / tan(vfov / 2) (non-square pixels
// when they disagree with width / height, as a projector's may), standard depth ([-1, 1], near_m, far_m).
glm::dmat4 channel_projection(const Layout& layout);

}  // namespace atmo::channels
