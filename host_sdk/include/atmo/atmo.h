/*
 * atmo.h — the stable C ABI of the Atmo atmosphere plugin (libatmo.so).
 *
 * Atmo draws the sky, aerial perspective, clouds, night sky and light glows
 * into the host's own OpenGL context. This header is all a host needs: it is
 * valid C99, C11 and C++ (tested), and depends on <stdint.h>/<stddef.h> only.
 *
 * LIFECYCLE
 *   1. dlopen("libatmo.so"), dlsym("atmo_negotiate") — the only exported symbol.
 *   2. atmo_negotiate(&host_info, &api): agree on an interface version, receive
 *      a size-prefixed table of function pointers (AtmoPluginApi).
 *   3. api.create_context(&create_info, &ctx)      one per world / atmosphere state
 *      api.gl_init(ctx)                            with the host's GL context current
 *      api.create_view(ctx, &view_info, &view)     one per channel / eye
 *   4. Each frame: api.set_frame(ctx, &frame); api.set_view(view, &view_state);
 *      api.render_pass(view, &pass) for each pass, where it belongs in the
 *      host's pipeline (sky, opaques, aerial perspective, clouds, ...).
 *   5. api.destroy_view(view); api.gl_shutdown(ctx); api.destroy_context(ctx).
 *      If the GL context was lost, call api.gl_context_lost(ctx) instead of
 *      gl_shutdown; gl_init may then be called again on a new context.
 *
 * THREAD RULES (each function's comment ends with its rule in brackets)
 *   [any-thread]       may be called from any thread.
 *   [ctx-sync]         calls on one context (and its views) must not overlap;
 *                      the host serialises them. Different contexts are independent.
 *   [gl-current]       the host's GL context that gl_init saw (or a context
 *                      sharing objects with it) must be current on the calling thread.
 *   [no-gl]            touches no GL; no context needs to be current.
 *
 * UNITS: SI everywhere. Lengths in metres, time in seconds, angles in radians
 * except geodetic latitude/longitude, which are degrees (the edge convention of
 * GPS, CIGI and GeographicLib). Luminance in cd/m^2, illuminance in lux.
 *
 * GL STATE CONTRACT: on return from every function, all GL state the plugin
 * touched is as the host left it (program, VAO, buffer and texture bindings on
 * every unit it used, active texture unit, framebuffer bindings, viewport,
 * scissor, depth/blend/cull/stencil state, colour and depth masks, ...).
 * Core and compatibility profiles (3.3 or later) both work.
 *
 * VERSIONED STRUCTS: every struct that crosses the ABI begins with an
 * AtmoStructHeader {type, struct_size, next}. A struct may grow at its end in
 * later versions: the plugin reads min(struct_size, its own size) bytes and
 * zero-fills the rest, so every field's zero value is a documented default.
 * A struct_size smaller than the version-1 size is rejected with
 * ATMO_ERROR_STRUCT_TOO_SMALL. `next` chains extension structs; entries whose
 * type the plugin does not know are skipped.
 *
 * ARRAYS: an array the host passes (cloud layers, lights) comes as a pointer,
 * a count and a stride field `<element>_size` beside them: sizeof the element
 * as the host compiled it, so the element can grow like any struct. 0 means
 * the version-1 size; otherwise it must be a multiple of 8 within
 * [version-1 size, ATMO_ARRAY_ELEMENT_SIZE_MAX]: smaller is
 * ATMO_ERROR_STRUCT_TOO_SMALL, larger or unaligned ATMO_ERROR_OUT_OF_RANGE.
 * The plugin reads count * stride bytes and no more.
 *
 * RESULTS: 0 is success, > 0 a status (success with a remark), < 0 an error.
 * api.result_string(code) names any code; api.last_error(ctx) gives the last
 * detailed message (what went wrong and where). No C++ exception crosses the ABI.
 */
#ifndef ATMO_ATMO_H
#define ATMO_ATMO_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Versions                                                                  */
/* ------------------------------------------------------------------------ */

/* Interface versions are integers; the plugin implements a contiguous range. */
#define ATMO_INTERFACE_VERSION_1 1u
#define ATMO_INTERFACE_VERSION_CURRENT ATMO_INTERFACE_VERSION_1

#define ATMO_NEGOTIATE_SYMBOL "atmo_negotiate"

/* The largest stride of an array element (see ARRAYS above), bytes. */
#define ATMO_ARRAY_ELEMENT_SIZE_MAX 1024u
/* The largest file the plugin reads (AtmoHostServices.file_read), bytes: 1 GiB. */
#define ATMO_FILE_SIZE_MAX (1ull << 30)

/* ------------------------------------------------------------------------ */
/* Results                                                                   */
/* ------------------------------------------------------------------------ */

typedef int32_t AtmoResult;

enum {
  ATMO_SUCCESS = 0,
  /* Statuses (> 0): the call succeeded. */
  ATMO_STATUS_NOTHING_TO_DRAW = 1, /* the pass had nothing visible; it cost nothing */
  ATMO_STATUS_NOT_YET_SUPPORTED = 2, /* reserved: no function of version 1 returns it (every pass is implemented) */
  /* Errors (< 0): the call did nothing, state is unchanged. */
  ATMO_ERROR_INVALID_ARGUMENT = -1,      /* NULL where a pointer is required, bad enum, ... */
  ATMO_ERROR_INCOMPATIBLE_VERSION = -2,  /* no interface version in the host's range */
  ATMO_ERROR_STRUCT_TOO_SMALL = -3,      /* struct_size below the version-1 size */
  ATMO_ERROR_WRONG_STRUCT_TYPE = -4,     /* header.type is not the expected tag */
  ATMO_ERROR_NON_FINITE_VALUE = -5,      /* NaN or Inf in a field that must be finite */
  ATMO_ERROR_OUT_OF_RANGE = -6,          /* a finite value outside its documented range */
  ATMO_ERROR_CALL_OUT_OF_ORDER = -7,     /* e.g. render_pass before gl_init or set_view */
  ATMO_ERROR_GL = -8,                    /* GL loading, shader compile or a GL error */
  ATMO_ERROR_OUT_OF_MEMORY = -9,
  ATMO_ERROR_IO = -10,                   /* a file could not be opened or read */
  ATMO_ERROR_INVALID_HANDLE = -11,       /* a handle not made by this plugin, or destroyed */
  ATMO_ERROR_INTERNAL = -12              /* a bug in the plugin; the message says where */
};

/* ------------------------------------------------------------------------ */
/* Struct header and type tags                                               */
/* ------------------------------------------------------------------------ */

typedef enum AtmoStructType {
  ATMO_TYPE_NONE = 0,
  ATMO_TYPE_NEGOTIATE_INFO = 0x41540001,
  ATMO_TYPE_PLUGIN_API = 0x41540002,
  ATMO_TYPE_HOST_SERVICES = 0x41540003,
  ATMO_TYPE_CONTEXT_CREATE_INFO = 0x41540004,
  ATMO_TYPE_VIEW_CREATE_INFO = 0x41540005,
  ATMO_TYPE_ATMOSPHERE_STATE = 0x41540006,
  ATMO_TYPE_FRAME_STATE = 0x41540007,
  ATMO_TYPE_VIEW_STATE = 0x41540008,
  ATMO_TYPE_PASS_INFO = 0x41540009,
  ATMO_TYPE_LIGHTING = 0x4154000A,
  ATMO_TYPE_CLOUD_LAYER = 0x4154000B,
  ATMO_TYPE_CLOUDS_STATE = 0x4154000C,
  ATMO_TYPE_CLOUD_SHADOWS = 0x4154000D,
  ATMO_TYPE_FOG_STATE = 0x4154000E,
  ATMO_TYPE_LIGHTS_STATE = 0x4154000F,
  ATMO_TYPE_FOG_LIGHTING = 0x41540010,
  ATMO_TYPE_LIGHT_GROUP_POSE = 0x41540011,
  ATMO_TYPE_LIGHTS_UPDATE = 0x41540012,
  ATMO_TYPE_OCCLUDERS_STATE = 0x41540013,
  ATMO_TYPE_OCCLUDER_POSES = 0x41540014,
  ATMO_TYPE_SKY_OCCLUSION = 0x41540015,
  ATMO_TYPE_STATE_HASH = 0x41540016,
  ATMO_TYPE_MAX_ENUM = 0x7fffffff
} AtmoStructType;

typedef struct AtmoStructHeader {
  uint32_t type;        /* an AtmoStructType */
  uint32_t struct_size; /* sizeof the struct as the caller compiled it */
  const void* next;     /* chain of extension structs, each starting with a header; may be NULL */
} AtmoStructHeader;

/* Fills a header; use as `AtmoFrameState f = {ATMO_HEADER(ATMO_TYPE_FRAME_STATE, AtmoFrameState)};`. */
#define ATMO_HEADER(type_tag, struct_type) \
  { (uint32_t)(type_tag), (uint32_t)sizeof(struct_type), NULL }

/* ------------------------------------------------------------------------ */
/* Opaque handles                                                            */
/* ------------------------------------------------------------------------ */

typedef struct AtmoContext_T* AtmoContext; /* one world / atmosphere state */
typedef struct AtmoView_T* AtmoView;       /* one channel or eye of a context */

/* ------------------------------------------------------------------------ */
/* Host services — every member may be NULL; the fallback is documented.    */
/* ------------------------------------------------------------------------ */

