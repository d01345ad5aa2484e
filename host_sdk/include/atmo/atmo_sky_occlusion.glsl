// atmo_sky_occlusion.glsl — the sky's light on the HOST's surfaces near its
// moving objects (aircraft, vehicles, hangars), with the objects' soft sky
// shadow, the Sun's visibility past them and one diffuse bounce off them
// (Ren et al. 2006; Guerrero's thesis, the bounce; docs/SKY_OCCLUSION.md).
//
// Each object is a set of spheres (set_occluders). For a receiver p with
// normal n, each sphere hides a cap of the sky of angular radius
// theta = asin(r / |c - p|); the caps' visibility is multiplied in spherical
// harmonics (order 4, 16 coefficients) as the exponential of the sum of the
// caps' logarithms (one table lookup and one zonal rotation a sphere; the
// exponential once a receiver: "optimal linear" or the hybrid of it with
// squarings), and the sky's radiance (SH16) is integrated against it with the
// receiver's cosine. Far objects count as one sphere of equal mean projected
// area, near ones sphere by sphere, blended between (no seams).
//
// HOST USE (GLSL 3.30+ fragment shader):
//   Each frame, after set_view: api.get_sky_occlusion(view, &occ) (AtmoSkyOcclusion).
//   If occ.object_count == 0 nothing is occluded: shade with get_lighting's SH9.
//   Bind (each to its own texture unit)
//     occ.tables       -> sampler2D  atmo_occ_tables
//     occ.spheres      -> sampler2D  atmo_occ_spheres
//     occ.objects      -> sampler2D  atmo_occ_objects
//     occ.tiles        -> usampler2D atmo_occ_tiles
//     occ.tile_objects -> usampler2D atmo_occ_tile_objects
//   and set the uniforms (glUniform*fv from the struct's arrays)
//     atmo_occ_tile_from_position = mat4(occ.tile_from_position)
//     atmo_occ_enu_from_world     = mat3(occ.enu_from_world)
//     atmo_occ_grid    = vec4(occ.grid)      atmo_occ_limits = vec4(occ.limits)
//     atmo_occ_sun     = vec4(occ.sun)       atmo_occ_sun_lux = vec3(occ.sun_lux)
//     atmo_occ_sky_sh9[9], atmo_occ_sun_sh9[9] (vec3), atmo_occ_transfer[108] (vec4)
//   then, per fragment:
//     AtmoSkyOcclusion o = atmo_sky_occlusion(position_rel_eye_m, normal);
//     vec3 L = albedo / pi * (o.sky_lux + o.bounce_lux
//                             + sun_lux * max(dot(normal, sun), 0.0) * o.sun_visibility);
//   position_rel_eye_m: the fragment's position minus the eye's (metres, the
//   view's world axes); normal: unit, world axes. sky_lux is the sky's
//   irradiance (the Sun excluded) with the objects' shadow, in [0, the
//   unoccluded]; bounce_lux the light the objects reflect onto the point;
//   sun_visibility the fraction of the Sun's disc the spheres leave (1 with
//   no object near: multiply your own sun term, or your shadow map's, by it).
//   #define ATMO_OCC_NO_BOUNCE before the include compiles the bounce out (about
//   half the cost: a uniform flag does not skip it on every GPU); bounce_lux is 0.
//   #define ATMO_OCC_NO_SUN compiles the Sun's visibility out (a fifth to a third
//   of the cost; for a host whose shadow maps give the Sun's shadow): it is 1.
//   A surface of an object itself is a receiver too: its own spheres that
//   contain the point or lie behind its tangent plane are left out.
//
// THE IMAGE (every pixel at a few texture reads; docs/SKY_OCCLUSION.md, "The image"):
//   after the host's depth, render_pass(ATMO_PASS_SKY_OCCLUSION, ATMO_PASS_SKY_OCCLUSION_IMAGE
//   [| QUARTER_RES | SIXTEENTH_RES] [| NORMAL_UP]); then get_sky_occlusion, and
//   #define ATMO_OCC_IMAGE before this include: the same atmo_sky_occlusion() call, which
//   reads (each on its own unit; no sampler object there: they filter linearly)
//     occ.image[0..2]  -> sampler2D atmo_occ_image0, atmo_occ_image1, atmo_occ_image2
//     atmo_occ_image_map = vec4(occ.image_map), atmo_occ_enu_from_world, atmo_occ_sky_sh9[9]
//   and gl_FragCoord (the image is the view's viewport's). The answer is the
//   include's at each block's pixel, its normal applied by bands 0 and 1 at
//   others; sun_visibility is the blocks' (edges move by up to a block: take
//   the Sun's shadow from your shadow maps); sky_visibility is the fraction of
//   the sky's light left.
//
// Everything outside the "#ifndef ATMO_TWIN" blocks is written in the subset the
// plugin's C++ twin compiles (float literals with f, no swizzles).
#ifndef ATMO_SKY_OCCLUSION_GLSL
#define ATMO_SKY_OCCLUSION_GLSL

// The helpers, once (the twin includes the file twice: helpers, then what reads the frame).
#ifndef ATMO_OCC_HELPERS
#define ATMO_OCC_HELPERS
#ifndef ATMO_OCC_FN
#define ATMO_OCC_FN
#endif
#ifndef INOUT
#define INOUT(T) inout T
#endif

const float ATMO_OCC_PI = 3.14159265358979f;
const float ATMO_OCC_TABLE_SIZE = 256.0f;  // texels a table row
const float ATMO_OCC_TABLE_ROWS = 3.0f;    // log cap, form factor, optimal linear

// 16 SH coefficients: a = (0..3), b = (4..7), c = (8..11), d = (12..15); index l(l+1)+m, Sloan's signs.
#ifndef ATMO_TWIN
struct AtmoOccSh {
  vec4 a;
  vec4 b;
  vec4 c;
  vec4 d;
};
struct AtmoSkyOcclusion {
  vec3 sky_lux;          // the sky's irradiance with the objects' shadow (the Sun excluded), lux
  float sun_visibility;  // the fraction of the Sun's disc the objects leave, [0, 1]
  vec3 bounce_lux;       // the objects' diffuse light onto the point, lux
  float sky_visibility;  // the cosine-weighted fraction of a uniform sky left (ambient occlusion), [0, 1]
};
// A receiver's answer as a function of its normal (the image's texels): the luminance the objects take from the
// sky and the bounce's luminance, each as 4 coefficients of y_0..y_3 (the normal's bands 0 and 1, ENU), made
// exact at the normal it was evaluated with; extra: the bounce's r/Y and b/Y, the Sun's visibility, the distance.
struct AtmoOccFit {
  vec4 sky;
  vec4 bounce;
  vec4 extra;
};
#endif

