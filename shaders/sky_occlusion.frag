// ATMO_PASS_SKY_OCCLUSION: the host's objects' sky shadow, Sun shadow and
// bounce on the host's opaque surfaces (its terrain), for a host that does not
// shade them with atmo_sky_occlusion.glsl itself: each pixel's colour is
// multiplied by the ratio of its light with the objects to its light without
// (sky SH9 + Sun), for a surface at the host depth whose normal is the
// depth's (or up: AtmoPassInfo.flags). docs/SKY_OCCLUSION.md.
#include "atmosphere/pass_common.glsl"
#include "../host_sdk/include/atmo/atmo_sky_occlusion.glsl"

uniform int u_normal_up;  // 1: every surface faces up (terrain); 0: the normal from the depth's derivatives
uniform int u_no_sun;     // 1: the Sun's visibility left to the host (its shadow map): only the sky and the bounce
#if defined(ATMO_OCC_REDUCED) || defined(ATMO_OCC_IMAGE_PREPARE)
// At a fraction of the pixels (AtmoPassFlags): one texel for each u_reduction x u_reduction block, evaluated at
// the block's centre pixel; sky_occlusion_upsample.frag spreads it by depth.
uniform int u_reduction;
#endif

#ifdef ATMO_OCC_IMAGE_PREPARE
// ATMO_PASS_SKY_OCCLUSION_IMAGE: the view's image for the include with ATMO_OCC_IMAGE, one texel a block:
// the receiver's fit by normal (AtmoOccFit), evaluated at the block's middle pixel (the include's
// atmo_occ_image_map says which), with the depth's normal (or up) for its tangent plane and its anchor.
layout(location = 0) out vec4 out_sky;
layout(location = 1) out vec4 out_bounce;
layout(location = 2) out vec4 out_extra;

void main() {
  vec2 pixel = min(u_viewport.xy + floor(gl_FragCoord.xy) * float(u_reduction) + float(u_reduction / 2) + 0.5,
                   u_viewport.xy + u_viewport.zw - 0.5);
  vec2 ndc = (pixel - u_viewport.xy) / u_viewport.zw * 2.0 - 1.0;
  float depth = texelFetch(u_depth, ivec2(pixel) - u_depth_origin, 0).r;
  vec4 p = view_point_from_depth(u_view_from_clip, ndc, depth, u_depth_convention, u_log_far_m, u_log_coefficient);
  out_sky = vec4(0.0);
  out_bounce = vec4(0.0);
  out_extra = vec4(1.0, 1.0, 1.0, -1.0);  // no surface
  if (p.w < 0.0) return;
  vec3 position = u_enu_from_view * p.xyz;
  vec3 normal = vec3(0.0, 0.0, 1.0);
  if (u_normal_up == 0) {
    vec3 n = cross(dFdx(position), dFdy(position));
    normal = dot(n, n) > 1.0e-12 ? normalize(n) : normal;
    if (dot(normal, position) > 0.0) normal = -normal;  // towards the eye
  }
  AtmoOccFit fit;
  atmo_occ_evaluate(position, normal, true, fit);
  out_sky = fit.sky;
  out_bounce = fit.bounce;
  out_extra = fit.extra;
}
#else
out vec4 out_factor;

void main() {
#ifdef ATMO_OCC_REDUCED
  vec2 pixel = min(u_viewport.xy + (floor(gl_FragCoord.xy) + 0.5) * float(u_reduction),
                   u_viewport.xy + u_viewport.zw - 0.5);
  vec2 ndc = (pixel - u_viewport.xy) / u_viewport.zw * 2.0 - 1.0;
  float depth = texelFetch(u_depth, ivec2(pixel) - u_depth_origin, 0).r;
#else
  vec2 ndc = ndc_xy();
  float depth = host_depth();
#endif
  vec4 p = view_point_from_depth(u_view_from_clip, ndc, depth, u_depth_convention, u_log_far_m, u_log_coefficient);
#ifdef ATMO_OCC_REDUCED
  if (p.w < 0.0) {  // open sky: no surface (distance -1)
    out_factor = vec4(1.0, 1.0, 1.0, -1.0);
    return;
  }
#else
  if (p.w < 0.0) discard;  // open sky: nothing to shade
#endif
  // The include's "world" here is ENU at the eye (atmo_occ_enu_from_world is the identity).
  vec3 position = u_enu_from_view * p.xyz;
  vec3 normal = vec3(0.0, 0.0, 1.0);
  if (u_normal_up == 0) {
    vec3 n = cross(dFdx(position), dFdy(position));
    normal = dot(n, n) > 1.0e-12 ? normalize(n) : normal;
    if (dot(normal, position) > 0.0) normal = -normal;  // towards the eye
  }
  AtmoSkyOcclusion o = atmo_sky_occlusion(position, normal);
  vec3 sun = atmo_occ_sun_lux * max(dot(normal, atmo_occ_sun.xyz), 0.0);
  vec3 open = max(atmo_occ_sh9_dot(0, atmo_occ_basis(normal)), vec3(0.0)) + sun;
  vec3 lit = o.sky_lux + o.bounce_lux + sun * (u_no_sun != 0 ? 1.0 : o.sun_visibility);
  // Per channel, but where a channel's open light is small (a face turned from the Sun and most of the sky)
  // its ratio is noise over nothing: there the luminance's ratio, so no tint appears.
  const vec3 kLuminance = vec3(0.2126, 0.7152, 0.0722);
  float open_y = dot(open, kLuminance);
  float ratio_y = open_y > 0.0 ? dot(lit, kLuminance) / open_y : 1.0;
  float brightest = max(max(open.x, open.y), max(open.z, 1.0e-30));
  vec3 ratio = lit / max(open, vec3(1.0e-30));
  vec3 trust = smoothstep(vec3(0.02), vec3(0.1), open / brightest);
  vec3 factor = clamp(mix(vec3(ratio_y), ratio, trust), 0.0, 4.0);
#ifdef ATMO_OCC_REDUCED
  out_factor = vec4(factor, length(p.xyz));  // linear; the upsampling encodes
  return;
#endif
  // On a display-encoded target the factor applies to encoded values: its sRGB-like power (approximate: the
  // tone map is not undone).
  if (u_output_encoding == 1) factor = pow(factor, vec3(1.0 / 2.2));
  out_factor = vec4(factor, 1.0);
}
#endif  // ATMO_OCC_IMAGE_PREPARE