typedef enum AtmoLogSeverity {
  ATMO_LOG_DEBUG = 0,
  ATMO_LOG_INFO = 1,
  ATMO_LOG_WARNING = 2,
  ATMO_LOG_ERROR = 3,
  ATMO_LOG_HOST_MISBEHAVING = 4 /* the host broke a documented rule */
} AtmoLogSeverity;

typedef void* (*AtmoGlProcLoader)(void* user, const char* name);

typedef struct AtmoHostServices {
  AtmoStructHeader header; /* ATMO_TYPE_HOST_SERVICES */
  void* user;              /* passed back as the first argument of every service */

  /* Log sink. Fallback: warnings and errors go to stderr, prefixed "[atmo]".
     May be called from any thread the plugin is called on. */
  void (*log)(void* user, int32_t severity, const char* message);

  /* Allocator for the memory of the plugin's handles: each context and view
     object comes from it and goes back to it when destroyed. alignment is a
     power of two. Fallback: aligned_alloc/free. Everything else (lookup
     tables, cloud volumes, star catalogues, containers) comes from the C++
     heap: version 1 does not route those through the host. */
  void* (*allocate)(void* user, size_t size, size_t alignment);
  void (*deallocate)(void* user, void* pointer);

  /* File access, so a host can relocate or package assets. open returns a
     non-NULL handle or NULL; read fills at most `size` bytes of `buffer` and
     returns how many (0 at end, < 0 on error); a return above `size` fails the
     read (ATMO_ERROR_IO, a HOST_MISBEHAVING log line) and nothing past the
     buffer is used. A file may hold at most ATMO_FILE_SIZE_MAX bytes; a longer
     one fails with ATMO_ERROR_IO. Paths are UTF-8, relative ones resolve
     against AtmoContextCreateInfo.asset_root. All three or none must be set.
     Fallback: the C standard library's fopen/fread/fclose (the same cap). */
  void* (*file_open)(void* user, const char* path);
  int64_t (*file_read)(void* user, void* file, void* buffer, uint64_t size);
  void (*file_close)(void* user, void* file);

  /* GL entry-point loader (eglGetProcAddress, glfwGetProcAddress, ...). The
     plugin links no libGL/libEGL. Fallback: eglGetProcAddress, then
     glXGetProcAddressARB, looked up in the libraries the process has already
     loaded; gl_init fails with ATMO_ERROR_GL if neither is there. */
  AtmoGlProcLoader gl_get_proc_address;
} AtmoHostServices;

/* ------------------------------------------------------------------------ */
/* Context and view creation                                                 */
/* ------------------------------------------------------------------------ */

typedef struct AtmoContextCreateInfo {
  AtmoStructHeader header;        /* ATMO_TYPE_CONTEXT_CREATE_INFO */
  const AtmoHostServices* services; /* may be NULL: all fallbacks. Copied; need not outlive the call. */
  const char* asset_root;         /* UTF-8 directory for plugin data files; NULL: next to libatmo.so */
  const char* application_name;   /* named in the stderr log fallback's lines ("[atmo] name: error: ...");
                                     may be NULL */
  uint64_t seed;                  /* seed of every random stream (clouds, scintillation); 0 is a valid seed */
} AtmoContextCreateInfo;

typedef struct AtmoViewCreateInfo {
  AtmoStructHeader header; /* ATMO_TYPE_VIEW_CREATE_INFO */
  uint32_t channel_id;     /* host's channel / eye number: named in the view's pass log lines; changes no result */
  uint32_t reserved;
} AtmoViewCreateInfo;

/* ------------------------------------------------------------------------ */
/* World state                                                               */
/* ------------------------------------------------------------------------ */

/* The air. Zero fields take the defaults given. */
typedef struct AtmoAtmosphereState {
  AtmoStructHeader header;   /* ATMO_TYPE_ATMOSPHERE_STATE */
  /* Meteorological optical range (MOR, 5 % contrast threshold) at the ground, metres.
     Sets the aerosol (Mie) extinction at sea level: beta = ln(20) / MOR = 2.996 / MOR
     (Koschmieder, 5 % contrast threshold) minus Rayleigh at 550 nm.
     0: default 40 000 m (clear). Valid range [50, 500 000]. */
  double visibility_m;
  /* Aerosol scale height, metres. 0: default 1200 m. Valid range [100, 20 000]. */
  double aerosol_scale_height_m;
  /* Lambertian ground albedo in [0, 1] (used where the view ray meets the Earth
     with no host geometry, e.g. from high altitude). 0: default 0.1.
     Use a tiny positive value for a black ground. */
  double ground_albedo;
} AtmoAtmosphereState;

/* Time. UTC is POSIX time: days of exactly 86 400 s since 1970-01-01T00:00:00Z,
   as the host's clock gives it; leap seconds are re-inserted inside the plugin
   (UTC -> TAI -> TT with the IAU SOFA/ERFA tables) where precise ephemerides
   need TT, and UT1 = UTC + dut1_s for the Earth's rotation. */
typedef struct AtmoFrameState {
  AtmoStructHeader header;      /* ATMO_TYPE_FRAME_STATE */
  uint64_t host_frame_number;   /* the frame's number, the same on every channel: work done off the host's
                                   thread (new tables, the clouds' lighting) takes effect at the frame it was
                                   asked at + ATMO_DEFERRED_FRAMES; the clouds' impostors are updated once a
                                   frame; the clouds' temporal history (AtmoViewState.cloud_quality) is
                                   dropped when it is neither the last frame's nor the next; named in the
                                   passes' log lines. A host that leaves it 0 has its set_frame calls counted
                                   instead (docs/MULTI_CHANNEL.md) */
  double utc_posix_s;           /* simulation time, see above. Valid range [-62 135 596 800, 253 402 300 799] s:
                                   0001-01-01T00:00:00Z to 9999-12-31T23:59:59Z (docs/EPHEMERIS.md: accuracy
                                   degrades outside 1900-2100) */
  double dut1_s;                /* UT1 - UTC in seconds (IERS Bulletin A). Valid range [-0.9, 0.9]; 0 is fine
                                   for rendering */
  /* --- Added with several channels (a 40-byte host struct reads these as 0) --- */
  uint32_t deferred_frames;     /* frames between asking for work off the host's thread and its effect;
                                   0: ATMO_DEFERRED_FRAMES. [1, 100 000]. The same on every channel. A frame that
                                   comes before the work is done waits for it: a real-time host gives the
                                   slowest work room (new tables ~0.4 s, a large deck's relight seconds on 2
                                   cores: 60-120 frames at 60 Hz), a test a few frames (docs/MULTI_CHANNEL.md) */
  uint32_t reserved;            /* 0 */
} AtmoFrameState;

typedef enum AtmoPositionKind {
  ATMO_POSITION_ECEF = 0,     /* eye_ecef_m is used */
  ATMO_POSITION_GEODETIC = 1  /* eye_geodetic is used (WGS84) */
} AtmoPositionKind;

typedef enum AtmoWorldFrame {
  /* The host's world axes are ECEF (X to 0°N 0°E, Z to the North Pole). */
  ATMO_WORLD_ECEF = 0,
  /* The host's world axes are east-north-up at world_origin_geodetic (a local tangent plane). */
  ATMO_WORLD_ENU = 1
} AtmoWorldFrame;

typedef enum AtmoDepthConvention {
  /* glDepthRange(0,1), NDC z in [-1,1], near -> 0, far -> 1, depth test LESS/LEQUAL.
     Distance is recovered through the inverse of clip_from_view. */
  ATMO_DEPTH_STANDARD = 0,
  /* glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) with a reversed projection:
     NDC z in [0,1], near -> 1, far (or infinity) -> 0, depth test GREATER/GEQUAL. */
  ATMO_DEPTH_REVERSED_ZERO_TO_ONE = 1,
  /* Logarithmic depth written by the host's fragment shaders:
     depth = log2(C * w + 1) / log2(C * far + 1), w = view-space distance along -z,
     C = log_depth_coefficient, far = far_plane_m. Far -> 1. */
  ATMO_DEPTH_LOGARITHMIC = 2
} AtmoDepthConvention;

/* Which texel of depth_texture belongs to a pixel of the viewport. */
typedef enum AtmoDepthTextureOrigin {
  /* The texture covers the framebuffer: texel (x, y) is window pixel (x, y),
     as for a depth attachment of the framebuffer the passes draw into. */
  ATMO_DEPTH_ORIGIN_WINDOW = 0,
  /* The texture covers the viewport only: texel (0, 0) is its lower-left pixel
     (viewport[0], viewport[1]); e.g. VTK's renderer depth copied per viewport. */
  ATMO_DEPTH_ORIGIN_VIEWPORT = 1
} AtmoDepthTextureOrigin;

typedef enum AtmoOutputEncoding {
  /* Linear Rec.709/sRGB primaries (D65 white): RGB in cd/m^2 times exposure_scale,
     for a float render target the host tone-maps itself. */
  ATMO_OUTPUT_LINEAR_HDR = 0,
  /* Display-referred: exposure, a filmic tone curve and the sRGB transfer function
     are applied in the shader, for an 8-bit non-sRGB target. */
  ATMO_OUTPUT_DISPLAY_SRGB = 1
} AtmoOutputEncoding;

/* How the sky and aerial-perspective passes compute the air (docs/SKY.md has
   each method's measured error and cost). */