ATMO_OCC_FN AtmoOccSh atmo_occ_sh(vec4 a, vec4 b, vec4 c, vec4 d) {
  AtmoOccSh s;
  s.a = a;
  s.b = b;
  s.c = c;
  s.d = d;
  return s;
}
ATMO_OCC_FN AtmoOccSh atmo_occ_add(AtmoOccSh x, AtmoOccSh y, float w) {
  return atmo_occ_sh(x.a + w * y.a, x.b + w * y.b, x.c + w * y.c, x.d + w * y.d);
}
ATMO_OCC_FN float atmo_occ_dot(AtmoOccSh x, AtmoOccSh y) {
  return dot(x.a, y.a) + dot(x.b, y.b) + dot(x.c, y.c) + dot(x.d, y.d);
}

// y_i(d) for a unit d, order 4.
ATMO_OCC_FN AtmoOccSh atmo_occ_basis(vec3 d) {
  float x = d.x;
  float y = d.y;
  float z = d.z;
  float x2 = x * x;
  float y2 = y * y;
  float z2 = z * z;
  return atmo_occ_sh(vec4(0.2820948f, 0.4886025f * y, 0.4886025f * z, 0.4886025f * x),
                     vec4(1.0925484f * x * y, 1.0925484f * y * z, 0.3153916f * (3.0f * z2 - 1.0f), 1.0925484f * x * z),
                     vec4(0.5462742f * (x2 - y2), 0.5900436f * y * (3.0f * x2 - y2), 2.8906114f * x * y * z,
                          0.4570458f * y * (5.0f * z2 - 1.0f)),
                     vec4(0.3731763f * z * (5.0f * z2 - 3.0f), 0.4570458f * x * (5.0f * z2 - 1.0f),
                          1.4453057f * z * (x2 - y2), 0.5900436f * x * (x2 - 3.0f * y2)));
}

// A zonal function about the axis whose basis is y: k = its ZH bands times sqrt(4 pi / (2l + 1)).
ATMO_OCC_FN AtmoOccSh atmo_occ_rotate(vec4 k, AtmoOccSh y) {
  return atmo_occ_sh(y.a * vec4(k.x, k.y, k.y, k.y), y.b * k.z, y.c * vec4(k.z, k.w, k.w, k.w), y.d * k.w);
}

// max(0, cos)/pi about n (its band 3 is 0): rho . V is the cosine-weighted visible fraction.
ATMO_OCC_FN AtmoOccSh atmo_occ_cosine(AtmoOccSh y) {
  return atmo_occ_rotate(vec4(1.0f, 2.0f / 3.0f, 0.25f, 0.0f), y);
}

// Texture coordinate of x in [0, 1] on a row of n texels that holds both ends.
ATMO_OCC_FN float atmo_occ_grid_coordinate(float x, float n) { return (clamp(x, 0.0f, 1.0f) * (n - 1.0f) + 0.5f) / n; }

// A sphere (centre relative to the receiver, radius) against the receiver's tangent plane (unit normal n):
// behind it, left out (radius 0); across it, shrunk to the largest sphere inside it in front of the plane
// (tangent to the plane under the old centre); if its centre is behind the plane, also scaled down as the
// receiver nears the circle where it cuts the plane and out inside it (the thesis's alpha: a receiver on an
// object's own surface is not hidden by the spheres that hold that surface). Continuous in p and n.
ATMO_OCC_FN vec4 atmo_occ_adjust(vec4 sphere, vec3 n) {
  vec3 c = vec3(sphere.x, sphere.y, sphere.z);
  float r = sphere.w;
  float h = dot(n, c);
  if (!(r > 0.0f) || h + r <= 0.0f) return vec4(0.0f, 0.0f, 0.0f, 0.0f);
  if (h >= r) return sphere;
  float shrunk = 0.5f * (h + r);
  vec3 centre = c + n * (shrunk - h);
  if (h < 0.0f) {
    vec3 q = c - n * h;                        // the centre projected onto the plane (receiver at 0)
    float cut = sqrt(max(r * r - h * h, 0.0f));  // radius of the circle the sphere cuts from the plane
    shrunk *= clamp((length(q) - cut) / max(cut, 1.0e-6f), 0.0f, 1.0f);
  }
  return vec4(centre, shrunk);
}

// The fraction of the Sun's disc (angular radius sun_rad) a cap of half-angle theta covers, its centre at
// cos_gamma from the Sun: the disc as a chord's segment across the cap's edge (sun_rad << theta).
ATMO_OCC_FN float atmo_occ_sun_cover(float theta, float cos_gamma, float sun_rad) {
  // atan, not acos: GPUs' acos may be off by 1e-4 rad (llvmpipe's is), a fifth of the Sun's radius.
  float gamma = atan(sqrt(max(1.0f - cos_gamma * cos_gamma, 0.0f)), clamp(cos_gamma, -1.0f, 1.0f));
  float x = clamp((theta - gamma) / max(sun_rad, 1.0e-6f), -1.0f, 1.0f);
  return clamp(0.5f + (x * sqrt(max(1.0f - x * x, 0.0f)) + asin(x)) / ATMO_OCC_PI, 0.0f, 1.0f);
}

const vec3 ATMO_OCC_LUMINANCE = vec3(0.2126f, 0.7152f, 0.0722f);  // Rec.709 Y

// A receiver's light from its fit (AtmoOccFit) for a unit normal n (ENU) whose open sky irradiance is `open`:
// the sky's light less what the objects take (as a fraction of the open sky's luminance, in the open sky's
// colour), the bounce's luminance in its colour, the Sun's visibility.
ATMO_OCC_FN AtmoSkyOcclusion atmo_occ_from_fit(AtmoOccFit f, vec3 n, vec3 open) {
  vec4 y = vec4(0.2820948f, 0.4886025f * n.y, 0.4886025f * n.z, 0.4886025f * n.x);
  float open_y = dot(open, ATMO_OCC_LUMINANCE);
  float taken = max(dot(f.sky, y), 0.0f);
  AtmoSkyOcclusion o;
  o.sky_visibility = open_y > 0.0f ? clamp(1.0f - taken / open_y, 0.0f, 1.0f) : 1.0f;
  o.sky_lux = open * o.sky_visibility;
  vec3 tint = vec3(f.extra.x, (1.0f - 0.2126f * f.extra.x - 0.0722f * f.extra.y) / 0.7152f, f.extra.y);
  o.bounce_lux = max(dot(f.bounce, y), 0.0f) * max(tint, vec3(0.0f));
  o.sun_visibility = clamp(f.extra.z, 0.0f, 1.0f);
  return o;
}

