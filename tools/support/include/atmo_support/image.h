// Float RGBA images and their EXR/PNG files; tone mapping for previews.
#pragma once

#include <string>
#include <vector>

namespace atmo::support {

// Row 0 is the TOP of the image; rgba holds width*height*4 floats.
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgba;

  float* pixel(int x, int y) { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
  const float* pixel(int x, int y) const { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
  size_t pixel_count() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
};

// A width x height image filled with (r, g, b, a).
Image make_image(int width, int height, float r = 0.0f, float g = 0.0f, float b = 0.0f, float a = 1.0f);

// Linear scene-referred EXR, 32-bit float R,G,B,A (half would overflow at the
// sun's luminance, ~1.6e9 cd/m^2), ZIP compression.
bool write_exr(const std::string& path, const Image& image, std::string* error);
// Reads R,G,B,A of any pixel type as float; missing channels read 0 (A reads 1).
// A missing, truncated or corrupt file gives false and a message, never a crash.
bool read_exr(const std::string& path, Image* out, std::string* error);

// Values already display-encoded in [0,1] -> 8-bit RGBA with alpha 255; values
// are clamped, NaN writes 0.
bool write_png(const std::string& path, const Image& display_referred, std::string* error);
// Back to [0,1] floats (8-bit values / 255), no decoding of the transfer curve.
bool read_png(const std::string& path, Image* out, std::string* error);

// The plugin's display encoding, one source (host_sdk/include/atmo/atmo_tone_map.glsl):
// IEC 61966-2-1 sRGB transfer function; negative and NaN give 0.
float srgb_encode(float linear);
// The filmic curve of tone_map_to_display: ACES fitted by K. Narkowicz (2015),
// x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clamped to [0,1]; x <= 0 gives 0, NaN stays NaN.
float aces_filmic(float x);
// rgb * exposure_scale, then aces_filmic per channel, then srgb_encode; alpha 1.
// NaN stays NaN so a preview writer can flag it (write_png writes it as 0).
Image tone_map_to_display(const Image& linear_hdr, float exposure_scale);

}  // namespace atmo::support
