#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "atmo_support/image.h"

using namespace atmo::support;
namespace fs = std::filesystem;

namespace {

fs::path temp_path(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("atmo_support_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

Image gradient(int w, int h) {
  Image img = make_image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = img.pixel(x, y);
      p[0] = static_cast<float>(x) / w;
      p[1] = static_cast<float>(y) / h * 1.0e6f;  // HDR values survive float EXR
      p[2] = 0.001f * static_cast<float>(x + y);
      p[3] = 0.5f;
    }
  return img;
}

}  // namespace

TEST(Image, PixelAccessRowMajorTopFirst) {
  Image img = make_image(3, 2, 0.1f, 0.2f, 0.3f, 0.4f);
  ASSERT_EQ(img.rgba.size(), 24u);
  img.pixel(2, 1)[0] = 9.0f;
  EXPECT_EQ(img.rgba[(1 * 3 + 2) * 4], 9.0f);
  EXPECT_EQ(img.pixel(0, 0)[3], 0.4f);
}

TEST(Image, ExrRoundTrip) {
  const Image img = gradient(37, 21);
  const std::string path = temp_path("round.exr").string();
  std::string error;
  ASSERT_TRUE(write_exr(path, img, &error)) << error;
  Image back;
  ASSERT_TRUE(read_exr(path, &back, &error)) << error;
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 21);
  EXPECT_EQ(back.rgba, img.rgba);  // 32-bit float, lossless
}

TEST(Image, ExrMissingFileGivesError) {
  Image out;
  std::string error;
  EXPECT_FALSE(read_exr(temp_path("does_not_exist.exr").string(), &out, &error));
  EXPECT_NE(error.find("does_not_exist.exr"), std::string::npos) << error;
}

TEST(Image, ExrTruncatedFileGivesErrorNotCrash) {
  const Image img = gradient(128, 96);
  const fs::path path = temp_path("truncated.exr");
  std::string error;
  ASSERT_TRUE(write_exr(path.string(), img, &error)) << error;
  const auto size = fs::file_size(path);
  fs::resize_file(path, size / 2);
  Image out;
  error.clear();
  EXPECT_FALSE(read_exr(path.string(), &out, &error));
  EXPECT_FALSE(error.empty());
  std::printf("truncated EXR: %s\n", error.c_str());
  // Header only, and garbage.
  fs::resize_file(path, 20);
  EXPECT_FALSE(read_exr(path.string(), &out, &error));
  { std::ofstream(path, std::ios::binary) << "not an exr file at all"; }
  EXPECT_FALSE(read_exr(path.string(), &out, &error));
}

TEST(Image, ExrWriteErrors) {
  std::string error;
  EXPECT_FALSE(write_exr("/nonexistent_dir/x.exr", make_image(2, 2), &error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(write_exr(temp_path("empty.exr").string(), Image{}, &error));
}

TEST(Image, PngRoundTrip) {
  Image img = make_image(5, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) {
      float* p = img.pixel(x, y);
      p[0] = static_cast<float>(x * 51) / 255.0f;
      p[1] = static_cast<float>(y * 80) / 255.0f;
      p[2] = 1.5f;  // clamps to 1
      p[3] = 0.2f;  // alpha is written as 255
    }
  img.pixel(0, 0)[1] = std::numeric_limits<float>::quiet_NaN();  // written as 0
  img.pixel(1, 0)[1] = -3.0f;
  const std::string path = temp_path("round.png").string();
  std::string error;
  ASSERT_TRUE(write_png(path, img, &error)) << error;
  Image back;
  ASSERT_TRUE(read_png(path, &back, &error)) << error;
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) {
      const float* p = back.pixel(x, y);
      EXPECT_FLOAT_EQ(p[0], static_cast<float>(x * 51) / 255.0f);
      if (y > 0) {
        EXPECT_FLOAT_EQ(p[1], static_cast<float>(y * 80) / 255.0f);
      }
      EXPECT_EQ(p[2], 1.0f);
      EXPECT_EQ(p[3], 1.0f);
    }
  EXPECT_EQ(back.pixel(0, 0)[1], 0.0f);
  EXPECT_EQ(back.pixel(1, 0)[1], 0.0f);
  EXPECT_FALSE(read_png(temp_path("missing.png").string(), &back, &error));
  EXPECT_FALSE(error.empty());
}

TEST(Image, SrgbEncode) {
  EXPECT_EQ(srgb_encode(0.0f), 0.0f);
  EXPECT_EQ(srgb_encode(-1.0f), 0.0f);
  EXPECT_EQ(srgb_encode(std::numeric_limits<float>::quiet_NaN()), 0.0f);
  EXPECT_NEAR(srgb_encode(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(srgb_encode(0.002f), 0.02584f, 1e-5f);
  EXPECT_NEAR(srgb_encode(0.18f), 0.46135f, 1e-4f);  // mid grey
}

TEST(Image, ToneMapIsMonotonicAndBounded) {
  EXPECT_EQ(aces_filmic(0.0f), 0.0f);
  EXPECT_NEAR(aces_filmic(1.0f), 0.8038f, 1e-3f);
  EXPECT_EQ(aces_filmic(std::numeric_limits<float>::infinity()), 1.0f);
  float prev = -1.0f;
  for (float x = 0.0f; x < 100.0f; x += 0.05f) {
    const float y = aces_filmic(x);
    EXPECT_GE(y, prev);
    EXPECT_LE(y, 1.0f);
    prev = y;
  }
  Image hdr = make_image(2, 1, 1.0e-3f, 1.0e-3f, 1.0e-3f, 0.3f);
  hdr.pixel(1, 0)[0] = 1.6e9f;  // the sun
  hdr.pixel(1, 0)[1] = std::numeric_limits<float>::quiet_NaN();
  const Image d = tone_map_to_display(hdr, 100.0f);
  EXPECT_NEAR(d.pixel(0, 0)[0], srgb_encode(aces_filmic(0.1f)), 1e-6f);
  EXPECT_EQ(d.pixel(0, 0)[3], 1.0f);
  EXPECT_EQ(d.pixel(1, 0)[0], 1.0f);
  EXPECT_TRUE(std::isnan(d.pixel(1, 0)[1]));  // stays visible to count_nonfinite
}