// g * g at order 4 (the triple product's non-zeros; generated: core/shadows sh_square_glsl).
ATMO_OCC_FN AtmoOccSh atmo_occ_square(AtmoOccSh g) {
  AtmoOccSh r;
  r.a.x = 0.282094792f * g.a.x * g.a.x + 0.282094792f * g.a.y * g.a.y + 0.282094792f * g.a.z * g.a.z + 0.282094792f * g.a.w * g.a.w + 0.282094792f * g.b.x * g.b.x + 0.282094792f * g.b.y * g.b.y + 0.282094792f * g.b.z * g.b.z + 0.282094792f * g.b.w * g.b.w + 0.282094792f * g.c.x * g.c.x + 0.282094792f * g.c.y * g.c.y + 0.282094792f * g.c.z * g.c.z + 0.282094792f * g.c.w * g.c.w + 0.282094792f * g.d.x * g.d.x + 0.282094792f * g.d.y * g.d.y + 0.282094792f * g.d.z * g.d.z + 0.282094792f * g.d.w * g.d.w;
  r.a.y = 0.564189584f * g.a.x * g.a.y - 0.252313252f * g.a.y * g.b.z - 0.437019372f * g.a.y * g.c.x + 0.437019372f * g.a.z * g.b.y + 0.437019372f * g.a.w * g.b.x - 0.116798340f * g.b.x * g.d.y - 0.452358026f * g.b.x * g.d.w - 0.286096336f * g.b.y * g.d.x - 0.369348782f * g.b.y * g.d.z + 0.404601319f * g.b.z * g.c.w + 0.369348782f * g.b.w * g.c.z + 0.452358026f * g.c.x * g.c.y + 0.116798340f * g.c.x * g.c.w;
  r.a.z = 0.564189584f * g.a.x * g.a.z + 0.437019372f * g.a.y * g.b.y + 0.504626504f * g.a.z * g.b.z + 0.437019372f * g.a.w * g.b.w + 0.369348782f * g.b.x * g.c.z + 0.467193361f * g.b.y * g.c.w + 0.495533390f * g.b.z * g.d.x + 0.467193361f * g.b.w * g.d.y + 0.369348782f * g.c.x * g.d.z;
  r.a.w = 0.564189584f * g.a.x * g.a.w + 0.437019372f * g.a.y * g.b.x + 0.437019372f * g.a.z * g.b.w - 0.252313252f * g.a.w * g.b.z + 0.437019372f * g.a.w * g.c.x + 0.452358026f * g.b.x * g.c.y - 0.116798340f * g.b.x * g.c.w + 0.369348782f * g.b.y * g.c.z + 0.404601319f * g.b.z * g.d.y - 0.286096336f * g.b.w * g.d.x + 0.369348782f * g.b.w * g.d.z - 0.116798340f * g.c.x * g.d.y + 0.452358026f * g.c.x * g.d.w;
  r.b.x = 0.564189584f * g.a.x * g.b.x + 0.437019372f * g.a.y * g.a.w - 0.116798340f * g.a.y * g.d.y - 0.452358026f * g.a.y * g.d.w + 0.369348782f * g.a.z * g.c.z + 0.452358026f * g.a.w * g.c.y - 0.116798340f * g.a.w * g.c.w - 0.360447503f * g.b.x * g.b.z + 0.312156694f * g.b.y * g.b.w - 0.188063195f * g.c.y * g.d.y - 0.376126389f * g.c.z * g.d.x + 0.291346248f * g.c.w * g.d.y + 0.188063195f * g.c.w * g.d.w;
  r.b.y = 0.564189584f * g.a.x * g.b.y + 0.437019372f * g.a.y * g.a.z - 0.286096336f * g.a.y * g.d.x - 0.369348782f * g.a.y * g.d.z + 0.467193361f * g.a.z * g.c.w + 0.369348782f * g.a.w * g.c.z + 0.312156694f * g.b.x * g.b.w + 0.180223752f * g.b.y * g.b.z - 0.312156694f * g.b.y * g.c.x + 0.297354019f * g.c.y * g.d.z + 0.230329433f * g.c.z * g.d.y - 0.297354019f * g.c.z * g.d.w + 0.118941608f * g.c.w * g.d.x - 0.230329433f * g.c.w * g.d.z;
  r.b.z = 0.564189584f * g.a.x * g.b.z - 0.126156626f * g.a.y * g.a.y + 0.404601319f * g.a.y * g.c.w + 0.252313252f * g.a.z * g.a.z + 0.495533390f * g.a.z * g.d.x - 0.126156626f * g.a.w * g.a.w + 0.404601319f * g.a.w * g.d.y - 0.180223752f * g.b.x * g.b.x + 0.090111876f * g.b.y * g.b.y + 0.180223752f * g.b.z * g.b.z + 0.090111876f * g.b.w * g.b.w - 0.180223752f * g.c.x * g.c.x - 0.210261044f * g.c.y * g.c.y + 0.126156626f * g.c.w * g.c.w + 0.168208835f * g.d.x * g.d.x + 0.126156626f * g.d.y * g.d.y - 0.210261044f * g.d.w * g.d.w;
  r.b.w = 0.564189584f * g.a.x * g.b.w + 0.369348782f * g.a.y * g.c.z + 0.437019372f * g.a.z * g.a.w + 0.467193361f * g.a.z * g.d.y - 0.286096336f * g.a.w * g.d.x + 0.369348782f * g.a.w * g.d.z + 0.312156694f * g.b.x * g.b.y + 0.180223752f * g.b.z * g.b.w + 0.312156694f * g.b.w * g.c.x + 0.297354019f * g.c.y * g.c.z + 0.230329433f * g.c.z * g.c.w + 0.118941608f * g.d.x * g.d.y + 0.230329433f * g.d.y * g.d.z + 0.297354019f * g.d.z * g.d.w;
  r.c.x = 0.564189584f * g.a.x * g.c.x - 0.218509686f * g.a.y * g.a.y + 0.452358026f * g.a.y * g.c.y + 0.116798340f * g.a.y * g.c.w + 0.369348782f * g.a.z * g.d.z + 0.218509686f * g.a.w * g.a.w - 0.116798340f * g.a.w * g.d.y + 0.452358026f * g.a.w * g.d.w - 0.156078347f * g.b.y * g.b.y - 0.360447503f * g.b.z * g.c.x + 0.156078347f * g.b.w * g.b.w - 0.188063195f * g.c.y * g.c.w - 0.145673124f * g.c.w * g.c.w - 0.376126389f * g.d.x * g.d.z + 0.145673124f * g.d.y * g.d.y - 0.188063195f * g.d.y * g.d.w;
  r.c.y = 0.564189584f * g.a.x * g.c.y + 0.452358026f * g.a.y * g.c.x + 0.452358026f * g.a.w * g.b.x - 0.188063195f * g.b.x * g.d.y + 0.297354019f * g.b.y * g.d.z - 0.420522087f * g.b.z * g.c.y + 0.297354019f * g.b.w * g.c.z - 0.188063195f * g.c.x * g.c.w;
  r.c.z = 0.564189584f * g.a.x * g.c.z + 0.369348782f * g.a.y * g.b.w + 0.369348782f * g.a.z * g.b.x + 0.369348782f * g.a.w * g.b.y - 0.376126389f * g.b.x * g.d.x + 0.230329433f * g.b.y * g.d.y - 0.297354019f * g.b.y * g.d.w + 0.297354019f * g.b.w * g.c.y + 0.230329433f * g.b.w * g.c.w;
  r.c.w = 0.564189584f * g.a.x * g.c.w + 0.404601319f * g.a.y * g.b.z + 0.116798340f * g.a.y * g.c.x + 0.467193361f * g.a.z * g.b.y - 0.116798340f * g.a.w * g.b.x + 0.291346248f * g.b.x * g.d.y + 0.188063195f * g.b.x * g.d.w + 0.118941608f * g.b.y * g.d.x - 0.230329433f * g.b.y * g.d.z + 0.252313252f * g.b.z * g.c.w + 0.230329433f * g.b.w * g.c.z - 0.188063195f * g.c.x * g.c.y - 0.291346248f * g.c.x * g.c.w;
  r.d.x = 0.564189584f * g.a.x * g.d.x - 0.286096336f * g.a.y * g.b.y + 0.495533390f * g.a.z * g.b.z - 0.286096336f * g.a.w * g.b.w - 0.376126389f * g.b.x * g.c.z + 0.118941608f * g.b.y * g.c.w + 0.336417670f * g.b.z * g.d.x + 0.118941608f * g.b.w * g.d.y - 0.376126389f * g.c.x * g.d.z;
  r.d.y = 0.564189584f * g.a.x * g.d.y - 0.116798340f * g.a.y * g.b.x + 0.467193361f * g.a.z * g.b.w + 0.404601319f * g.a.w * g.b.z - 0.116798340f * g.a.w * g.c.x - 0.188063195f * g.b.x * g.c.y + 0.291346248f * g.b.x * g.c.w + 0.230329433f * g.b.y * g.c.z + 0.252313252f * g.b.z * g.d.y + 0.118941608f * g.b.w * g.d.x + 0.230329433f * g.b.w * g.d.z + 0.291346248f * g.c.x * g.d.y - 0.188063195f * g.c.x * g.d.w;
  r.d.z = 0.564189584f * g.a.x * g.d.z - 0.369348782f * g.a.y * g.b.y + 0.369348782f * g.a.z * g.c.x + 0.369348782f * g.a.w * g.b.w + 0.297354019f * g.b.y * g.c.y - 0.230329433f * g.b.y * g.c.w + 0.230329433f * g.b.w * g.d.y + 0.297354019f * g.b.w * g.d.w - 0.376126389f * g.c.x * g.d.x;
  r.d.w = 0.564189584f * g.a.x * g.d.w - 0.452358026f * g.a.y * g.b.x + 0.452358026f * g.a.w * g.c.x + 0.188063195f * g.b.x * g.c.w - 0.297354019f * g.b.y * g.c.z - 0.420522087f * g.b.z * g.d.w + 0.297354019f * g.b.w * g.d.z - 0.188063195f * g.c.x * g.d.y;
  return r;
}

