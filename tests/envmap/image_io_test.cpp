// Image and cubemap files: round trips and every kind of bad input readImage must refuse.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "envmap/cubemap_io.h"
#include "image/image.h"
#include "support/tool_test.h"

namespace sss {
namespace {

class ImageIo : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return scratch_.path(name); }
  // Error message of readImage(file), or "" when it succeeds.
  static std::string readError(const std::string& file, bool sanitize = false) {
    try {
      readImage(file, {sanitize});
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  test::ScratchDir scratch_;
};

ImageRgb gradient(int w, int h) {
  ImageRgb image;
  image.width = w;
  image.height = h;
  image.pixels.resize(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) image.at(x, y) = glm::vec3(x * 0.5f, y * 2.0f, 1000.0f + x * y);
  }
  return image;
}

TEST_F(ImageIo, FloatFormatsRoundTripExactly) {
  const ImageRgb image = gradient(7, 5);
  for (const char* ext : {".exr", ".hdr", ".tif"}) {
    const std::string file = path(std::string("a") + ext);
    writeImage(file, image);
    const ImageRgb back = readImage(file);
    ASSERT_EQ(back.width, 7);
    ASSERT_EQ(back.height, 5);
    // Radiance .hdr keeps 8-bit mantissas with one shared exponent (RGBE).
    const float tol = std::string(ext) == ".hdr" ? 0.01f : 0.0f;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      const glm::vec3 p = image.pixels[i];
      const float scale = std::max(p.x, std::max(p.y, p.z));
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(back.pixels[i][k], p[k], tol * scale) << ext;
    }
  }
  // No temporary file is left beside the outputs.
  EXPECT_EQ(scratch_.fileNames(), (std::vector<std::string>{"a.exr", "a.hdr", "a.tif"}));
}

TEST_F(ImageIo, PfmIsReadTopRowFirst) {
  // PFM stores rows bottom to top, little-endian floats when the scale is negative.
  std::ofstream out(path("a.pfm"), std::ios::binary);
  out << "PF\n1 2\n-1.0\n";
  const float bottom[3] = {1, 2, 3}, top[3] = {4, 5, 6};
  out.write(reinterpret_cast<const char*>(bottom), sizeof bottom);
  out.write(reinterpret_cast<const char*>(top), sizeof top);
  out.close();
  const ImageRgb image = readImage(path("a.pfm"));
  ASSERT_EQ(image.height, 2);
  EXPECT_EQ(image.at(0, 0), glm::vec3(4, 5, 6));
  EXPECT_EQ(image.at(0, 1), glm::vec3(1, 2, 3));
}

TEST_F(ImageIo, PngIsSrgbEncoded) {
  ImageRgb image;
  image.width = 2;
  image.height = 1;
  image.pixels = {glm::vec3(0.0f, 0.2140f, 1.0f), glm::vec3(5.0f, -1.0f, 0.5f)};
  writeImage(path("a.png"), image);
  const ImageRgb back = readImage(path("a.png"));  // decoded back to linear
  EXPECT_NEAR(back.at(0, 0).y, 0.2140f, 0.003f);   // sRGB 0.5
  EXPECT_NEAR(back.at(1, 0).x, 1.0f, 1e-6f);       // clamped
  EXPECT_NEAR(back.at(1, 0).z, 0.5f, 0.004f);
  EXPECT_NEAR(linearToSrgb(0.0031308f), 0.04045f, 1e-5f);
  EXPECT_NEAR(linearToSrgb(0.2140f), 0.5f, 1e-3f);
}

