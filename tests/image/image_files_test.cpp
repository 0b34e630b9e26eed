// lib/image's own readers and writers (OpenEXR, libpng, Radiance HDR): the bytes OpenImageIO
// wrote for the same calls, OpenImageIO loaded only for the other formats, and every kind of
// hostile file refused with one line naming the file and the problem.
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "image/image.h"
#include "image/oiio_file.h"
#include "support/tool_test.h"

namespace sss {
namespace {

class ImageFiles : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return scratch_.path(name); }
  // readImage's error message, or "" when it reads.
  static std::string readError(const std::string& file) {
    try {
      readImage(file);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  // writeImage's error message, or "" when it writes.
  static std::string writeError(const std::string& file, const ImageRgb& image,
                                const ImageAttributes& attributes) {
    try {
      writeImage(file, image, attributes);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  void writeBytes(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
  }
  std::string bytesOf(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  test::ScratchDir scratch_;
};

ImageRgb gradient(int w, int h) {
  ImageRgb image;
  image.width = w;
  image.height = h;
  image.pixels.resize(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) image.at(x, y) = glm::vec3(x * 0.25f, y * 0.5f, 0.1f + x * y);
  }
  return image;
}

// An EXR without its capDate attribute (the time of writing): name, type, size, value.
std::string withoutCapDate(const std::string& exr) {
  const std::size_t at = exr.find(std::string("capDate\0string\0", 15));
  if (at == std::string::npos) return exr;
  const std::size_t value = at + 15;
  const auto size =
      static_cast<std::uint8_t>(exr[value]) | static_cast<std::uint8_t>(exr[value + 1]) << 8;
  return exr.substr(0, at) + exr.substr(value + 4 + size);
}

// What the project's writers made through OpenImageIO 2.4, made here through it directly.
void writeWithOpenImageIo(const std::string& file, const ImageRgb& image,
                          const ImageAttributes& attributes, bool linear) {
  auto out = OIIO::ImageOutput::create(file);
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(image.width, image.height, 3,
                       linear ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  for (const auto& [name, value] : attributes) spec.attribute(name, value);
  std::vector<std::uint8_t> bytes;
  for (const glm::vec3& p : image.pixels) {
    for (int k = 0; k < 3; ++k) bytes.push_back(linearToSrgbByte(p[k]));
  }
  if (!linear) spec.attribute("oiio:ColorSpace", "sRGB");
  ASSERT_TRUE(out->open(file, spec));
  ASSERT_TRUE(linear ? out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data())
                     : out->write_image(OIIO::TypeDesc::UINT8, bytes.data()));
  ASSERT_TRUE(out->close());
}

TEST_F(ImageFiles, ExrAndPngBytesAreOpenImageIosButForTheTimeOfWriting) {
  const ImageRgb image = gradient(37, 222);  // several ZIP chunks, IDAT blocks
  const ImageAttributes cube = {{"sss:layout", "stack"}, {"textureformat", "CubeFace Environment"}};
  writeImage(path("ours.exr"), image, cube);
  writeWithOpenImageIo(path("oiio.exr"), image, cube, true);
  EXPECT_EQ(withoutCapDate(bytesOf("ours.exr")), withoutCapDate(bytesOf("oiio.exr")));
  const ImageAttributes software = {{"Software", "sss-render"}};
  writeImage(path("ours.png"), image, software);
  writeWithOpenImageIo(path("oiio.png"), image, software, false);
  EXPECT_EQ(bytesOf("ours.png"), bytesOf("oiio.png"));
  // In memory (a texture to embed): the same bytes.
  std::vector<std::uint8_t> srgb;
  for (const glm::vec3& p : image.pixels) {
    for (int k = 0; k < 3; ++k) srgb.push_back(linearToSrgbByte(p[k]));
  }
  EXPECT_EQ(encodePng("texture", {.width = image.width,
                                  .height = image.height,
                                  .srgb8 = srgb.data(),
                                  .attributes = software}),
            bytesOf("ours.png"));
  // "compression" sets the header's own field, as OpenImageIO does (irrmap_compare writes the
  // uncompressed EXRs of tests/bench/irrmap_vs_cmft.sh so).
  for (const char* compression : {"none", "piz"}) {
    SCOPED_TRACE(compression);
    writeImage(path("ours.exr"), image, {{"compression", compression}});
    writeWithOpenImageIo(path("oiio.exr"), image, {{"compression", compression}}, true);
    EXPECT_EQ(withoutCapDate(bytesOf("ours.exr")), withoutCapDate(bytesOf("oiio.exr")));
    EXPECT_EQ(readImage(path("ours.exr")).pixels, image.pixels);
  }
  EXPECT_EQ(writeError(path("b44.exr"), image, {{"compression", "b44"}}),
            path("b44.exr") +
                ": cannot write (unknown EXR compression 'b44': none, zip, zips, piz, rle)");
  EXPECT_FALSE(std::filesystem::exists(path("b44.exr")));
}

TEST_F(ImageFiles, OurFormatsNeverLoadOpenImageIo) {
  // In a child process: this one may have loaded it for another test. "threadsafe" re-executes
  // the test binary: forking a process that OpenImageIO's threads run in can deadlock.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        writeImage(path("a.exr"), gradient(9, 4));
        writeImage(path("a.hdr"), gradient(9, 4));
        writeImage(path("a.png"), gradient(9, 4));
        for (const char* name : {"a.exr", "a.hdr", "a.png"}) readImage(path(name));
        const bool loaded = oiioLoaded();
        scratch_.remove();
        std::exit(loaded ? 1 : 0);
      },
      ::testing::ExitedWithCode(0), "");
  EXPECT_EXIT(
      {
        writeImage(path("a.tif"), gradient(9, 4));
        const bool read = oiioLoaded() && readImage(path("a.tif")).width == 9;
        scratch_.remove();
        std::exit(read ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
}

TEST_F(ImageFiles, RadianceHdrRoundTripsFlatAndRunLengthEncoded) {
  for (const int width : {5, 40}) {  // under 8 pixels a row is flat
    const ImageRgb image = gradient(width, 3);
    writeImage(path("a.hdr"), image);
    const ImageRgb back = readImage(path("a.hdr"));
    ASSERT_EQ(back.width, width);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      const glm::vec3 p = image.pixels[i];
      const float scale = std::max(p.x, std::max(p.y, p.z));
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(back.pixels[i][k], p[k], 0.01f * scale);
    }
  }
  // "+Y": the bottom row first (Ward, "The RADIANCE Picture File Format", resolution string).
  writeBytes("flipped.hdr", std::string("#?RADIANCE\n\n+Y 2 +X 1\n") +
                                std::string("\x80\x80\x80\x81\x80\x00\x00\x81", 8));
  const ImageRgb flipped = readImage(path("flipped.hdr"));
  EXPECT_EQ(flipped.at(0, 0), glm::vec3(1.0f, 0.0f, 0.0f));
  EXPECT_EQ(flipped.at(0, 1), glm::vec3(1.0f, 1.0f, 1.0f));
}

TEST_F(ImageFiles, HostileRadianceHdrFiles) {
  const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
  writeBytes("unterminated.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe");
  EXPECT_EQ(readError(path("unterminated.hdr")),
            path("unterminated.hdr") + ": Radiance HDR header is not terminated");
  writeBytes("resolution.hdr", header + "-Y two +X 3\n");
  EXPECT_EQ(readError(path("resolution.hdr")),
            path("resolution.hdr") + ": Radiance HDR resolution line '-Y two +X 3' is not valid");
  writeBytes("xyze.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\x80\x80\x80\x81");
  EXPECT_EQ(readError(path("xyze.hdr")),
            path("xyze.hdr") +
                ": Radiance HDR pixel format '32-bit_rle_xyze' is not supported (only "
                "32-bit_rle_rgbe)");
  writeBytes("axes.hdr", header + "-Y 1 +Z 1\n\x80\x80\x80\x81");
  EXPECT_EQ(readError(path("axes.hdr")),
            path("axes.hdr") + ": Radiance HDR resolution line '-Y 1 +Z 1' is not valid");
  writeBytes("zero.hdr", header + "-Y 0 +X 16\n");
  EXPECT_EQ(readError(path("zero.hdr")), path("zero.hdr") + ": image has zero size (16x0)");
  writeBytes("negative.hdr", header + "-Y 4 +X -16\n");
  EXPECT_EQ(readError(path("negative.hdr")),
            path("negative.hdr") + ": image has zero size (-16x4)");
  // Two 16-pixel RLE rows declared, one and a half given: the second ends inside a run.
  const std::string row = std::string("\x02\x02\x00\x10", 4) + std::string("\x90\x80", 2) +
                          std::string("\x90\x80", 2) + std::string("\x90\x80", 2) +
                          std::string("\x90\x81", 2);
  writeBytes("cut.hdr", header + "-Y 2 +X 16\n" + row + row.substr(0, 7) + std::string(40, '\0'));
  EXPECT_EQ(readError(path("cut.hdr")),
            path("cut.hdr") + ": Radiance HDR scanline 1 of 2 is truncated or corrupt");
  // A run of 20 in a 16-pixel row, and a row whose RLE header names another width.
  writeBytes("run.hdr", header + "-Y 1 +X 16\n" + std::string("\x02\x02\x00\x10\x94\x80", 6) +
                            std::string(40, '\0'));
  EXPECT_EQ(readError(path("run.hdr")),
            path("run.hdr") + ": Radiance HDR scanline 0 of 1 is truncated or corrupt");
  writeBytes("width.hdr",
             header + "-Y 1 +X 16\n" + std::string("\x02\x02\x00\x11", 4) + std::string(80, '\0'));
  EXPECT_EQ(readError(path("width.hdr")),
            path("width.hdr") + ": Radiance HDR scanline 0 of 1 is truncated or corrupt");
}

TEST_F(ImageFiles, HostilePngFiles) {
  writeImage(path("good.png"), gradient(64, 48));
  const std::string good = bytesOf("good.png");
  // Cut in the image data: 16 bytes into the first IDAT chunk's data (the text chunks before it
  // make the file's middle fall in the header).
  const std::size_t idat = good.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  writeBytes("cut.png", good.substr(0, idat + 4 + 16));
  EXPECT_EQ(readError(path("cut.png")).rfind(path("cut.png") + ": cannot read pixels (PNG: ", 0),
            0u)
      << readError(path("cut.png"));
  // A corrupt IHDR (its CRC no longer matches).
  std::string crc = good;
  crc[20] ^= 0x40;
  writeBytes("crc.png", crc);
  EXPECT_EQ(readError(path("crc.png")),
            path("crc.png") + ": cannot read image (PNG: IHDR: CRC error)");
  // Headers that lie, with a valid CRC: 100000 x 100000 pixels, and 16384 x 16384 in a few
  // hundred bytes. The IHDR's width and height are bytes 16-23, its CRC bytes 29-32.
  writeImage(path("small.png"), gradient(16, 16));
  const std::string small = bytesOf("small.png");
  auto withSize = [&](std::uint32_t w, std::uint32_t h) {
    std::string bytes = small;
    for (int i = 0; i < 4; ++i) {
      bytes[16 + i] = static_cast<char>(w >> (24 - 8 * i));
      bytes[20 + i] = static_cast<char>(h >> (24 - 8 * i));
    }
    std::uint32_t c = 0xffffffffu;  // CRC-32 of the type and data (PNG specification, D)
    for (int i = 12; i < 29; ++i) {
      c ^= static_cast<std::uint8_t>(bytes[i]);
      for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
    }
    c ^= 0xffffffffu;
    for (int i = 0; i < 4; ++i) bytes[29 + i] = static_cast<char>(c >> (24 - 8 * i));
    return bytes;
  };
  writeBytes("huge.png", withSize(100000, 100000));
  EXPECT_EQ(readError(path("huge.png")),
            path("huge.png") +
                ": header declares 100000x100000 pixels, more than the 268435456 "
                "(2^28) an image may have");
  writeBytes("lying.png", withSize(16384, 16384));
  EXPECT_EQ(readError(path("lying.png")),
            path("lying.png") +
                ": header declares 16384x16384 pixels, which take at least 4096 "
                "bytes, but the file has " +
                std::to_string(small.size()) + " (truncated?)");
  // A text chunk after the header that declares 1.19 GB in a file of a few hundred bytes: skipped
  // unread, not allocated (the fuzzer found it under its 1 GiB malloc limit).
  const std::string chunk = std::string("\x47\x0d\x2e\x75", 4) + "tEXt" + "key";
  writeBytes("chunk.png", small.substr(0, 33) + chunk + small.substr(33));
  EXPECT_EQ(readError(path("chunk.png")),
            path("chunk.png") + ": cannot read image (PNG: the file ends early (truncated?))");
}

TEST_F(ImageFiles, HostileExrFiles) {
  writeImage(path("good.exr"), gradient(64, 48));
  const std::string good = bytesOf("good.exr");
  writeBytes("cut.exr", good.substr(0, good.size() - 100));
  EXPECT_EQ(readError(path("cut.exr")).rfind(path("cut.exr") + ": cannot read image (", 0), 0u)
      << readError(path("cut.exr"));
  // Compressed data overwritten: the decoder fails, and says so in one line.
  std::string garbled = good;
  for (std::size_t i = good.size() - 100; i < good.size(); ++i) garbled[i] = '\xff';
  writeBytes("garbled.exr", garbled);
  EXPECT_EQ(readError(path("garbled.exr")).rfind(path("garbled.exr") + ": cannot read image (", 0),
            0u)
      << readError(path("garbled.exr"));
}

}  // namespace
}  // namespace sss