#ifndef ATMO_TWIN
#ifndef ATMO_OCC_NO_UNIFORMS
#ifdef ATMO_OCC_IMAGE
uniform sampler2D atmo_occ_image0;     // RGBA32F, linear: AtmoOccFit.sky a texel (one texel a block of pixels)
uniform sampler2D atmo_occ_image1;     // RGBA32F, linear: AtmoOccFit.bounce
uniform sampler2D atmo_occ_image2;     // RGBA32F, linear: AtmoOccFit.extra (w: the surface's distance m, -1: none)
uniform vec4 atmo_occ_image_map;       // the window pixel of texel (0, 0)'s evaluation xy, pixels a texel spans, 0
uniform mat3 atmo_occ_enu_from_world;  // the eye's ENU axes from the view's world axes
uniform vec3 atmo_occ_sky_sh9[9];      // the sky's irradiance, SH9, lux

vec3 atmo_occ_sky_sh9_at(int k) { return atmo_occ_sky_sh9[k]; }
#else
uniform sampler2D atmo_occ_tables;         // RGBA32F, 256 x 3: log cap, form factor (by theta), (a, b) (by |f^|)
uniform sampler2D atmo_occ_spheres;        // RGBA32F: a sphere a texel (centre ENU relative to the eye m, radius m),
                                           // then 3 texels a group (bound, stand-in, first sphere and count); 1024 a row
uniform sampler2D atmo_occ_objects;        // RGBA32F: 4 texels an object (see atmo_occ_object), 256 a row
uniform usampler2D atmo_occ_tiles;         // RG32UI: per screen tile, its first object in atmo_occ_tile_objects and count
uniform usampler2D atmo_occ_tile_objects;  // R32UI: object indices, 4096 a row
uniform mat4 atmo_occ_tile_from_position;  // clip from the position relative to the eye (world axes)
uniform mat3 atmo_occ_enu_from_world;      // the eye's ENU axes from the view's world axes
uniform vec4 atmo_occ_grid;                // tiles across, tiles up, |f^| of the (a, b) row's end, flags (1 bounce, 2 hybrid)
uniform vec4 atmo_occ_limits;              // sin theta below which a sphere is left out, sin theta of an object's
                                           // bound below which it is one sphere, that times the blend, the Sun's radius rad
uniform vec4 atmo_occ_sun;                 // unit direction to the Sun, ENU; 0
uniform vec3 atmo_occ_sun_lux;             // the Sun's illuminance facing it (for the bounce)
uniform vec3 atmo_occ_sky_sh9[9];          // the sky's irradiance, SH9, lux
uniform vec3 atmo_occ_sun_sh9[9];          // the Sun's irradiance on an object's surface by normal, SH9, lux
uniform vec4 atmo_occ_transfer[108];       // the sky's product matrix against the cosine (see AtmoSkyOcclusion)