// The byte from the threshold table is lround(255 linearToSrgb(v)) exactly: at a dense sweep of
// [0, 1.1], on a log sweep of small values, and at NaN and negative values.
TEST(Srgb, ByteTableMatchesTheTransferFunction) {
  auto direct = [](float v) {
    return static_cast<std::uint8_t>(std::lround(255.0f * linearToSrgb(v)));
  };
  for (int i = 0; i <= 1'100'000; ++i) {
    const float v = i * 1e-6f;
    ASSERT_EQ(linearToSrgbByte(v), direct(v)) << v;
  }
  for (int i = 0; i <= 100'000; ++i) {
    const float v = std::pow(10.0f, -7.0f + 7.0f * i / 100'000);
    ASSERT_EQ(linearToSrgbByte(v), direct(v)) << v;
  }
  EXPECT_EQ(linearToSrgbByte(NAN), 0);
  EXPECT_EQ(linearToSrgbByte(-1.0f), 0);
  EXPECT_EQ(linearToSrgbByte(INFINITY), 255);
}

TEST_F(ImageIo, CubemapStackRoundTrip) {
  Cubemap cube(4);
  for (std::size_t i = 0; i < cube.texelCount(); ++i) cube.data()[i] = glm::vec3(i, 2 * i, 0.5f);
  writeCubemap(path("c.exr"), cube);
  const Cubemap back = readCubemap(path("c.exr"));
  ASSERT_EQ(back.size(), 4);
  for (std::size_t i = 0; i < cube.texelCount(); ++i) EXPECT_EQ(back.data()[i], cube.data()[i]);
  writeImage(path("wide.exr"), gradient(8, 4));
  EXPECT_THROW(readCubemap(path("wide.exr")), Error);
}

TEST_F(ImageIo, MissingUnreadableAndEmptyFiles) {
  EXPECT_EQ(readError(path("nope.exr")), path("nope.exr") + ": no such file");
  std::ofstream(path("junk.exr")) << "this is not an image";
  EXPECT_EQ(readError(path("junk.exr")).rfind(path("junk.exr") + ": cannot read image", 0), 0u)
      << readError(path("junk.exr"));
  std::ofstream(path("empty.hdr"));
  EXPECT_NE(readError(path("empty.hdr")), "");
  // A PFM header that declares 0 x 0 pixels.
  std::ofstream(path("zero.pfm"), std::ios::binary) << "PF\n0 0\n-1.0\n";
  EXPECT_EQ(readError(path("zero.pfm")), path("zero.pfm") + ": image has zero size (0x0)");
  // A header that promises more pixels than the file has.
  std::ofstream(path("short.pfm"), std::ios::binary) << "PF\n64 64\n-1.0\nabc";
  EXPECT_NE(readError(path("short.pfm")), "");
}

// A header's declared size is checked against kMaxImagePixels and the file's size before any
// pixel is allocated (unchecked: "std::bad_alloc" with no file name).
TEST_F(ImageIo, LyingHeadersAreRefusedBeforeAllocating) {
  const std::string rgbe = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
  std::ofstream(path("tall.hdr"), std::ios::binary) << rgbe << "-Y 99999999999 +X 64\n";
  EXPECT_EQ(readError(path("tall.hdr")),
            path("tall.hdr") +
                ": header declares 64x99999999999 pixels, more than the 268435456 (2^28) an "
                "image may have");
  std::ofstream(path("wide.hdr"), std::ios::binary) << rgbe << "-Y 400000 +X 400000\n";
  EXPECT_NE(readError(path("wide.hdr")).find("400000x400000 pixels, more than"), std::string::npos);
  // 1024 x 512 run-length encoded takes at least 512 x (4 + 8 x 9) bytes.
  std::ofstream(path("short.hdr"), std::ios::binary) << rgbe << "-Y 512 +X 1024\n\x02\x02\x04";
  EXPECT_EQ(readError(path("short.hdr")),
            path("short.hdr") +
                ": header declares 1024x512 pixels, which take at least 38912 bytes, but the file "
                "has 53 (truncated?)");
  std::ofstream(path("short.pfm"), std::ios::binary) << "PF\n4096 2048\n-1.0\nabc";
  EXPECT_NE(readError(path("short.pfm")).find("which take at least 100663296 bytes"),
            std::string::npos);
  std::filesystem::create_directory(path("folder.exr"));
  EXPECT_EQ(readError(path("folder.exr")), path("folder.exr") + ": is a directory, not a file");
}

TEST(ImageFileSize, MinimumBytesPerFormat) {
  // HDR: flat below 8 or above 32767 pixels a row, else at least a 4-byte header and 2 bytes per
  // 127 pixels per channel.
  EXPECT_EQ(minimumImageFileBytes("hdr", 4, 10, 3, true), 10u * 16u);
  EXPECT_EQ(minimumImageFileBytes("hdr", 127, 2, 3, true), 2u * 12u);
  EXPECT_EQ(minimumImageFileBytes("hdr", 128, 1, 3, true), 4u + 16u);
  EXPECT_EQ(minimumImageFileBytes("hdr", 40000, 1, 3, true), 160000u);
  EXPECT_EQ(minimumImageFileBytes("pnm", 8, 4, 3, true), 8u * 4u * 3u * 4u);  // PFM
  EXPECT_EQ(minimumImageFileBytes("pnm", 8, 4, 1, false), 4u);                // a P4 bitmap
  EXPECT_EQ(minimumImageFileBytes("openexr", 16384, 16384, 3, false), 4096u);
  EXPECT_EQ(minimumImageFileBytes("png", 100, 100, 3, false), 0u);
}

TEST_F(ImageIo, SmallestValidFilesPassTheSizeCheck) {
  // Constant images compress the most; every writer's output must still read back.
  ImageRgb flat;
  flat.width = 512;
  flat.height = 256;
  flat.pixels.assign(512 * 256, glm::vec3(0.25f));
  for (const char* name : {"flat.hdr", "flat.exr", "flat.png", "flat.tif"}) {
    writeImage(path(name), flat);
    EXPECT_EQ(readError(path(name)), "") << name;
  }
}

TEST_F(ImageIo, NonFiniteTexelsAreCountedWithTheFirstPosition) {
  ImageRgb image = gradient(6, 4);
  image.at(4, 1).y = std::numeric_limits<float>::quiet_NaN();
  image.at(2, 3).x = std::numeric_limits<float>::infinity();
  image.at(5, 3).z = -std::numeric_limits<float>::infinity();
  writeImage(path("nan.exr"), image);
  EXPECT_EQ(readError(path("nan.exr")),
            path("nan.exr") + ": 3 NaN/Inf texel values, first at (4, 1)");
  const ImageRgb clean = readImage(path("nan.exr"), {true});
  EXPECT_EQ(clean.at(4, 1).y, 0.0f);
  EXPECT_EQ(clean.at(2, 3).x, 0.0f);
  EXPECT_EQ(clean.at(5, 3).z, 0.0f);
  EXPECT_EQ(clean.at(3, 3), image.at(3, 3));
}

TEST_F(ImageIo, NegativeTexelsAreClamped) {
  ImageRgb image = gradient(4, 2);
  image.at(1, 1) = glm::vec3(-2.0f, 3.0f, -0.5f);
  writeImage(path("neg.exr"), image);
  const ImageRgb back = readImage(path("neg.exr"));
  EXPECT_EQ(back.at(1, 1), glm::vec3(0.0f, 3.0f, 0.0f));
}

}  // namespace
}  // namespace sss
