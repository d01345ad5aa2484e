#include "atmo_support/image.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>

#include <glm/glm.hpp>

// The plugin's tone map (host_sdk/include/atmo/atmo_tone_map.glsl) as C++ over GLM.
namespace atmo::support::tone_twin {
using namespace glm;
#define ATMO_TONE_FN inline
#include "atmo/atmo_tone_map.glsl"
#undef ATMO_TONE_FN
}  // namespace atmo::support::tone_twin

namespace atmo::support {

Image make_image(int width, int height, float r, float g, float b, float a) {
  Image img;
  img.width = std::max(width, 0);
  img.height = std::max(height, 0);
  img.rgba.resize(img.pixel_count() * 4);
  for (size_t i = 0; i < img.pixel_count(); ++i) {
    img.rgba[i * 4 + 0] = r;
    img.rgba[i * 4 + 1] = g;
    img.rgba[i * 4 + 2] = b;
    img.rgba[i * 4 + 3] = a;
  }
  return img;
}

namespace {

bool set_error(std::string* error, const std::string& msg) {
  if (error) *error = msg;
  return false;
}

bool valid_layout(const Image& image, const std::string& path, std::string* error) {
  if (image.width <= 0 || image.height <= 0)
    return set_error(error, path + ": cannot write an empty image");
  if (image.rgba.size() != image.pixel_count() * 4)
    return set_error(error, path + ": image has " + std::to_string(image.rgba.size()) + " floats, expected " +
                                std::to_string(image.pixel_count() * 4));
  return true;
}

// Guards against absurd sizes in corrupt headers before allocating.
constexpr long long kMaxPixels = 1ll << 28;

}  // namespace

bool write_exr(const std::string& path, const Image& image, std::string* error) {
  if (!valid_layout(image, path, error)) return false;
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    const char* names[4] = {"R", "G", "B", "A"};
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgba.data()));
    const size_t xs = 4 * sizeof(float), ys = xs * static_cast<size_t>(image.width);
    for (int c = 0; c < 4; ++c) {
      header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    return set_error(error, path + ": cannot write EXR: " + e.what());
  }
  return true;
}

bool read_exr(const std::string& path, Image* out, std::string* error) {
  if (!out) return set_error(error, "read_exr: out is null");
  if (!std::ifstream(path, std::ios::binary)) return set_error(error, path + ": cannot open file");
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const long long w = static_cast<long long>(dw.max.x) - dw.min.x + 1;
    const long long h = static_cast<long long>(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > kMaxPixels)
      return set_error(error, path + ": EXR data window " + std::to_string(w) + "x" + std::to_string(h) +
                                  " is empty or too large");
    if (!file.isComplete())
      return set_error(error, path + ": EXR file is incomplete (truncated or still being written)");

    Image img;
    img.width = static_cast<int>(w);
    img.height = static_cast<int>(h);
    img.rgba.assign(img.pixel_count() * 4, 0.0f);
    const char* names[4] = {"R", "G", "B", "A"};
    const double fill[4] = {0.0, 0.0, 0.0, 1.0};
    Imf::FrameBuffer fb;
    const size_t xs = 4 * sizeof(float), ys = xs * static_cast<size_t>(w);
    for (int c = 0; c < 4; ++c) {
      fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, img.rgba.data() + c, dw, xs, ys, 1, 1, fill[c]));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    *out = std::move(img);
  } catch (const std::exception& e) {
    return set_error(error, path + ": cannot read EXR: " + e.what());
  }
  return true;
}

bool write_png(const std::string& path, const Image& display_referred, std::string* error) {
  if (!valid_layout(display_referred, path, error)) return false;
  std::vector<png_byte> bytes(display_referred.pixel_count() * 4);
  for (size_t i = 0; i < bytes.size(); ++i) {
    float v = display_referred.rgba[i];
    if (i % 4 == 3) {
      bytes[i] = 255;
      continue;
    }
    v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
    bytes[i] = static_cast<png_byte>(std::lround(v * 255.0f));
  }
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  img.width = static_cast<png_uint_32>(display_referred.width);
  img.height = static_cast<png_uint_32>(display_referred.height);
  img.format = PNG_FORMAT_RGBA;
  if (!png_image_write_to_file(&img, path.c_str(), 0, bytes.data(), 0, nullptr)) {
    const std::string msg = img.message;
    png_image_free(&img);
    return set_error(error, path + ": cannot write PNG: " + msg);
  }
  return true;
}

bool read_png(const std::string& path, Image* out, std::string* error) {
  if (!out) return set_error(error, "read_png: out is null");
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str())) {
    const std::string msg = img.message;
    png_image_free(&img);
    return set_error(error, path + ": cannot read PNG: " + msg);
  }
  if (static_cast<long long>(img.width) * img.height > kMaxPixels) {
    png_image_free(&img);
    return set_error(error, path + ": PNG is too large");
  }
  img.format = PNG_FORMAT_RGBA;
  std::vector<png_byte> bytes(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, bytes.data(), 0, nullptr)) {
    const std::string msg = img.message;
    png_image_free(&img);
    return set_error(error, path + ": cannot read PNG: " + msg);
  }
  Image result;
  result.width = static_cast<int>(img.width);
  result.height = static_cast<int>(img.height);
  result.rgba.resize(result.pixel_count() * 4);
  for (size_t i = 0; i < result.rgba.size(); ++i) result.rgba[i] = bytes[i] / 255.0f;
  *out = std::move(result);
  return true;
}

float srgb_encode(float linear) {
  if (!(linear > 0.0f)) return 0.0f;  // also NaN
  return tone_twin::atmo_srgb_encode(glm::vec3(linear)).x;
}

float aces_filmic(float x) {
  if (std::isnan(x)) return x;
  return tone_twin::atmo_aces_filmic(glm::vec3(x)).x;
}

Image tone_map_to_display(const Image& linear_hdr, float exposure_scale) {
  Image out;
  out.width = linear_hdr.width;
  out.height = linear_hdr.height;
  out.rgba.resize(linear_hdr.rgba.size());
  for (size_t i = 0; i + 3 < linear_hdr.rgba.size(); i += 4) {
    for (int c = 0; c < 3; ++c) {
      const float x = linear_hdr.rgba[i + c] * exposure_scale;
      const float t = aces_filmic(x);
      out.rgba[i + c] = std::isnan(t) ? t : srgb_encode(t);
    }
    out.rgba[i + 3] = 1.0f;
  }
  return out;
}

}  // namespace atmo::support