vec4 atmo_occ_table(float u, float row) {
  return texture(atmo_occ_tables, vec2(atmo_occ_grid_coordinate(u, ATMO_OCC_TABLE_SIZE), (row + 0.5) / ATMO_OCC_TABLE_ROWS));
}
vec4 atmo_occ_sphere(uint i) { return texelFetch(atmo_occ_spheres, ivec2(int(i % 1024u), int(i / 1024u)), 0); }
vec4 atmo_occ_object(uint i, int k) {
  return texelFetch(atmo_occ_objects, ivec2(4 * int(i % 256u) + k, int(i / 256u)), 0);
}
uvec2 atmo_occ_tile_list(vec3 position_rel_eye_m) {
  vec4 clip = atmo_occ_tile_from_position * vec4(position_rel_eye_m, 1.0);
  if (!(clip.w > 1.0e-6)) return uvec2(0u, 0u);
  vec2 ndc = clamp(clip.xy / clip.w, -1.0, 1.0);
  ivec2 tile = ivec2(min(floor((ndc * 0.5 + 0.5) * atmo_occ_grid.xy), atmo_occ_grid.xy - 1.0));
  return texelFetch(atmo_occ_tiles, tile, 0).xy;
}
uint atmo_occ_tile_object(uint entry) {
  return texelFetch(atmo_occ_tile_objects, ivec2(int(entry % 4096u), int(entry / 4096u)), 0).r;
}
vec4 atmo_occ_transfer_at(int k) { return atmo_occ_transfer[k]; }
vec3 atmo_occ_sky_sh9_at(int k) { return atmo_occ_sky_sh9[k]; }
vec3 atmo_occ_sun_sh9_at(int k) { return atmo_occ_sun_sh9[k]; }
vec4 atmo_occ_grid_value() { return atmo_occ_grid; }
vec4 atmo_occ_limits_value() { return atmo_occ_limits; }
vec4 atmo_occ_sun_value() { return atmo_occ_sun; }
mat3 atmo_occ_enu_from_world_value() { return atmo_occ_enu_from_world; }
#endif  // ATMO_OCC_IMAGE
#endif  // ATMO_OCC_NO_UNIFORMS
#endif  // ATMO_TWIN
#endif  // ATMO_OCC_HELPERS

#ifndef ATMO_OCC_NO_UNIFORMS
// The sky's irradiance: its SH9 (atmo_occ_sky_sh9, lux) against the first 9 coefficients of f.
ATMO_OCC_FN vec3 atmo_occ_sky_irradiance(AtmoOccSh f) {
  return atmo_occ_sky_sh9_at(0) * f.a.x + atmo_occ_sky_sh9_at(1) * f.a.y + atmo_occ_sky_sh9_at(2) * f.a.z +
         atmo_occ_sky_sh9_at(3) * f.a.w + atmo_occ_sky_sh9_at(4) * f.b.x + atmo_occ_sky_sh9_at(5) * f.b.y +
         atmo_occ_sky_sh9_at(6) * f.b.z + atmo_occ_sky_sh9_at(7) * f.b.w + atmo_occ_sky_sh9_at(8) * f.c.x;
}
#endif

#if !defined(ATMO_OCC_NO_UNIFORMS) && defined(ATMO_OCC_IMAGE) && !defined(ATMO_TWIN)
// The image's texels around this fragment, blended bilinearly among those on the fragment's own surface (their
// distance within 2 % of its own; none beyond 10 %) so no object's shadow bleeds across a silhouette; where none
// is, the nearest in distance; where the image has no surface there, the open sky.
AtmoSkyOcclusion atmo_sky_occlusion(vec3 position_rel_eye_m, vec3 normal_world) {
  vec3 n = normalize(atmo_occ_enu_from_world * normal_world);
  AtmoOccSh y = atmo_occ_basis(n);
  vec3 open = max(atmo_occ_sky_irradiance(y), vec3(0.0));
  vec2 size = vec2(textureSize(atmo_occ_image2, 0));
  vec2 at = (gl_FragCoord.xy - atmo_occ_image_map.xy) / atmo_occ_image_map.z;  // in texels from texel (0, 0)
  vec2 base = floor(at);
  vec2 f = at - base;
  ivec2 last = ivec2(size) - 1;
  ivec2 t00 = clamp(ivec2(base), ivec2(0), last);
  ivec2 t11 = clamp(ivec2(base) + 1, ivec2(0), last);
  // The four texels' surfaces' distances; each one's weight: bilinear, times whether it lies on this fragment's
  // surface (within 2 % of its distance: yes; beyond 10 %: no, a silhouette).
#if __VERSION__ >= 400
  // One gather (its order: (0, 1), (1, 1), (1, 0), (0, 0)); the clamped edge as texelFetch's.
  vec4 gathered = textureGather(atmo_occ_image2, (vec2(t00) + 1.0) / size, 3);
  vec4 dist = vec4(gathered.w, gathered.z, gathered.x, gathered.y);
  if (t11.x == t00.x) dist = vec4(dist.x, dist.x, dist.z, dist.z);
  if (t11.y == t00.y) dist = vec4(dist.x, dist.y, dist.x, dist.y);
#else
  vec4 e0 = texelFetch(atmo_occ_image2, t00, 0);
  vec4 e1 = texelFetch(atmo_occ_image2, ivec2(t11.x, t00.y), 0);
  vec4 e2 = texelFetch(atmo_occ_image2, ivec2(t00.x, t11.y), 0);
  vec4 e3 = texelFetch(atmo_occ_image2, t11, 0);
  vec4 dist = vec4(e0.w, e1.w, e2.w, e3.w);
#endif
  float d = length(position_rel_eye_m);
  vec4 off = abs(dist - d) / max(d, 1.0e-3);
  vec4 has = step(0.0, dist);
  vec4 w = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y) *
           (1.0 - smoothstep(0.02, 0.1, off)) * has;
  float total = w.x + w.y + w.z + w.w;
  // None on it: the nearest in distance (of those with a surface).
  vec4 far = mix(vec4(1.0e30), off, has);
  float best = min(min(far.x, far.y), min(far.z, far.w));
  vec4 nearest = vec4(equal(far, vec4(best)));
  w = total > 1.0e-4 ? w / total : nearest / max(nearest.x + nearest.y + nearest.z + nearest.w, 1.0);
  // The fit's other two parts by one filtered fetch each where the bilinear weights are the weights' centroid:
  // the plain bilinear on one surface, one texel or one side of a silhouette at its edge (no branch: a CPU
  // rasteriser runs both sides of one).
  vec2 towards = vec2(w.y + w.w, w.z + w.w);
  vec2 uv = (vec2(t00) + 0.5 + towards * vec2(t11 - t00)) / size;
  AtmoOccFit fit;
  fit.sky = texture(atmo_occ_image0, uv);
  fit.bounce = texture(atmo_occ_image1, uv);
#if __VERSION__ >= 400
  fit.extra = texture(atmo_occ_image2, uv);
#else
  fit.extra = w.x * e0 + w.y * e1 + w.z * e2 + w.w * e3;
#endif
  if (!(best < 1.0e29)) {  // no surface in the four texels (the sky's pixels): nothing occluded
    fit.sky = vec4(0.0);
    fit.bounce = vec4(0.0);
    fit.extra = vec4(1.0, 1.0, 1.0, 0.0);
  }
  return atmo_occ_from_fit(fit, n, open);
}
#endif  // ATMO_OCC_IMAGE

