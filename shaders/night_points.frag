// Night-sky pass, point sources: one fragment per pixel of a source's
// (2 R + 1)^2 square. The pixel receives the source's light integrated over
// its square (night_sky/point_footprint.glsl), only where the host drew
// nothing (its depth is at the far plane, as in the sky pass).
//
// Output (u_output_encoding, AtmoOutputEncoding):
//  LINEAR_HDR: exposure · L_source, added to the framebuffer (blend ONE, ONE).
//  DISPLAY_SRGB: the framebuffer holds encode(exposure · L_sky) from the sky
//    pass, which cannot be added to; this writes encode(exposure · (L_sky +
//    L_source)) with L_sky re-evaluated for the pixel by sky.frag's own
//    function (atmosphere/sky_pixel.glsl, per ATMO_METHOD), and the renderer blends with MAX: encode is increasing
//    in each channel, so for one source the result is the encoded sum, and
//    where sources overlap the brightest one wins, whatever the drawing order.
#include "atmosphere/pass_common.glsl"
#include "atmosphere/sky_pixel.glsl"
#include "night_sky/point_footprint.glsl"

flat in vec2 v_center_px;
flat in vec3 v_radiance;

uniform float u_footprint_sigma_px;

out vec4 out_color;

void main() {
  vec2 d = gl_FragCoord.xy - v_center_px;
  float weight = point_footprint_weight(d.x, d.y, u_footprint_sigma_px);
  if (u_has_depth != 0) {
    vec4 p = view_point_from_depth(u_view_from_clip, ndc_xy(), host_depth(), u_depth_convention, u_log_far_m,
                                   u_log_coefficient);
    if (p.w >= 0.0f) discard;  // host geometry is here
  }
  vec3 source = v_radiance * weight;
  if (u_output_encoding == 1) {
    vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc_xy(), u_depth_convention));
    // Alpha 0: MAX keeps the host's.
    out_color = vec4(encode_display_srgb((sky_pixel_radiance(dir) + source) * u_exposure), 0.0f);
  } else {
    out_color = vec4(source * u_exposure, 0.0f);  // alpha: adds nothing
  }
}