typedef enum AtmoSkyMethod {
  /* The plugin chooses: ATMO_SKY_METHOD_LUT, or the march where the tables do
     not apply (eye above the atmosphere). */
  ATMO_SKY_METHOD_AUTO = 0,
  /* Lookup tables (Hillaire 2020): a sky-view table per view and an
     aerial-perspective volume per view and frame, built on the GPU from the
     transmittance and multiple-scattering tables. The default. */
  ATMO_SKY_METHOD_LUT = 1,
  /* Preetham 1999 analytic sky, its zenith luminance calibrated to the LUT
     model; where the fit is not valid (low turbidity, sun below ~6 degrees,
     eye above ~500 m) it cross-fades to the LUT tier by its confidence.
     Aerial perspective as in the LUT tier. Cheapest. */
  ATMO_SKY_METHOD_ANALYTIC = 2,
  /* Per-pixel ray march of the same model, no sky-view or volume tables:
     the most accurate real-time method and the slowest. */
  ATMO_SKY_METHOD_MARCH = 3,
  ATMO_SKY_METHOD_COUNT = 4
} AtmoSkyMethod;

/* The clouds' cost knob of a view (AtmoViewState.cloud_quality): what the
   layer march (ATMO_CLOUD_DRAW_LAYER) spends on this view. Each level is an
   image resolution, a step budget per pixel and whether a frame traces a
   quarter of the image's pixels and reprojects the others from this view's
   last frame (temporal: a view's image then depends on its own earlier
   frames, never on another view's). docs/CLOUDS.md charts each level's error
   and cost. The impostor and direct modes take AtmoCloudsState's
   march_resolution_divisor and ignore this. */
typedef enum AtmoCloudQuality {
  ATMO_CLOUD_QUALITY_DEFAULT = 0, /* ATMO_CLOUD_QUALITY_MEDIUM */
  ATMO_CLOUD_QUALITY_LOW = 1,     /* 1/4 resolution, 96 steps, temporal */
  ATMO_CLOUD_QUALITY_MEDIUM = 2,  /* 1/2 resolution, 64 steps, temporal */
  ATMO_CLOUD_QUALITY_HIGH = 3,    /* 1/2 resolution, 192 steps, every pixel every frame */
  ATMO_CLOUD_QUALITY_FULL = 4,    /* full resolution, 384 steps, every pixel every frame */
  ATMO_CLOUD_QUALITY_COUNT = 5
} AtmoCloudQuality;

/* One channel's camera and render target for this frame. Matrices are
   column-major 4x4 doubles (OpenGL convention, element [col*4 + row]). */
typedef struct AtmoViewState {
  AtmoStructHeader header; /* ATMO_TYPE_VIEW_STATE */

  /* Eye position, double precision; rendering inside is relative to the eye. */
  uint32_t eye_kind;            /* AtmoPositionKind */
  uint32_t world_frame;         /* AtmoWorldFrame of view_from_world's axes */
  double eye_ecef_m[3];         /* ECEF metres, if eye_kind == ATMO_POSITION_ECEF; its height must be valid (below) */
  /* latitude deg [-90,90], longitude deg [-1e4, 1e4], height m above the WGS84 ellipsoid.
     Eye height valid range (either kind) [-1000, 1e7] m: every pass draws, and the Sun, Moon,
     planets and stars are placed for the eye's height (the Moon's parallax) up to 10 000 km. */
  double eye_geodetic[3];
  double world_origin_geodetic[3]; /* origin of the ENU world frame (lat deg, lon deg, h m); ATMO_WORLD_ENU only */

  /* The host's view matrix. Only its rotation is used (the eye is given above),
     so a host whose world is ECEF loses no precision to a huge translation.
     Must be rigid: the upper 3x3 a rotation (R R^T = I to 1e-3 per entry,
     det > 0: no scale, shear or mirror), the bottom row (0, 0, 0, 1) to 1e-3,
     the translation finite; else ATMO_ERROR_OUT_OF_RANGE. */
  double view_from_world[16];
  /* The host's projection matrix (perspective, finite or infinite far plane).
     Must be invertible with condition number |P|inf |P^-1|inf <= 1e10; else
     ATMO_ERROR_OUT_OF_RANGE. */
  double clip_from_view[16];

  /* Render target: the plugin draws into the framebuffer bound when a pass is
     called, restricted to this viewport (pixels). */
  int32_t viewport[4];          /* x, y, width, height; width, height > 0 */

  /* The host's depth, as a GL texture name (GL_TEXTURE_2D, any depth format),
     read with texelFetch at each pixel of the viewport, at the texel that
     depth_origin (below) names: by default the window pixel. 0: no depth — the sky
     then covers the whole viewport and aerial perspective draws nothing. The
     plugin never writes depth; strictly by the GL spec the texture should not
     be attached to the framebuffer bound for the passes (docs/ABI.md). */
  uint32_t depth_texture;
  uint32_t depth_convention;    /* AtmoDepthConvention */
  double far_plane_m;           /* ATMO_DEPTH_LOGARITHMIC only: the far distance in the formula */
  double log_depth_coefficient; /* ATMO_DEPTH_LOGARITHMIC only: C; 0 means 1 */

  uint32_t output_encoding;     /* AtmoOutputEncoding */
  uint32_t reserved;
  /* Multiplier from cd/m^2 to output units. 0: default 1 / (1.2 * 2^15), i.e.
     EV100 = 15, a sunny-day exposure. Photographic: 1 / (1.2 * 2^EV100). */
  double exposure_scale;

  /* --- Added after version 1 (a 408-byte host struct reads these as 0) --- */
  uint32_t sky_method;          /* AtmoSkyMethod; 0 = ATMO_SKY_METHOD_AUTO */
  uint32_t reserved2;           /* 0 */
  /* LUT-tier table sizes (docs/SKY.md charts error against cost per size).
     0 takes the default. Sky view: width in [16, 1024], height even in
     [16, 1024], default 192 x 108. Aerial-perspective volume: froxels across
     and up in [4, 256], slices in [4, 256], default 32 x 32 x 32. */
  uint32_t sky_view_table_size[2];
  uint32_t aerial_volume_size[3];
  uint32_t reserved3;           /* 0 */

  /* --- Added after version 2 (a 440-byte host struct reads these as 0) --- */
  uint32_t depth_origin;        /* AtmoDepthTextureOrigin; 0 = ATMO_DEPTH_ORIGIN_WINDOW */
  uint32_t reserved4;           /* 0 */
  /* How far the aerial-perspective volume's last slice reaches from the eye, m
     (slice k of n at range * ((k + 1) / n)^2; geometry farther away gets the
     last slice's haze). 0: default, the nearer of the farthest ground the eye
     can see (its horizon plus a 9 km summit's, 423 km from 600 m) and the end
     of the air along the horizon, whatever the projection (the depth
     conventions and an infinite far plane draw one image). Else [100, 1e7].
     docs/SKY.md. */
  double aerial_range_m;

  /* --- Added after version 3 (a 456-byte host struct reads these as 0) --- */
  uint32_t cloud_quality;       /* AtmoCloudQuality; 0 = ATMO_CLOUD_QUALITY_DEFAULT */
  uint32_t reserved5;           /* 0 */
} AtmoViewState;

/* ------------------------------------------------------------------------ */
/* Passes                                                                    */
/* ------------------------------------------------------------------------ */

/* AtmoPassKind: which pass AtmoPassInfo.pass draws. Named AtmoPass at first; that name (a host's own
   render-pass class often has it) stays as an alias unless the host defines ATMO_NO_LEGACY_NAMES before
   including this header. */