#if !defined(ATMO_OCC_NO_UNIFORMS) && !defined(ATMO_OCC_IMAGE)
// exp*(f) by Ren's optimal linear form: exp(f_0 / sqrt(4 pi)) (a(|f^|) 1 + b(|f^|) f^).
ATMO_OCC_FN AtmoOccSh atmo_occ_exp_linear(AtmoOccSh f) {
  AtmoOccSh hat = atmo_occ_sh(vec4(0.0f, f.a.y, f.a.z, f.a.w), f.b, f.c, f.d);
  float m = sqrt(atmo_occ_dot(hat, hat));
  vec4 ab = atmo_occ_table(m / atmo_occ_grid_value().z, 2.0f);
  float scale = exp(f.a.x * 0.2820948f);
  AtmoOccSh r = atmo_occ_add(atmo_occ_sh(vec4(0.0f), vec4(0.0f), vec4(0.0f), vec4(0.0f)), hat, scale * ab.y);
  r.a.x = scale * ab.x * 3.5449077f;
  return r;
}

// The hybrid: the optimal linear form of f^ / 2^p (|f^| / 2^p <= 1, p <= 3), then p squarings.
ATMO_OCC_FN AtmoOccSh atmo_occ_exp_hybrid(AtmoOccSh f) {
  AtmoOccSh hat = atmo_occ_sh(vec4(0.0f, f.a.y, f.a.z, f.a.w), f.b, f.c, f.d);
  float m = sqrt(atmo_occ_dot(hat, hat));
  int p = m > 4.0f ? 3 : (m > 2.0f ? 2 : (m > 1.0f ? 1 : 0));
  float s = p == 3 ? 0.125f : (p == 2 ? 0.25f : (p == 1 ? 0.5f : 1.0f));
  AtmoOccSh g = atmo_occ_exp_linear(atmo_occ_add(atmo_occ_sh(vec4(0.0f), vec4(0.0f), vec4(0.0f), vec4(0.0f)), hat, s));
  for (int k = 0; k < p; ++k) g = atmo_occ_square(g);
  float scale = exp(f.a.x * 0.2820948f);
  return atmo_occ_add(atmo_occ_sh(vec4(0.0f), vec4(0.0f), vec4(0.0f), vec4(0.0f)), g, scale);
}

// sum_k sh9_k f_k over the first 9 coefficients of f: the sky's (which 0) or the Sun's (1) irradiance SH9.
ATMO_OCC_FN vec3 atmo_occ_sh9_dot(int which, AtmoOccSh f) {
  if (which == 0) return atmo_occ_sky_irradiance(f);
  return atmo_occ_sun_sh9_at(0) * f.a.x + atmo_occ_sun_sh9_at(1) * f.a.y + atmo_occ_sun_sh9_at(2) * f.a.z +
         atmo_occ_sun_sh9_at(3) * f.a.w + atmo_occ_sun_sh9_at(4) * f.b.x + atmo_occ_sun_sh9_at(5) * f.b.y +
         atmo_occ_sun_sh9_at(6) * f.b.z + atmo_occ_sun_sh9_at(7) * f.b.w + atmo_occ_sun_sh9_at(8) * f.c.x;
}

// One sphere's part (its weight w in [0, 1]) in the running log-visibility, the Sun's visibility and the
// bounce (prev: exp of the log before it, for the bounce's telescoping visibilities).
// fit: also the bounce's luminance by normal (bands 0 and 1 of rho . mine, unclamped) into bounce_fit.
ATMO_OCC_FN void atmo_occ_add_sphere(vec4 sphere_rel, vec3 n, AtmoOccSh rho, vec3 albedo, float w, bool sun_too,
                                     bool bounce, bool fit, INOUT(AtmoOccSh) log_v, INOUT(AtmoOccSh) prev,
                                     INOUT(float) sun_v, INOUT(vec3) bounce_lux, INOUT(vec4) bounce_fit) {
  vec4 s = atmo_occ_adjust(sphere_rel, n);
  if (!(s.w > 0.0f)) return;
  vec3 c = vec3(s.x, s.y, s.z);
  float d = length(c);
  vec4 limits = atmo_occ_limits_value();
  float sin_theta = d > s.w ? s.w / d : 1.0f;
  if (sin_theta < limits.x) return;
  // Faded in over [limit, 2 limit]: a sphere leaves the sum smoothly as it recedes.
  w *= smoothstep(limits.x, 2.0f * limits.x, sin_theta);
  float theta = atan(sin_theta, sqrt(max(1.0f - sin_theta * sin_theta, 0.0f)));  // asin's precision, as above
  vec3 omega = c / max(d, 1.0e-9f);
  AtmoOccSh y = atmo_occ_basis(omega);
  float u = theta / (0.5f * ATMO_OCC_PI);
  AtmoOccSh g = atmo_occ_rotate(atmo_occ_table(u, 0.0f) * w, y);
  vec4 sun = atmo_occ_sun_value();
#ifndef ATMO_OCC_NO_SUN
  if (sun_too) sun_v *= 1.0f - w * atmo_occ_sun_cover(theta, dot(omega, vec3(sun.x, sun.y, sun.z)), limits.w);
#endif
  if (bounce) {
    // The part of the sky this sphere hides and no sphere before it: exp(sum before) - exp(sum with it).
    AtmoOccSh next = atmo_occ_exp_linear(atmo_occ_add(log_v, g, 1.0f));
    AtmoOccSh mine = atmo_occ_add(prev, next, -1.0f);
    float seen = max(atmo_occ_dot(rho, mine), 0.0f);
    // Its mean radiance towards p: the surface irradiance (SH9 by normal) weighed by the form factor about
    // the direction from its centre to p (-omega: odd bands change sign).
    vec4 k = atmo_occ_table(u, 1.0f);
    AtmoOccSh f = atmo_occ_rotate(k, atmo_occ_sh(y.a * vec4(1.0f, -1.0f, -1.0f, -1.0f), y.b, y.c * vec4(1.0f, -1.0f, -1.0f, -1.0f), -y.d));
    // Sky and Sun apart: the Sun's clamped cosine rings negative in 9 coefficients on the surface turned
    // from it, which would cancel the sky's light there.
    vec3 e = max(atmo_occ_sh9_dot(0, f), vec3(0.0f)) + max(atmo_occ_sh9_dot(1, f), vec3(0.0f));
    // Radiance albedo E / pi over the cosine-weighted fraction it fills (seen): irradiance albedo E seen.
    bounce_lux += albedo * e * seen;
    if (fit)
      bounce_fit += dot(albedo * e, ATMO_OCC_LUMINANCE) *
                    vec4(mine.a.x, 2.0f / 3.0f * mine.a.y, 2.0f / 3.0f * mine.a.z, 2.0f / 3.0f * mine.a.w);
    prev = next;
  }
  log_v = atmo_occ_add(log_v, g, 1.0f);
}

