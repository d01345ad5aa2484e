#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "atmo_support/image_metrics.h"

using namespace atmo::support;

TEST(ImageMetrics, IdenticalImagesHaveInfinitePsnr) {
  const Image a = make_image(8, 8, 0.3f, 0.5f, 0.7f, 1.0f);
  const ImageDiff d = compare_images(a, a, 1.0);
  EXPECT_TRUE(std::isinf(d.psnr_db) && d.psnr_db > 0);
  EXPECT_EQ(d.rmse, 0.0);
  EXPECT_EQ(d.max_abs, 0.0);
  EXPECT_EQ(d.pixels, 64u);
}

TEST(ImageMetrics, KnownPerturbationMatchesFormula) {
  const Image a = make_image(10, 10, 0.5f, 0.5f, 0.5f, 1.0f);
  Image b = a;
  // One channel of one pixel off by 0.25; alpha differences are ignored.
  b.pixel(3, 4)[1] += 0.25f;
  b.pixel(7, 7)[3] = 0.0f;
  const ImageDiff d = compare_images(a, b, 1.0);
  const double rmse = std::sqrt(0.25 * 0.25 / 300.0);
  EXPECT_NEAR(d.rmse, rmse, 1e-12);
  EXPECT_NEAR(d.psnr_db, 20.0 * std::log10(1.0 / rmse), 1e-9);
  EXPECT_NEAR(d.max_abs, 0.25, 1e-7);
  // Uniform offset: rmse = offset exactly.
  Image c = make_image(10, 10, 0.6f, 0.6f, 0.6f, 1.0f);
  const ImageDiff e = compare_images(a, c, 2.0);
  EXPECT_NEAR(e.psnr_db, 20.0 * std::log10(2.0 / 0.1), 1e-5);
}

TEST(ImageMetrics, NonFiniteCountedAndExcluded) {
  Image a = make_image(4, 4, 1, 1, 1, 1);
  Image b = a;
  a.pixel(0, 0)[0] = std::numeric_limits<float>::quiet_NaN();
  b.pixel(1, 0)[2] = std::numeric_limits<float>::infinity();
  b.pixel(2, 0)[3] = std::numeric_limits<float>::quiet_NaN();  // alpha: counted by count_nonfinite only
  const ImageDiff d = compare_images(a, b, 1.0);
  EXPECT_EQ(d.nonfinite_a, 1u);
  EXPECT_EQ(d.nonfinite_b, 1u);
  EXPECT_EQ(d.pixels, 14u);
  EXPECT_TRUE(std::isinf(d.psnr_db));
  EXPECT_EQ(count_nonfinite(a), 1u);
  EXPECT_EQ(count_nonfinite(b), 2u);
}

TEST(ImageMetrics, SizeMismatchThrows) {
  EXPECT_THROW(compare_images(make_image(2, 2), make_image(2, 3), 1.0), std::invalid_argument);
  EXPECT_THROW(relative_luminance_error(make_image(2, 2), make_image(3, 2), 1e-3), std::invalid_argument);
}

TEST(ImageMetrics, RelativeLuminanceError) {
  // Reference Y = 1; test pixels scaled by 1.00 .. 1.99 -> errors 0.00 .. 0.99.
  const Image ref = make_image(100, 1, 1, 1, 1, 1);
  Image test = ref;
  for (int x = 0; x < 100; ++x)
    for (int c = 0; c < 3; ++c) test.pixel(x, 0)[c] = 1.0f + 0.01f * static_cast<float>(x);
  const LuminanceErrorStats s = relative_luminance_error(test, ref, 1e-4);
  EXPECT_NEAR(s.median, 0.495, 1e-5);
  EXPECT_NEAR(s.p95, 0.9405, 1e-5);
  EXPECT_NEAR(s.max, 0.99, 1e-5);

  // The floor guards dark reference pixels.
  const Image dark = make_image(1, 1, 0, 0, 0, 1);
  const Image lit = make_image(1, 1, 0.01f, 0.01f, 0.01f, 1);
  EXPECT_NEAR(relative_luminance_error(lit, dark, 0.1).max, 0.1, 1e-6);
  EXPECT_NEAR(luminance(lit.pixel(0, 0)), 0.01, 1e-8);
}