typedef enum AtmoPassKind {
  /* Sky dome, sun disc, and the Earth seen from above where no geometry is;
     the Moon's disc, the moonlit sky and the faint night background whenever
     they can be seen. Draws only where the host depth is at the far plane (or
     everywhere with no depth texture), so it may be called before or after
     opaques. Replaces colour. */
  ATMO_PASS_SKY = 0,
  /* Haze over the host's opaque geometry, from the host depth: colour =
     colour * transmittance + in-scattered light. Call after opaques. */
  ATMO_PASS_AERIAL_PERSPECTIVE = 1,
  /* Volumetric clouds (set_clouds): blended over what is drawn, against the
     host depth, with the aerial perspective applied. Call after
     ATMO_PASS_NIGHT_SKY, so clouds hide the stars, and after the host's
     opaques. ATMO_STATUS_NOTHING_TO_DRAW (no GL call) with no clouds.
     docs/CLOUDS.md. */
  ATMO_PASS_CLOUDS = 2,
  /* Stars and planets as points (photometric, dimmed by the air, only where
     the host depth is at the far plane). Call after ATMO_PASS_SKY, which
     draws the Moon's disc, the moonlit sky and the faint night background
     (airglow, zodiacal light, Milky Way) whenever they can be seen. Returns
     ATMO_STATUS_NOTHING_TO_DRAW, with no GL call, when no star or planet can
     change a pixel at this exposure (daylight). docs/NIGHT_SKY.md. */
  ATMO_PASS_NIGHT_SKY = 3,
  /* Fog (set_fog) over everything drawn so far, from the host depth: colour =
     colour * fog transmittance + the fog's own light, and the glows of the
     host's lights (set_lights) around them in the fog. Call last, after the
     clouds and the host's opaques (whose fogged lighting comes from
     atmo_fog_lights.glsl, which leaves the fog between surface and eye to this
     pass). ATMO_STATUS_NOTHING_TO_DRAW, with no GL call, without fog.
     docs/FOG.md. */
  ATMO_PASS_LIGHT_GLOWS = 4,
  /* The host's lights (set_lights) as points: each light's direct image, its
     illuminance at the eye I T / d^2 (the air's and the fog's transmittance T
     along the way, the cone towards the eye) spread over a few pixels, where
     the host's geometry does not hide it. A light is drawn where that
     illuminance exceeds the eye's threshold (Allard's law; night ~8e-7 lx,
     day 1e-4 lx: AtmoLightsState.visual_threshold_lux), so a light dimmer
     than the sky behind it costs nothing. Needs no fog. Call after
     ATMO_PASS_LIGHT_GLOWS (the points carry their own fog). NOTHING_TO_DRAW,
     with no GL call, when no light is visible. docs/FOG.md. */
  ATMO_PASS_LIGHT_POINTS = 5,
  /* The host's objects (set_occluders) shading its opaque surfaces, for a host
     that does not shade them with atmo_sky_occlusion.glsl (its terrain, say):
     colour *= the surface's light with the objects (their sky shadow, the
     Sun's visibility past them, their bounce) / its light without (get_lighting's
     sky SH9 and Sun), at the host depth, with the depth's normal or, with
     ATMO_PASS_SKY_OCCLUSION_NORMAL_UP, facing up (terrain: the depth's normal
     is unreliable on silhouettes, so shade objects with the include). Call
     after the surfaces it shades and before ATMO_PASS_AERIAL_PERSPECTIVE;
     draw the surfaces that use the include after it. NOTHING_TO_DRAW, with no GL call, without
     objects or depth. docs/SKY_OCCLUSION.md. */
  ATMO_PASS_SKY_OCCLUSION = 6,
  ATMO_PASS_COUNT = 7
} AtmoPassKind;
#ifndef ATMO_NO_LEGACY_NAMES
typedef AtmoPassKind AtmoPass;
#endif

/* AtmoPassInfo.flags */
typedef enum AtmoPassFlags {
  ATMO_PASS_SKY_OCCLUSION_NORMAL_UP = 1u,    /* ATMO_PASS_SKY_OCCLUSION: every surface faces up (terrain) */
  /* ATMO_PASS_SKY_OCCLUSION at a fraction of the pixels: one evaluation a 4 x 4 (QUARTER), 8 x 8 (EIGHTH)
     or 16 x 16 (SIXTEENTH) block, spread over the block by depth (no bleeding across silhouettes; the Sun's
     shadow edges soften over the block: with ATMO_PASS_SKY_OCCLUSION_NO_SUN they keep their shape). At most
     one of the three. Cost and error: docs/SKY_OCCLUSION.md. */
  ATMO_PASS_SKY_OCCLUSION_QUARTER_RES = 2u,
  ATMO_PASS_SKY_OCCLUSION_EIGHTH_RES = 4u,
  /* ATMO_PASS_SKY_OCCLUSION: the Sun's visibility left to the host (its shadow maps): only the sky's shadow
     and the bounce, which are smooth, so a fraction of the pixels loses little */
  ATMO_PASS_SKY_OCCLUSION_NO_SUN = 8u,
  /* ATMO_PASS_SKY_OCCLUSION: instead of shading the host's colour, evaluates the objects' light once a block
     (QUARTER_RES 4 x 4, SIXTEENTH_RES 16 x 16, else 8 x 8) at the host depth into the view's image, which atmo_sky_occlusion.glsl
     compiled with ATMO_OCC_IMAGE reads (AtmoSkyOcclusion.image: call get_sky_occlusion after this pass);
     the host's framebuffer is not touched. For a host that shades every pixel through the include at the
     cost of a few texture reads: after its depth (a depth pre-pass or a G-buffer), before its shading.
     With NO_SUN the image holds no Sun visibility (1; its edges would move by up to a block anyway: take the
     Sun's shadow from the host's shadow maps), a fifth cheaper. docs/SKY_OCCLUSION.md. */
  ATMO_PASS_SKY_OCCLUSION_IMAGE = 16u,
  ATMO_PASS_SKY_OCCLUSION_SIXTEENTH_RES = 32u
} AtmoPassFlags;

typedef struct AtmoPassInfo {
  AtmoStructHeader header; /* ATMO_TYPE_PASS_INFO */
  uint32_t pass;           /* AtmoPassKind */
  uint32_t flags;          /* AtmoPassFlags the pass takes; 0 for the others */
} AtmoPassInfo;

/* ------------------------------------------------------------------------ */
/* Clouds                                                                    */
/* ------------------------------------------------------------------------ */

typedef enum AtmoCloudLayerType {
  ATMO_CLOUD_CUMULUS = 0,   /* fair-weather cumulus: separate clouds, flat bases, coverage in oktas */
  ATMO_CLOUD_STRATUS = 1,   /* a low deck, broken below 8 oktas */
  ATMO_CLOUD_OVERCAST = 2,  /* a dense deck, 8 oktas (coverage is ignored) */
  ATMO_CLOUD_CIRRUS = 3,    /* thin, high ice streaks */
  ATMO_CLOUD_VDB_FILE = 4,  /* a density grid from an OpenVDB file */
  ATMO_CLOUD_LAYER_TYPE_COUNT = 5
} AtmoCloudLayerType;

/* One cloud layer or one OpenVDB volume. Heights and positions are metres in
   the clouds' east-north-up frame (AtmoCloudsState.origin_geodetic). Zero
   fields take the defaults given. */
typedef struct AtmoCloudLayer {
  AtmoStructHeader header;   /* ATMO_TYPE_CLOUD_LAYER */
  uint32_t type;             /* AtmoCloudLayerType */
  int32_t coverage_oktas;    /* procedural: 0..8, the share of the ground under cloud in eighths */
  double base_m;             /* procedural: cloud base, ENU up; [0, 20 000] */
  double top_m;              /* procedural: cloud tops; > base_m, <= 20 000 */
  double area_centre_enu_m[2]; /* procedural: centre (east, north) of the square the layer fills */
  double area_size_m;        /* procedural: its side; 0: 20 000; [500, 400 000] */
  uint64_t seed;             /* procedural: the layer's random stream (0 is a valid seed) */
  /* ATMO_CLOUD_VDB_FILE: the file (UTF-8; relative paths resolve against
     AtmoContextCreateInfo.asset_root; read through the host's file service)
     and the float grid in it (NULL: "density"). Values are densities, 1 =
     the extinction below. */
  const char* vdb_path;
  const char* vdb_grid;
  double position_enu_m[3];  /* VDB: where the file's world origin goes */
  double rotation_deg[3];    /* VDB: heading (about up, clockwise from north), pitch, roll of the file's axes
                                (x east, y north, z up at 0,0,0); only heading is supported yet: pitch, roll 0 */
  double metres_per_unit;    /* VDB: metres per unit of the file's world space; 0: 1 */
  double density_scale;      /* VDB: multiplies the file's values; 0: 1 */
  /* Optics, all types: 0 takes the type's default (docs/CLOUDS.md). */
  double extinction_per_m;   /* at density 1, 1/m; (0, 1] */
  double droplet_diameter_um; /* effective droplet diameter (phase function), [5, 50] */
} AtmoCloudLayer;

typedef struct AtmoCloudsState {
  AtmoStructHeader header;   /* ATMO_TYPE_CLOUDS_STATE */
  /* The ENU frame the layers are given in (latitude deg, longitude deg, height m, WGS84). */
  double origin_geodetic[3];
  /* The layers: layer_count structs, layer_size bytes apart (ARRAYS above);
     each layer's header.struct_size must lie in [168, layer_size]. At most 64
     layers; 0 layers: no clouds (the pass then costs nothing). */
  const AtmoCloudLayer* layers;
  uint32_t layer_count;
  /* Quality knobs; 0 takes the default (docs/CLOUDS.md charts their error and cost). */
  uint32_t march_resolution_divisor; /* the cloud march renders at 1/n of the viewport per axis, [1, 8]; default 2 */
  double march_step_voxels;          /* view-ray step, voxels, [0.25, 8]; default 1 */
  uint32_t multiple_scattering_octaves; /* 1 = single scattering, [1, 8]; default 6 */
  uint32_t layer_size;               /* sizeof(AtmoCloudLayer) as the host compiled it: the layers' stride;
                                        0: 168 (version 1) */
  double light_update_threshold_deg; /* the light's direction may move this far before the clouds are relit; default 0.5 */
  /* Impostors (Harris & Lastra 2001; docs/CLOUDS.md). These fields grew the
     struct after its first 80-byte layout: a host with that layout gets the
     defaults. 0 takes the default. */
  uint32_t draw_mode;                /* AtmoCloudDrawMode; default ATMO_CLOUD_DRAW_AUTO */
  uint32_t impostor_texels;          /* an impostor's side in the atlas, [16, 512]; default 128 */
  double impostor_angle_threshold_deg; /* re-render an impostor when the view of it changed this much, [0.05, 10];
                                        default 0.5 */
  uint32_t impostor_updates_per_frame; /* re-renders of existing impostors per pass, [1, 4096]; default 8 (a cloud
                                          entering the view always gets its impostor at once) */
  uint32_t reserved2;                /* 0 */
  double direct_march_radii;         /* the direct march takes over within this many bounding radii of a cloud,
                                        [1, 100]; default 2 */
  double impostor_max_pixels_per_texel; /* ... or where an impostor texel would cover more pixels of the march's
                                           image than this, [0.25, 8]; default 1 */
  /* Grew after the impostor settings (120 bytes): a host with that layout gets
     the default. */
  uint32_t setup;                    /* AtmoCloudSetup: how ATMO_CLOUD_DRAW_LAYER gets its lighting and clipmap
                                        ready; default ATMO_CLOUD_SETUP_STREAM. The other draw modes always wait */
  uint32_t reserved3;                /* 0 */
} AtmoCloudsState;