// The Sun's cover alone by spheres [first, first + count) (weight w): a stand-in is a blob in the sky, not the
// object's shadow, so where the Sun's ray meets a stand-in's bound its spheres cast the Sun's shadow.
ATMO_OCC_FN void atmo_occ_sun_spheres(uint first, uint count, vec3 p, vec3 n, float w, INOUT(float) sun_v) {
#ifdef ATMO_OCC_NO_SUN
  return;  // compiled out: the host's shadow maps give the Sun's shadow
#endif
  vec4 sun = atmo_occ_sun_value();
  vec3 s_dir = vec3(sun.x, sun.y, sun.z);
  float sun_rad = atmo_occ_limits_value().w;
  for (uint i = 0u; i < count; ++i) {
    vec4 raw = atmo_occ_sphere(first + i);
    vec4 s = atmo_occ_adjust(vec4(vec3(raw.x, raw.y, raw.z) - p, raw.w), n);
    if (!(s.w > 0.0f)) continue;
    vec3 c = vec3(s.x, s.y, s.z);
    float d = length(c);
    float sin_theta = d > s.w ? s.w / d : 1.0f;
    float theta = atan(sin_theta, sqrt(max(1.0f - sin_theta * sin_theta, 0.0f)));
    sun_v *= 1.0f - w * atmo_occ_sun_cover(theta, dot(c / max(d, 1.0e-9f), s_dir), sun_rad);
  }
}

// Whether the ray from p towards the Sun meets a bound (centre relative to p, radius).
ATMO_OCC_FN bool atmo_occ_sun_meets(vec3 to_centre, float radius) {
  vec4 sun = atmo_occ_sun_value();
  float t = dot(to_centre, vec3(sun.x, sun.y, sun.z));
  return t > -radius && dot(to_centre, to_centre) - t * t < radius * radius;
}

// rho_k times row k of the sky's transfer against V, per channel (the transfer: 36 vec4 a channel, 4 a row).
ATMO_OCC_FN vec3 atmo_occ_transfer_row(int k, float rho_k, AtmoOccSh v) {
  int at = 4 * k;
  return rho_k * vec3(dot(v.a, atmo_occ_transfer_at(at)) + dot(v.b, atmo_occ_transfer_at(at + 1)) +
                          dot(v.c, atmo_occ_transfer_at(at + 2)) + dot(v.d, atmo_occ_transfer_at(at + 3)),
                      dot(v.a, atmo_occ_transfer_at(36 + at)) + dot(v.b, atmo_occ_transfer_at(37 + at)) +
                          dot(v.c, atmo_occ_transfer_at(38 + at)) + dot(v.d, atmo_occ_transfer_at(39 + at)),
                      dot(v.a, atmo_occ_transfer_at(72 + at)) + dot(v.b, atmo_occ_transfer_at(73 + at)) +
                          dot(v.c, atmo_occ_transfer_at(74 + at)) + dot(v.d, atmo_occ_transfer_at(75 + at)));
}

