// The seams between the glows' tiles (fog_glow_smooth.frag). Each tile's list
// (its exact lights and its merged ones) fits its own part of the sky, so two
// neighbouring tiles' smooth glows differ a little at their border: a step a
// person sees as blocks. Within kSeam pixels of the reduced image from a
// border, along one axis a pass (x, then y), the pixel takes a tent-weighted
// mean of its neighbours at a similar surface distance (the step becomes a
// ramp 4 reduced pixels wide; nothing leaks across the host's geometry). Away
// from borders, and between tiles that merge nothing, the image is copied.
// The mean keeps the glows' sum.
uniform sampler2D u_near;  // RGBA32F: glow, log2 distance (fog_glow_smooth.frag)
uniform sampler2D u_far;
uniform float u_tile;      // reduced pixels per tile along the axis
uniform int u_axis;        // 0: x, 1: y
uniform usampler2D u_tiles;  // RGBA32UI per tile: first, count, merged, 0 (fog_renderer.cpp)
uniform vec2 u_tile_count;

layout(location = 0) out vec4 out_near;
layout(location = 1) out vec4 out_far;

const int kSeam = 2;

vec4 across(sampler2D image, ivec2 p, ivec2 step) {
  ivec2 last = textureSize(image, 0) - 1;
  vec4 c = texelFetch(image, p, 0);
  vec3 sum = float(kSeam + 1) * c.rgb;
  float w = float(kSeam + 1);
  for (int k = 1; k <= kSeam; ++k)
    for (int s = -1; s <= 1; s += 2) {
      vec4 n = texelFetch(image, clamp(p + s * k * step, ivec2(0), last), 0);
      if (abs(n.a - c.a) > 0.2) continue;  // another surface (log2 of the distance)
      sum += float(kSeam + 1 - k) * n.rgb;
      w += float(kSeam + 1 - k);
    }
  return vec4(sum / w, c.a);
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float x = (float(u_axis == 0 ? p.x : p.y) + 0.5) / u_tile;
  float to_border = min(fract(x), 1.0 - fract(x)) * u_tile;
  // The tiles on both sides of the nearest border: where neither holds a merged light their lists hold the
  // same lights exactly, and there is no seam to smooth.
  vec2 at = (vec2(p) + 0.5) / vec2(textureSize(u_near, 0)) * u_tile_count;
  vec2 other = at;
  if (u_axis == 0) other.x += fract(x) < 0.5 ? -1.0 : 1.0; else other.y += fract(x) < 0.5 ? -1.0 : 1.0;
  uint merged = texelFetch(u_tiles, ivec2(clamp(at, vec2(0.0), u_tile_count - 1.0)), 0).z +
                texelFetch(u_tiles, ivec2(clamp(other, vec2(0.0), u_tile_count - 1.0)), 0).z;
  if (to_border > float(kSeam) || merged == 0u) {
    out_near = texelFetch(u_near, p, 0);
    out_far = texelFetch(u_far, p, 0);
    return;
  }
  ivec2 step = u_axis == 0 ? ivec2(1, 0) : ivec2(0, 1);
  out_near = across(u_near, p, step);
  out_far = across(u_far, p, step);
}