/* When the layer march's light grids and clipmap are ready (docs/CLOUDS.md,
   "Bounded set-up"). */
typedef enum AtmoCloudSetup {
  ATMO_CLOUD_SETUP_STREAM = 0, /* the first pass after set_clouds draws a half-resolution draft (lit and
                                  resampled on the calling thread, ~1/10 of the full work); the full light
                                  grids, shadow map and clipmap are made on the worker and shown from the first
                                  pass after each is ready, and the clipmap follows the eye from cell to cell
                                  the same way: no pass waits. Decks (stratus, overcast, cirrus) are generated
                                  by set_clouds with half as many voxels across, and in full by a worker,
                                  swapped in by the first pass after it ends. What a frame shows then depends
                                  on how far the workers got (the machine's load), as with a changed air */
  ATMO_CLOUD_SETUP_WAIT = 1,   /* every pass that needs the full lighting or a clipmap for its cell makes it
                                  first (or waits for the worker's): slow first frames and hitches at cell
                                  crossings, but each frame is a function of the inputs alone. For tests and
                                  stills */
  ATMO_CLOUD_SETUP_COUNT = 2
} AtmoCloudSetup;

/* How ATMO_PASS_CLOUDS draws. */
typedef enum AtmoCloudDrawMode {
  /* The default: impostors where they are both cheaper and closer to the reference (a field of at most
     ATMO_CLOUD_AUTO_IMPOSTOR_CLOUDS clouds, no procedural layer wider than ATMO_CLOUD_AUTO_IMPOSTOR_AREA_M),
     else the layer march, whose cost does not grow with the clouds (docs/CLOUDS.md, "Which draw mode").
     Before this value existed 0 meant ATMO_CLOUD_DRAW_IMPOSTORS: such a host gets the same frames for a
     field impostors can draw, and the layer march for weather at scale (impostors: 41 s a frame for 17 682
     clouds at 1280x720 here). */
  ATMO_CLOUD_DRAW_AUTO = 0,
  ATMO_CLOUD_DRAW_DIRECT = 1,    /* the direct march for every cloud (the reference; slow) */
  ATMO_CLOUD_DRAW_LAYER = 2,     /* one march per pixel through every cloud, over a clipmap of the field around
                                    the eye: cost bounded by pixels x steps, not by the number of clouds
                                    (docs/CLOUDS.md, "The layer march") */
  ATMO_CLOUD_DRAW_IMPOSTORS = 3, /* impostors, the direct march near and inside clouds, cross-faded: cost grows
                                    with the clouds in view */
  ATMO_CLOUD_DRAW_MODE_COUNT = 4
} AtmoCloudDrawMode;

/* ATMO_CLOUD_DRAW_AUTO's bounds for impostors. */
#define ATMO_CLOUD_AUTO_IMPOSTOR_CLOUDS 1000u
#define ATMO_CLOUD_AUTO_IMPOSTOR_AREA_M 20000.0

/* The clouds' shadow on the ground, for the host's terrain shading: sample it
   with atmo_cloud_shadow() from atmo_cloud_shadow.glsl. The map holds the
   clouds' direct transmittance towards the light (Sun or Moon) from the
   clouds' ground plane (their origin's height); a position is slid along the
   light onto that plane, so terrain at any height is shadowed by the clouds
   above it (an object above the clouds is shadowed as if below them). */
typedef struct AtmoCloudShadows {
  AtmoStructHeader header;     /* ATMO_TYPE_CLOUD_SHADOWS; the host sets header, the plugin fills the rest */
  uint32_t texture;            /* GL_TEXTURE_2D, R16F, linear filtering, clamped; 1 = no cloud. 0 when there
                                  are no clouds. Owned by the plugin: valid until the next set_clouds,
                                  gl_shutdown or gl_context_lost; the host must not change it */
  uint32_t size;               /* texels per side */
  double uv_from_world[16];    /* column-major 4x4: (u, v) = (M * (world_position, 1)).xy, world_position in
                                  the view's world frame (AtmoViewState.world_frame); outside [0, 1]^2 no shadow */
  double light_direction_world[3]; /* unit, towards the light the map was made for, world axes */
  double texel_m;              /* texel edge on the ground plane, m */
} AtmoCloudShadows;

/* ------------------------------------------------------------------------ */
/* Fog and the host's lights                                                 */
/* ------------------------------------------------------------------------ */

/* How the fog scatters (docs/FOG.md charts each choice's error). */
typedef enum AtmoFogScattering {
  /* Single scattering (Sun et al. 2005, in a stable form) handing over to a
     diffusion term for multiple scattering as the fog thickens. The default. */
  ATMO_FOG_SCATTERING_AUTO = 0,
  /* Single scattering only (the paper's model): right to ~10 % up to optical
     thickness ~1, too dark beyond. */
  ATMO_FOG_SCATTERING_SINGLE = 1,
  ATMO_FOG_SCATTERING_COUNT = 2
} AtmoFogScattering;

/* A homogeneous fog layer on the ground: from below the terrain up to
   top_height_m. Zero fields take the defaults given; all zero: no fog. */
typedef struct AtmoFogState {
  AtmoStructHeader header;      /* ATMO_TYPE_FOG_STATE */
  /* Meteorological optical range in the fog, m: extinction = ln(20) / MOR, as
     AtmoAtmosphereState.visibility_m (the same 5 % contrast threshold).
     [10, 100 000]. 0: use extinction_per_m. */
  double visibility_m;
  double extinction_per_m;      /* used when visibility_m is 0: [0, 1]; 0 (both 0): no fog */
  /* Height of the fog's top above the WGS84 ellipsoid, m; 0: no top (the fog
     fills the air everywhere). [-500, 20 000]. Heights of lights and surfaces
     are taken in the tangent plane at the eye (good to ~2 m at 5 km). */
  double top_height_m;
  /* Henyey-Greenstein asymmetry of the droplets' phase function. 0: default
     0.85 (radiation fog, ~10 um droplets). [-0.95, 0.95]; for isotropic
     scattering give a tiny value such as 1e-6. */
  double phase_asymmetry;
  /* Single-scattering albedo. 0: default 0.999 (water). (0, 1]. */
  double single_scattering_albedo;
  uint32_t scattering;          /* AtmoFogScattering */
  /* Lookup-table side for the airlight special function, [8, 512]; 0: default 64. */
  uint32_t airlight_table_size;
} AtmoFogState;

/* The most lights a context holds, all groups together, and the group numbers. */
#define ATMO_LIGHTS_MAX 65536u
#define ATMO_LIGHT_GROUPS_MAX 4096u

/* AtmoLightPoint.flags */
typedef enum AtmoLightFlags {
  /* The cone shines both ways along its axis (a runway edge light seen from
     either end); needs cone_outer_rad <= pi/2. */
  ATMO_LIGHT_BIDIRECTIONAL = 1u
} AtmoLightFlags;

/* One light of the host's (an approach light, a street lamp, a headlight). */
typedef struct AtmoLightPoint {
  double position_m[3];         /* in the lights' world frame (AtmoLightsState.world_frame), metres, each [-1e9, 1e9] */
  double intensity_cd;          /* luminous intensity on the axis, cd, [0, 1e8] */
  double color[3];              /* linear Rec.709 RGB multiplier of the intensity, each [0, 16] */
  /* Cone (headlights, beamed runway lights): the intensity is
     intensity_cd * smoothstep(cos(outer), cos(inner), cos(angle to the axis)).
     cone_outer_rad = 0: omnidirectional (axis and inner ignored).
     Otherwise 0 <= inner < outer <= pi and the axis is a non-zero vector. */
  double direction[3];          /* cone axis, world axes; need not be unit */
  double cone_inner_rad;
  double cone_outer_rad;
  /* --- Grew after the 96-byte layout (light_size 96 reads these as 0) --- */
  uint32_t flags;               /* AtmoLightFlags */
  uint32_t reserved;            /* 0 */
} AtmoLightPoint;

/* The lights of one group (set_lights replaces one group's lights). A group
   is the host's unit of change: an airport's edge lights, a town, a vehicle's
   lights. A group's lights are given in its own frame: world = the group's
   pose (set_light_group_pose; identity until set) times the position. */