// The sky's light at a receiver (position relative to the eye, world axes; unit normal, world axes); with
// `fit`, also its light by normal into out_fit (the plugin's image: ATMO_PASS_SKY_OCCLUSION_IMAGE).
ATMO_OCC_FN AtmoSkyOcclusion atmo_occ_evaluate(vec3 position_rel_eye_m, vec3 normal_world, bool fit,
                                               INOUT(AtmoOccFit) out_fit) {
  mat3 enu = atmo_occ_enu_from_world_value();
  vec3 p = enu * position_rel_eye_m;
  vec3 n = normalize(enu * normal_world);
  AtmoOccSh y = atmo_occ_basis(n);
  vec3 open = max(atmo_occ_sh9_dot(0, y), vec3(0.0f));
  AtmoSkyOcclusion out_;
  out_.sky_lux = open;
  out_.sun_visibility = 1.0f;
  out_.bounce_lux = vec3(0.0f);
  out_.sky_visibility = 1.0f;
  out_fit.sky = vec4(0.0f);
  out_fit.bounce = vec4(0.0f);
  out_fit.extra = vec4(1.0f, 1.0f, 1.0f, length(position_rel_eye_m));
  uvec2 list = atmo_occ_tile_list(position_rel_eye_m);
  if (list.y == 0u) return out_;
  vec4 grid = atmo_occ_grid_value();
  vec4 limits = atmo_occ_limits_value();
  int flags = int(grid.w + 0.5f);
#ifdef ATMO_OCC_NO_BOUNCE
  bool bounce = false;  // compiled out: the host never draws the bounce
#else
  bool bounce = (flags % 2) == 1;
#endif
  AtmoOccSh rho = atmo_occ_cosine(y);
  AtmoOccSh zero = atmo_occ_sh(vec4(0.0f), vec4(0.0f), vec4(0.0f), vec4(0.0f));
  AtmoOccSh log_v = zero;
  AtmoOccSh prev = atmo_occ_sh(vec4(3.5449077f, 0.0f, 0.0f, 0.0f), vec4(0.0f), vec4(0.0f), vec4(0.0f));
  float sun_v = 1.0f;
  vec3 bounce_lux = vec3(0.0f);
  vec4 bounce_fit = vec4(0.0f);
  bool any = false;
  for (uint j = 0u; j < list.y; ++j) {
    uint o = atmo_occ_tile_object(list.x + j);
    vec4 bound = atmo_occ_object(o, 0);  // bounding sphere: centre ENU relative to the eye, radius
    vec3 to_bound = vec3(bound.x, bound.y, bound.z) - p;
    float db = length(to_bound);
    float sin_bound = db > bound.w ? bound.w / db : 1.0f;
    vec4 groups = atmo_occ_object(o, 3);  // first group's texel, groups
    uint first_group = uint(groups.x + 0.5f);
    uint group_count = uint(groups.y + 0.5f);
    if (sin_bound < limits.x) {
      // Too small in the sky to hide it, but not the Sun: its shadow reaches as far as it is listed.
      if (atmo_occ_sun_meets(to_bound, bound.w)) {
        for (uint k = 0u; k < group_count; ++k) {
          vec4 range = atmo_occ_sphere(first_group + 3u * k + 2u);
          atmo_occ_sun_spheres(uint(range.x + 0.5f), uint(range.y + 0.5f), p, n, 1.0f, sun_v);
        }
        any = true;
      }
      continue;
    }
    // Sphere by sphere where the object is large in the sky, one sphere where it is small, blended between;
    // and within it, group by group the same way (the hierarchy: object, groups of <= 8 spheres, spheres).
    float near_w = smoothstep(limits.y, limits.z, sin_bound);
    vec4 albedo_w = atmo_occ_object(o, 2);  // albedo rgb
    vec3 albedo = vec3(albedo_w.x, albedo_w.y, albedo_w.z);
    if (near_w < 1.0f) {
      vec4 proxy = atmo_occ_object(o, 1);
      atmo_occ_add_sphere(vec4(vec3(proxy.x, proxy.y, proxy.z) - p, proxy.w), n, rho, albedo, 1.0f - near_w, false,
                          bounce, fit, log_v, prev, sun_v, bounce_lux, bounce_fit);
      if (atmo_occ_sun_meets(to_bound, bound.w)) {
        for (uint k = 0u; k < group_count; ++k) {
          vec4 range = atmo_occ_sphere(first_group + 3u * k + 2u);
          atmo_occ_sun_spheres(uint(range.x + 0.5f), uint(range.y + 0.5f), p, n, 1.0f - near_w, sun_v);
        }
      }
    }
    if (near_w > 0.0f) {
      for (uint k = 0u; k < group_count; ++k) {
        uint at = first_group + 3u * k;
        vec4 gb = atmo_occ_sphere(at);
        vec3 to_group = vec3(gb.x, gb.y, gb.z) - p;
        float dg = length(to_group);
        float sin_group = dg > gb.w ? gb.w / dg : 1.0f;
        if (sin_group < limits.x) continue;
        float group_w = smoothstep(limits.y, limits.z, sin_group);
        vec4 range = atmo_occ_sphere(at + 2u);  // first sphere, count
        uint first = uint(range.x + 0.5f);
        uint count = uint(range.y + 0.5f);
        if (group_w < 1.0f) {
          vec4 gp = atmo_occ_sphere(at + 1u);
          atmo_occ_add_sphere(vec4(vec3(gp.x, gp.y, gp.z) - p, gp.w), n, rho, albedo, near_w * (1.0f - group_w),
                              false, bounce, fit, log_v, prev, sun_v, bounce_lux, bounce_fit);
          if (atmo_occ_sun_meets(to_group, gb.w))
            atmo_occ_sun_spheres(first, count, p, n, near_w * (1.0f - group_w), sun_v);
        }
        if (group_w > 0.0f) {
          for (uint i = 0u; i < count; ++i) {
            vec4 s = atmo_occ_sphere(first + i);
            atmo_occ_add_sphere(vec4(vec3(s.x, s.y, s.z) - p, s.w), n, rho, albedo, near_w * group_w, true, bounce,
                                fit, log_v, prev, sun_v, bounce_lux, bounce_fit);
          }
        }
      }
    }
    any = true;
  }
  if (!any) return out_;
  AtmoOccSh v = (flags / 2) % 2 == 1 ? atmo_occ_exp_hybrid(log_v) : atmo_occ_exp_linear(log_v);
  // E_c = sum_k rho_k sum_i M_ik V_i over the cosine's 9 coefficients.
  vec3 sky = atmo_occ_transfer_row(0, rho.a.x, v) + atmo_occ_transfer_row(1, rho.a.y, v) +
             atmo_occ_transfer_row(2, rho.a.z, v) + atmo_occ_transfer_row(3, rho.a.w, v) +
             atmo_occ_transfer_row(4, rho.b.x, v) + atmo_occ_transfer_row(5, rho.b.y, v) +
             atmo_occ_transfer_row(6, rho.b.z, v) + atmo_occ_transfer_row(7, rho.b.w, v) +
             atmo_occ_transfer_row(8, rho.c.x, v);
  out_.sky_lux = clamp(sky, vec3(0.0f), open);
  out_.sun_visibility = clamp(sun_v, 0.0f, 1.0f);
  // The bounce's visibilities came from the optimal-linear exponential, which runs bright under large
  // occluders: scale them to hide what the sky's (hybrid) visibility hides.
  float hidden = 1.0f - atmo_occ_dot(rho, v);
  float hidden_linear = 1.0f - atmo_occ_dot(rho, prev);
  float scale = hidden_linear > 1.0e-4f ? clamp(hidden / hidden_linear, 0.0f, 4.0f) : 1.0f;
  out_.bounce_lux = max(bounce_lux * scale, vec3(0.0f));
  out_.sky_visibility = clamp(atmo_occ_dot(rho, v), 0.0f, 1.0f);
  if (fit) {
    // Bands 0 and 1 (by normal) of what the objects take from the sky's luminance and of the bounce's,
    // each shifted in band 0 to be exact at n (the normal evaluated: the image's block).
    vec4 taken = vec4(dot(atmo_occ_sky_sh9_at(0), ATMO_OCC_LUMINANCE), dot(atmo_occ_sky_sh9_at(1), ATMO_OCC_LUMINANCE),
                      dot(atmo_occ_sky_sh9_at(2), ATMO_OCC_LUMINANCE), dot(atmo_occ_sky_sh9_at(3), ATMO_OCC_LUMINANCE)) -
                 vec4(dot(atmo_occ_transfer_row(0, 1.0f, v), ATMO_OCC_LUMINANCE),
                      2.0f / 3.0f * dot(atmo_occ_transfer_row(1, 1.0f, v), ATMO_OCC_LUMINANCE),
                      2.0f / 3.0f * dot(atmo_occ_transfer_row(2, 1.0f, v), ATMO_OCC_LUMINANCE),
                      2.0f / 3.0f * dot(atmo_occ_transfer_row(3, 1.0f, v), ATMO_OCC_LUMINANCE));
    float taken_here = dot(open - out_.sky_lux, ATMO_OCC_LUMINANCE);
    taken.x += (taken_here - dot(taken, y.a)) / 0.2820948f;
    vec4 b = bounce_fit * scale;
    float bounce_here = dot(out_.bounce_lux, ATMO_OCC_LUMINANCE);
    b.x += (bounce_here - dot(b, y.a)) / 0.2820948f;
    out_fit.sky = taken;
    out_fit.bounce = b;
    float by = max(bounce_here, 1.0e-30f);
    out_fit.extra = bounce_here > 0.0f ? vec4(out_.bounce_lux.x / by, out_.bounce_lux.z / by, out_.sun_visibility, out_fit.extra.w)
                                       : vec4(1.0f, 1.0f, out_.sun_visibility, out_fit.extra.w);
  }
  return out_;
}

ATMO_OCC_FN AtmoSkyOcclusion atmo_sky_occlusion(vec3 position_rel_eye_m, vec3 normal_world) {
  AtmoOccFit unused;
  return atmo_occ_evaluate(position_rel_eye_m, normal_world, false, unused);
}
#endif  // !ATMO_OCC_NO_UNIFORMS && !ATMO_OCC_IMAGE

#endif  // ATMO_SKY_OCCLUSION_GLSL