typedef struct AtmoLightsState {
  AtmoStructHeader header;      /* ATMO_TYPE_LIGHTS_STATE */
  uint32_t world_frame;         /* AtmoWorldFrame of the positions and axes (after the group's pose) */
  /* sizeof(AtmoLightPoint) as the host compiled it: the lights' stride
     (ARRAYS above); 0: 96 (version 1). */
  uint32_t light_size;
  double world_origin_geodetic[3]; /* ATMO_WORLD_ENU: the frame's origin (lat deg, lon deg, h m) */
  const AtmoLightPoint* lights; /* light_count entries, light_size bytes apart; copied */
  /* [0, ATMO_LIGHTS_MAX]; 0 empties the group. All groups together hold at
     most ATMO_LIGHTS_MAX lights (a call that would pass it is refused). */
  uint32_t light_count;
  uint32_t reserved;            /* 0 */
  /* Glows dimmer than this are not drawn (each light's glow is drawn only
     where it may exceed it: docs/FOG.md), cd/m^2. 0: default, 1/2000 of the
     view's white (1 / exposure_scale). Context-wide: the last set_lights sets it. */
  double glow_threshold_cd_m2;
  /* --- Grew after the 72-byte layout (such a host replaces group 0 and gets the defaults) --- */
  uint32_t group;               /* the group these lights replace, [0, ATMO_LIGHT_GROUPS_MAX) */
  uint32_t reserved2;           /* 0 */
  /* The eye's threshold illuminance (Allard's law), lux: a light point whose
     illuminance at the eye is below it is not drawn (ATMO_PASS_LIGHT_POINTS).
     0: default, from the luminance B of the sky behind the lights, the
     ICAO classes (night B <= 50 cd/m^2: 8e-7 lx; 1e-5 lx at 1 000 cd/m^2;
     1e-4 lx at 12 000; 1e-3 lx in sunlit fog) joined log-linearly
     (docs/FOG.md). [0, 1]. Context-wide: the last set_lights sets it. */
  double visual_threshold_lux;
} AtmoLightsState;

/* Moves a whole group (a vehicle's lights) without re-sending them: its
   lights' world positions and axes become world_from_group times what
   set_lights gave. */
typedef struct AtmoLightGroupPose {
  AtmoStructHeader header;      /* ATMO_TYPE_LIGHT_GROUP_POSE */
  uint32_t group;               /* a group set_lights filled */
  uint32_t reserved;            /* 0 */
  /* Column-major 4x4, rigid: the upper 3x3 a rotation (to 1e-3, det > 0), the
     bottom row (0, 0, 0, 1), the translation within [-1e9, 1e9] m; in the
     group's world frame (AtmoLightsState.world_frame). */
  double world_from_group[16];
} AtmoLightGroupPose;

/* Replaces some lights of a group in place (lights that move each frame). */
typedef struct AtmoLightsUpdate {
  AtmoStructHeader header;      /* ATMO_TYPE_LIGHTS_UPDATE */
  uint32_t group;               /* a group set_lights filled */
  uint32_t first;               /* the group's first light to replace */
  const AtmoLightPoint* lights; /* light_count entries, light_size bytes apart; copied */
  uint32_t light_count;         /* [first, first + light_count) must lie within the group */
  uint32_t light_size;          /* the stride, as AtmoLightsState.light_size */
} AtmoLightsUpdate;

/* What a host's surface shader needs for atmo_fog_lights.glsl (its header
   says how to bind each field). Filled by get_fog_lighting. */
typedef struct AtmoFogLighting {
  AtmoStructHeader header;      /* ATMO_TYPE_FOG_LIGHTING; the host sets header, the plugin fills the rest */
  /* Lights in light_texture; 0 without lights (then skip the include), and for a host with the 136-byte
     layout (its include predates the clusters: update host_sdk/include/atmo/atmo_fog_lights.glsl) */
  uint32_t light_count;
  uint32_t light_texture;       /* GL_TEXTURE_2D RGBA32F: the clusters' lights, 3 texels each, 1024 a row
                                   (positions relative to this view's eye in its world axes; valid until the
                                   next get_fog_lighting) */
  uint32_t surface_table;       /* GL_TEXTURE_2D R32F, GL_LINEAR */
  uint32_t reserved;
  double surface_table_size[2]; /* for atmo_fog_surface_table_size */
  double medium[4];             /* for atmo_fog_medium: extinction 1/m, albedo, fog top above the eye m, 0 */
  double diffusion[4];          /* for atmo_fog_diffusion */
  double up_world[3];           /* for atmo_fog_up */
  /* --- Grew after the 136-byte layout: the clusters (docs/FOG.md "Surfaces at scale") --- */
  uint32_t cluster_grid;        /* GL_TEXTURE_2D RG32UI: per cluster its first light in light_texture and count */
  uint32_t reserved3;           /* 0 */
  uint32_t far_field;           /* GL_TEXTURE_3D RGBA32F, linear: per cluster the far field's irradiance on the
                                   faces +E, -E, +N, -N, +U, -U (lux), six stacks of the slices */
  uint32_t reserved2;
  double cluster_from_position[16]; /* for atmo_fog_cluster_from_position (column-major) */
  double cluster_grid_size[4];  /* for atmo_fog_cluster_grid_size */
  double cluster_range[2];      /* for atmo_fog_cluster_range */
  double enu_from_world[9];     /* for atmo_fog_enu_from_world (column-major 3x3: the eye's ENU axes) */
  /* --- Grew after the clusters: the fog and glows in front of the host's translucent surfaces
     (atmo_fog_translucent; docs/FOG.md "Translucent surfaces"). The glow textures hold what the view's
     last ATMO_PASS_LIGHT_GLOWS drew: draw a view's translucent surfaces after its glow pass. --- */
  uint32_t airlight_table;      /* GL_TEXTURE_2D R32F, linear: for atmo_fog_airlight_table */
  uint32_t glow_tiles;          /* GL_TEXTURE_2D RGBA32UI: per screen tile its first glow in glow_lists, its count,
                                   how many of them are merged lights, 0 */
  uint32_t glow_lists;          /* GL_TEXTURE_2D R32UI: glows (indices into glow_entries), 4096 a row */
  uint32_t glow_entries;        /* GL_TEXTURE_2D RGBA32F: 4 texels a glow, 256 a row (ENU relative to the eye) */
  double glow_grid[4];          /* for atmo_fog_glow_grid: tiles across, tiles up, airlight table size, the
                                   pixel's floor of sin gamma */
  double ambient[3];            /* for atmo_fog_ambient: the sky's, Sun's and Moon's light the fog scatters,
                                   cd/m^2 (isotropic) */
  double fluence[3];            /* for atmo_fog_fluence: the lights' diffusion fluence at the eye */
  double flux[9];               /* for atmo_fog_flux (column-major 3x3; column c: channel c's flux towards the
                                   lights, ENU) */
} AtmoFogLighting;

/* ------------------------------------------------------------------------ */
/* The host's objects as occluders of the sky (docs/SKY_OCCLUSION.md)        */
/* ------------------------------------------------------------------------ */

/* The most objects a context holds, spheres an object holds, and spheres in all. */
#define ATMO_OCCLUDER_OBJECTS_MAX 4096u
#define ATMO_OCCLUDER_SPHERES_MAX 1024u
#define ATMO_OCCLUDER_SPHERES_TOTAL_MAX 65536u

/* One sphere of an object, in the object's own frame (metres). `atmo spheres MESH -n K` fits them to a
   mesh; they should hold the object (a receiver inside one of its object's spheres is not shadowed by it). */
typedef struct AtmoOccluderSphere {
  double centre_m[3];           /* each [-1e5, 1e5] */
  double radius_m;              /* [0, 1e5]; 0: ignored */
} AtmoOccluderSphere;

/* One object (an aircraft, a vehicle, a hangar): its spheres and how it reflects the sky. */
typedef struct AtmoOccluderObject {
  const AtmoOccluderSphere* spheres; /* sphere_count entries, sphere_size bytes apart; copied */
  uint32_t sphere_count;        /* [0, ATMO_OCCLUDER_SPHERES_MAX] */
  uint32_t sphere_size;         /* sizeof(AtmoOccluderSphere) as the host compiled it; 0: 32 */
  double albedo[3];             /* diffuse reflectance, linear RGB, each [0, 1] (the bounce) */
  /* Column-major 4x4, rigid (a rotation to 1e-3, det > 0, bottom row 0 0 0 1, translation within
     [-1e9, 1e9] m): the object's frame to the occluders' world frame. set_occluder_poses moves it. */
  double world_from_object[16];
} AtmoOccluderObject;

/* AtmoOccludersState.flags */
typedef enum AtmoOcclusionFlags {
  ATMO_OCCLUSION_NO_BOUNCE = 1u,      /* no light reflected by the objects (bounce_lux 0; cheaper) */
  ATMO_OCCLUSION_OPTIMAL_LINEAR = 2u  /* the optimal-linear exponential alone (cheaper, brighter under large
                                         objects) instead of the hybrid (docs/SKY_OCCLUSION.md) */
} AtmoOcclusionFlags;

/* Replaces every object (set_occluders). */
typedef struct AtmoOccludersState {
  AtmoStructHeader header;      /* ATMO_TYPE_OCCLUDERS_STATE */
  uint32_t world_frame;         /* AtmoWorldFrame of the poses */
  uint32_t object_size;         /* sizeof(AtmoOccluderObject) as the host compiled it; 0: 168 */
  double world_origin_geodetic[3]; /* ATMO_WORLD_ENU: the frame's origin (lat deg, lon deg, h m) */
  const AtmoOccluderObject* objects; /* object_count entries, object_size bytes apart; copied */
  uint32_t object_count;        /* [0, ATMO_OCCLUDER_OBJECTS_MAX]; 0: no occluders */
  uint32_t flags;               /* AtmoOcclusionFlags */
} AtmoOccludersState;

/* Moves objects [first, first + count) without re-sending their spheres: one column-major rigid 4x4 each,
   16 doubles apart (as AtmoOccluderObject.world_from_object). */
typedef struct AtmoOccluderPoses {
  AtmoStructHeader header;      /* ATMO_TYPE_OCCLUDER_POSES */
  uint32_t first;
  uint32_t count;
  const double* world_from_object; /* count x 16 doubles */
} AtmoOccluderPoses;

/* What a host's surface shader needs for atmo_sky_occlusion.glsl (its header says how to bind each field;
   docs/SKY_OCCLUSION.md). Filled by get_sky_occlusion; the textures are valid until the next
   get_sky_occlusion, gl_shutdown or gl_context_lost. */
typedef struct AtmoSkyOcclusion {
  AtmoStructHeader header;      /* ATMO_TYPE_SKY_OCCLUSION; the host sets header, the plugin fills the rest */
  uint32_t object_count;        /* 0: no occluders (shade with get_lighting's SH9; the textures are 0) */
  uint32_t tables;              /* GL_TEXTURE_2D RGBA32F 256 x 3, linear: atmo_occ_tables */
  uint32_t spheres;             /* GL_TEXTURE_2D RGBA32F: atmo_occ_spheres */
  uint32_t objects;             /* GL_TEXTURE_2D RGBA32F: atmo_occ_objects */
  uint32_t tiles;               /* GL_TEXTURE_2D RG32UI: atmo_occ_tiles */
  uint32_t tile_objects;        /* GL_TEXTURE_2D R32UI: atmo_occ_tile_objects */
  double tile_from_position[16];/* atmo_occ_tile_from_position (column-major) */
  double enu_from_world[9];     /* atmo_occ_enu_from_world (column-major) */
  double grid[4];               /* atmo_occ_grid */
  double limits[4];             /* atmo_occ_limits */
  double sun[4];                /* atmo_occ_sun */
  double sun_lux[3];            /* atmo_occ_sun_lux */
  uint32_t longest_tile_list;   /* the most objects a tile lists (the cost's bound) */
  uint32_t reserved;
  float sky_sh9[27];            /* atmo_occ_sky_sh9 (9 vec3) */
  float sun_sh9[27];            /* atmo_occ_sun_sh9 (9 vec3) */
  float transfer[432];          /* atmo_occ_transfer (108 vec4) */
  /* Grown (a host compiled before has a smaller struct, left unfilled here): the image of this view's
     ATMO_PASS_SKY_OCCLUSION with ATMO_PASS_SKY_OCCLUSION_IMAGE drawn after its last set_view (0 when none
     was), for the include compiled with ATMO_OCC_IMAGE, which reads these, enu_from_world and sky_sh9 only.
     Valid until that view's next image pass. */
  uint32_t image[3];            /* GL_TEXTURE_2D RGBA32F, linear: atmo_occ_image0, 1, 2 */
  uint32_t image_reduction;     /* pixels a texel spans across (4, 8 or 16) */
  double image_map[4];          /* atmo_occ_image_map */
} AtmoSkyOcclusion;

/* ------------------------------------------------------------------------ */
/* Several channels: the state hash (docs/MULTI_CHANNEL.md)                  */
/* ------------------------------------------------------------------------ */

/* What a frame shows is a function of the context's inputs (every set_* call), the frame state
   (set_frame: time, host_frame_number) and the view's state, never of the wall clock, of thread timing or
   of the order in which views are drawn: work done off the host's thread (new atmosphere tables, the
   clouds' lighting) takes effect at a frame fixed when it was asked for, host_frame_number +
   AtmoFrameState.deferred_frames (default ATMO_DEFERRED_FRAMES), on every channel alike (the frame that
   reaches it first waits for the work). */
#define ATMO_DEFERRED_FRAMES 8u

/* The parts of AtmoStateHash.parts (which one differs tells what two channels disagree on). */
typedef enum AtmoStateHashPart {
  ATMO_STATE_HASH_FRAME = 0,     /* set_frame: time, UT1 - UTC, host_frame_number */
  ATMO_STATE_HASH_AIR = 1,       /* set_atmosphere, and the air the tables in use were made for */
  ATMO_STATE_HASH_CLOUDS = 2,    /* set_clouds' layers, and the light they are lit with now */
  ATMO_STATE_HASH_FOG = 3,       /* set_fog */
  ATMO_STATE_HASH_LIGHTS = 4,    /* set_lights, update_lights, set_light_group_pose */
  ATMO_STATE_HASH_OCCLUDERS = 5, /* set_occluders, set_occluder_poses */
  ATMO_STATE_HASH_VIEW = 6,      /* this view's set_view (differs between channels by design: not in `hash`) */
  ATMO_STATE_HASH_PART_COUNT = 7
} AtmoStateHashPart;

/* A 64-bit hash of everything that changes a frame's pixels (get_state_hash), for channels, and tests, to
   check they agree: equal hashes, equal pictures of equal views. */
typedef struct AtmoStateHash {
  AtmoStructHeader header;      /* ATMO_TYPE_STATE_HASH; the host sets header, the plugin fills the rest */
  uint64_t host_frame_number;   /* the frame it was taken at (set_frame's) */
  uint64_t hash;                /* parts FRAME .. OCCLUDERS combined: what every channel must share */
  uint64_t parts[8];            /* by AtmoStateHashPart; the rest 0 */
} AtmoStateHash;

/* ------------------------------------------------------------------------ */
/* Lighting for the host's own shading                                       */
/* ------------------------------------------------------------------------ */

typedef struct AtmoLighting {
  AtmoStructHeader header;        /* ATMO_TYPE_LIGHTING; the host sets header, the plugin fills the rest */
  double sun_direction_ecef[3];   /* unit vector from the eye towards the sun */
  double sun_direction_enu[3];    /* the same in east-north-up at the eye */
  double sun_elevation_rad;       /* apparent (refracted) elevation above the horizontal plane */
  double sun_azimuth_rad;         /* from north, clockwise (east = pi/2) */
  double sun_illuminance_lux[3];  /* on a surface facing the sun at the eye, after the atmosphere and the clouds
                                     (set_clouds) between the eye and the sun, linear RGB */

  /* Sky light, the sun excluded (it is the light above), in ENU axes at the
     eye. These fields grew the struct after its first 104-byte layout: a host
     compiled with that layout still works and gets the fields above only. */
  /* Irradiance as 9 real spherical-harmonic coefficients (Ramamoorthi &
     Hanrahan 2001), lux, linear RGB: E(n) = sum_k sh9[k] * Y_k(n) for a unit
     normal n = (east, north, up), with Y_0 = 0.282095, Y_1..3 = 0.488603 (y, z, x),
     Y_4 = 1.092548 xy, Y_5 = 1.092548 yz, Y_6 = 0.315392 (3z^2 - 1),
     Y_7 = 1.092548 xz, Y_8 = 0.546274 (x^2 - y^2). Includes the ground seen
     below the horizon. Error: <= 6 % of the largest irradiance (docs/SKY.md). */
  double sky_irradiance_sh9[9][3];
  double sky_illuminance_horizontal_lux[3]; /* on an upward-facing surface (direct quadrature, not the SH) */
  double sky_average_radiance[3];           /* cd/m^2, mean over the upper hemisphere: the sky's colour */

  /* Aerial perspective for the host's own transparent objects, with the GLSL
     include host_sdk/include/atmo/atmo_aerial_perspective.glsl: the GL names
     of the context's aerial-perspective volume (GL_TEXTURE_3D, RGBA32F;
     in-scattered light in cd/m^2, and transmittance), how far its last slice
     reaches (metres) and its slice count. The volume holds what the last
     render_pass(ATMO_PASS_AERIAL_PERSPECTIVE) on this context built (call it
     for this view first; the names stay valid until gl_shutdown). Names are 0
     with the MARCH method or before any such pass. */
  uint32_t aerial_inscatter_texture;
  uint32_t aerial_transmittance_texture;
  double aerial_range_m;
  uint32_t aerial_slices;
  uint32_t reserved;

  /* The Moon as a light (added with the night sky; a host compiled with the
     392-byte layout gets the fields above only). Positions from the
     ephemeris (ELP 2000-82B, topocentric, refracted as seen; docs/EPHEMERIS.md),
     the light from the measured phase law (Krisciunas & Schaefer 1991) plus
     earthshine (docs/NIGHT_SKY.md). */
  double moon_direction_ecef[3];    /* unit vector from the eye towards the Moon */
  double moon_direction_enu[3];
  double moon_elevation_rad;        /* apparent (refracted) elevation */
  double moon_azimuth_rad;          /* from north, clockwise */
  double moon_illuminance_lux[3];   /* on a surface facing the Moon at the eye, after the atmosphere and the
                                       clouds between, linear RGB;
                                       0 when the Moon is below the horizon */
  double moon_illuminated_fraction; /* 0 new .. 1 full */
  double moon_phase_angle_rad;      /* Sun-Moon-eye angle: 0 full, pi new */
  /* The sun's elevation above is apparent (refracted) too, as the sky is drawn. */
} AtmoLighting;

/* ------------------------------------------------------------------------ */
/* Negotiation and the function table                                        */
/* ------------------------------------------------------------------------ */

typedef struct AtmoNegotiateInfo {
  AtmoStructHeader header;          /* ATMO_TYPE_NEGOTIATE_INFO */
  uint32_t min_interface_version;   /* the oldest the host can use, >= 1 */
  uint32_t max_interface_version;   /* the newest the host can use, >= min */
  const char* host_name;            /* for logs; may be NULL */
  uint32_t host_version;
  uint32_t reserved;
} AtmoNegotiateInfo;

typedef struct AtmoPluginApi {
  AtmoStructHeader header;   /* ATMO_TYPE_PLUGIN_API; host sets struct_size to the size it can take */
  uint32_t interface_version; /* written by the plugin: the version chosen */
  uint32_t plugin_version;   /* written by the plugin: (major << 16) | (minor << 8) | patch */
  const char* plugin_name;   /* written by the plugin; static string */

  /* Name of any result code; a static string, never NULL. [any-thread] */
  const char* (*result_string)(AtmoResult result);

  /* Detailed message of the last error on this context (what failed and where);
     "" if none. Valid until the next call on the context. [ctx-sync][no-gl] */
  const char* (*last_error)(AtmoContext context);

  /* Creates a context. On failure *out_context is NULL. [any-thread][no-gl] */
  AtmoResult (*create_context)(const AtmoContextCreateInfo* info, AtmoContext* out_context);
  /* Destroys a context and any views it still has. Call gl_shutdown (or
     gl_context_lost) first; if GL objects are still alive they are leaked, not
     deleted, and a HOST_MISBEHAVING message is logged. NULL is ignored. [ctx-sync][no-gl] */
  void (*destroy_context)(AtmoContext context);

  /* Loads GL entry points and creates the plugin's GL objects in the current
     context. Idempotent: a second call with objects alive returns ATMO_SUCCESS. [ctx-sync][gl-current] */
  AtmoResult (*gl_init)(AtmoContext context);
  /* Deletes the plugin's GL objects. Idempotent. [ctx-sync][gl-current] */
  AtmoResult (*gl_shutdown)(AtmoContext context);
  /* The GL context is gone: forget GL objects without calling GL. gl_init may
     follow on a new context. Idempotent. [ctx-sync][no-gl] */
  AtmoResult (*gl_context_lost)(AtmoContext context);

  /* Views: one per channel / eye. destroy_view(NULL) is ignored. [ctx-sync][no-gl] */
  AtmoResult (*create_view)(AtmoContext context, const AtmoViewCreateInfo* info, AtmoView* out_view);
  void (*destroy_view)(AtmoView view);

  /* World state; each validated whole, and on error nothing changes. [ctx-sync][no-gl] */
  AtmoResult (*set_atmosphere)(AtmoContext context, const AtmoAtmosphereState* state);
  AtmoResult (*set_frame)(AtmoContext context, const AtmoFrameState* state);
  AtmoResult (*set_view)(AtmoView view, const AtmoViewState* state);

  /* Draws one pass of a view into the bound framebuffer. Needs gl_init,
     set_frame and set_view first (else ATMO_ERROR_CALL_OUT_OF_ORDER).
     Returns ATMO_STATUS_NOTHING_TO_DRAW when nothing was visible (no GL work). [ctx-sync][gl-current] */
  AtmoResult (*render_pass)(AtmoView view, const AtmoPassInfo* pass);

  /* Sun light at the view's eye for the host's shading. Needs set_frame and set_view. [ctx-sync][no-gl] */
  AtmoResult (*get_lighting)(AtmoView view, AtmoLighting* out_lighting);

  /* --- Added after the first table (a host whose struct_size ends above gets
     NULL here and has no clouds) --- */
  /* Replaces the clouds. Generates procedural layers and reads VDB files on
     the calling thread: seconds for large layers, so call it when a scenario
     or the weather changes, not every frame. All or nothing, like every
     call: invalid fields in any layer (bad enum, NaN, out of range) or a
     layer whose file fails (missing, corrupt, empty or wrong-typed) reject
     the whole call and the clouds are unchanged. Every file is still tried:
     each failure is logged, last_error names the first, and the result is
     ATMO_ERROR_IO (a file) or the validation error.
     The clouds are lit on the first cloud pass (ATMO_CLOUD_DRAW_LAYER with
     ATMO_CLOUD_SETUP_STREAM, the default there: a half-resolution draft at
     once, the full lighting on a worker, AtmoCloudSetup); when the light
     later moves past light_update_threshold_deg they are relit on a worker
     thread the plugin owns (it never calls the host), and passes keep
     drawing with the old light until it ends. [ctx-sync][no-gl] */
  AtmoResult (*set_clouds)(AtmoContext context, const AtmoCloudsState* state);

  /* The clouds' shadow map for this view's world frame. Needs gl_init,
     set_frame and set_view. The first call after set_clouds makes the map on
     the calling thread (up to ~1 s for a large deck at low sun); from then on
     it is remade with the clouds' light, on the relight worker. Without
     clouds: ATMO_STATUS_NOTHING_TO_DRAW and texture 0. NULL in a table from
     a plugin that predates it. [ctx-sync][gl-current] */
  AtmoResult (*get_cloud_shadows)(AtmoView view, AtmoCloudShadows* out_shadows);

  /* --- Added with fog (a host whose table ends above gets NULL here) --- */
  /* Sets the fog; NULL or all-zero extinction: no fog. Builds the fog's
     lookup tables on the calling thread (~0.1-0.5 s when the phase function
     changes; the same phase reuses them). On error the fog is unchanged. [ctx-sync][no-gl] */
  AtmoResult (*set_fog)(AtmoContext context, const AtmoFogState* state);
  /* Replaces one group's lights (copied; AtmoLightsState.group, 0 for a host
     that has one set of lights); NULL: no lights in any group. On error the
     lights are unchanged, and the message names the bad light's index.
     65 536 lights take < 10 ms. [ctx-sync][no-gl] */
  AtmoResult (*set_lights)(AtmoContext context, const AtmoLightsState* state);
  /* The lights' lighting for the host's surface shaders this frame, in fog
     or clear air (uploads the lights relative to this view's eye and their
     clusters). Needs gl_init, set_frame and set_view. Without lights:
     ATMO_STATUS_NOTHING_TO_DRAW and light_count 0. [ctx-sync][gl-current] */
  AtmoResult (*get_fog_lighting)(AtmoView view, AtmoFogLighting* out_lighting);

  /* --- Added with light groups (a host whose table ends above gets NULL here) --- */
  /* Moves a group (AtmoLightGroupPose). A group set_lights never filled is
     ATMO_ERROR_OUT_OF_RANGE. [ctx-sync][no-gl] */
  AtmoResult (*set_light_group_pose)(AtmoContext context, const AtmoLightGroupPose* pose);
  /* Replaces lights [first, first + count) of a group (AtmoLightsUpdate); on
     error nothing changes and the message names the bad light's index.
     1 000 lights take < 1 ms. [ctx-sync][no-gl] */
  AtmoResult (*update_lights)(AtmoContext context, const AtmoLightsUpdate* update);

  /* --- Added with sky occlusion (a host whose table ends above gets NULL here) --- */
  /* Replaces the occluding objects (AtmoOccludersState; NULL or object_count 0: none). Copies the
     spheres and prepares each object's bound and far stand-in (~1 ms an object of 32 spheres). On error
     nothing changes and the message names the object's and the sphere's index. [ctx-sync][no-gl] */
  AtmoResult (*set_occluders)(AtmoContext context, const AtmoOccludersState* state);
  /* Moves objects (AtmoOccluderPoses); 16 objects take microseconds. On error nothing moves. [ctx-sync][no-gl] */
  AtmoResult (*set_occluder_poses)(AtmoContext context, const AtmoOccluderPoses* poses);
  /* The objects' sky occlusion for the host's surface shaders this frame (uploads them relative to this
     view's eye, and per screen tile the objects near enough to shade). Needs gl_init, set_frame and
     set_view. Without objects: ATMO_STATUS_NOTHING_TO_DRAW and object_count 0. [ctx-sync][gl-current] */
  AtmoResult (*get_sky_occlusion)(AtmoView view, AtmoSkyOcclusion* out_occlusion);

  /* --- Added with several channels (a host whose table ends above gets NULL here) --- */
  /* The state this view's next pass would draw from, hashed (AtmoStateHash): call it after set_frame and
     set_view, on every channel, and compare `hash` (docs/MULTI_CHANNEL.md). It settles what takes effect
     this frame (deferred work whose frame has come: it may wait for it), as the first pass would.
     [ctx-sync][no-gl] */
  AtmoResult (*get_state_hash)(AtmoView view, AtmoStateHash* out_hash);
} AtmoPluginApi;

/* The one exported entry point. The host fills `host` and sets
   api->header = ATMO_HEADER(ATMO_TYPE_PLUGIN_API, AtmoPluginApi); the plugin
   picks the highest interface version in [min, max] it implements and fills
   api up to min(api->header.struct_size, its own table size). Returns
   ATMO_ERROR_INCOMPATIBLE_VERSION (api untouched past its header) when the
   ranges do not overlap. [any-thread][no-gl] */
typedef AtmoResult (*PFN_atmo_negotiate)(const AtmoNegotiateInfo* host, AtmoPluginApi* api);

#if defined(ATMO_BUILDING_PLUGIN)
#  define ATMO_EXPORT __attribute__((visibility("default")))
#else
#  define ATMO_EXPORT
#endif

ATMO_EXPORT AtmoResult atmo_negotiate(const AtmoNegotiateInfo* host, AtmoPluginApi* api);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* ATMO_ATMO_H */
