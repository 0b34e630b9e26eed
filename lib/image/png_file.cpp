#include "image/png_file.h"

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <png.h>
#include <zlib.h>

#include "core/error.h"
#include "image/image_limits.h"

namespace sss {
namespace {

// libpng reports errors through a callback that must not return: it longjmps back to the
// setjmp of the function that called libpng (libpng manual, "Setjmp/longjmp issues"), with the
// message kept here. Only libpng's frames and ours without destructors lie between the two.
struct PngErrors {
  std::jmp_buf jump;
  char message[200] = "";
};

[[noreturn]] void onError(png_structp png, png_const_charp message) {
  auto* errors = static_cast<PngErrors*>(png_get_error_ptr(png));
  std::snprintf(errors->message, sizeof errors->message, "%s", message);
  std::longjmp(errors->jump, 1);
}

void onWarning(png_structp, png_const_charp) {}  // libpng's warnings are about benign chunks

// libpng's default reader says only "Read Error" when the file ends early.
void readOrFail(png_structp png, png_bytep data, png_size_t size) {
  auto* file = static_cast<std::FILE*>(png_get_io_ptr(png));
  if (std::fread(data, 1, size, file) != size) png_error(png, "the file ends early (truncated?)");
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// One libpng read or write struct with its info struct, destroyed with it.
class PngStruct {
 public:
  explicit PngStruct(bool write) : write_(write) {
    png_ = write ? png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors_, onError, onWarning)
                 : png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors_, onError, onWarning);
    if (png_) info_ = png_create_info_struct(png_);
  }
  ~PngStruct() {
    if (write_) {
      png_destroy_write_struct(&png_, &info_);
    } else {
      png_destroy_read_struct(&png_, &info_, nullptr);
    }
  }
  PngStruct(const PngStruct&) = delete;
  PngStruct& operator=(const PngStruct&) = delete;
  bool ok() const { return png_ != nullptr && info_ != nullptr; }
  png_structp png() const { return png_; }
  png_infop info() const { return info_; }
  PngErrors& errors() { return errors_; }

 private:
  bool write_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  PngErrors errors_;
};

// The header, the transforms to 8- or 16-bit grey or RGB without alpha, and the samples' layout.
struct PngLayout {
  png_uint_32 width = 0, height = 0;
  int channels = 0, bytesPerSample = 1;
  bool linear = false;  // a 16-bit file whose gAMA says linear
};

// False, with the message in png.errors(), when libpng fails; the setjmp here keeps every object
// with a destructor out of the jump's way.
bool readLayout(PngStruct& png, std::FILE* file, PngLayout& layout) {
  if (setjmp(png.errors().jump)) return false;
  png_structp p = png.png();
  png_infop info = png.info();
  png_set_read_fn(p, file, readOrFail);
  // Our limits, not libpng's default 1,000,000 x 1,000,000, say what is too large.
  png_set_user_limits(p, 0x7fffffff, 0x7fffffff);
  // libpng reads a metadata chunk (text, ICC profile) whole, at the length it declares, even past
  // its own "chunk data is too large" warning: skip every ancillary chunk but the two that say
  // how to read the samples (libpng manual, "Unknown-chunk handling").
  static const png_byte wanted[] = "gAMA\0sRGB";
  png_set_keep_unknown_chunks(p, PNG_HANDLE_CHUNK_NEVER, nullptr, -1);
  png_set_keep_unknown_chunks(p, PNG_HANDLE_CHUNK_AS_DEFAULT, wanted, 2);
  png_read_info(p, info);
  int bitDepth = 0, colorType = 0;
  png_get_IHDR(p, info, &layout.width, &layout.height, &bitDepth, &colorType, nullptr, nullptr,
               nullptr);
  if (colorType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(p);
  if (colorType == PNG_COLOR_TYPE_GRAY && bitDepth < 8) png_set_expand_gray_1_2_4_to_8(p);
  if (colorType & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(p);
  if (bitDepth == 16) png_set_swap(p);  // native little-endian uint16
  png_set_interlace_handling(p);
  double gamma = 0.0;
  layout.linear = bitDepth == 16 && png_get_gAMA(p, info, &gamma) && gamma > 0.99 && gamma < 1.01 &&
                  !png_get_valid(p, info, PNG_INFO_sRGB);
  png_read_update_info(p, info);
  layout.channels = png_get_channels(p, info);
  layout.bytesPerSample = bitDepth == 16 ? 2 : 1;
  return true;
}

// The rows into samples (bytes, or uint16 of 16-bit files), allocated by the caller.
bool readRows(PngStruct& png, png_bytep* rows) {
  if (setjmp(png.errors().jump)) return false;
  png_read_image(png.png(), rows);
  png_read_end(png.png(), nullptr);
  return true;
}

DecodedImage toRgb(const PngLayout& layout, const std::vector<unsigned char>& samples) {
  DecodedImage decoded;
  ImageRgb& image = decoded.image;
  image.width = static_cast<int>(layout.width);
  image.height = static_cast<int>(layout.height);
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
  const bool wide = layout.bytesPerSample == 2;
  const float scale = wide ? 1.0f / 65535.0f : 1.0f / 255.0f;
  const auto* words = reinterpret_cast<const std::uint16_t*>(samples.data());
  const int n = layout.channels;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const std::size_t s = i * n + (n >= 3 ? k : 0);  // grey is replicated
      image.pixels[i][k] = (wide ? words[s] : samples[s]) * scale;
    }
  }
  decoded.srgb = !layout.linear;
  return decoded;
}

// libpng's write callbacks: the encoded bytes appended to a string.
void appendBytes(png_structp png, png_bytep data, png_size_t size) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), size);
}
void flushNothing(png_structp) {}

// The chunks in OpenImageIO 2.4's order, then the rows; false (message in png.errors()) when
// libpng fails.
bool writeRows(PngStruct& png, std::string& out, const PixelsToWrite& pixels,
               std::vector<png_text>& texts, png_bytep* rows) {
  if (setjmp(png.errors().jump)) return false;
  png_structp p = png.png();
  png_set_write_fn(p, &out, appendBytes, flushNothing);
  png_set_compression_level(p, pixels.fastPng ? 1 : 6);
  // zlib's default strategy, not libpng's Z_FILTERED for filtered rows, as OpenImageIO set it.
  png_set_compression_strategy(p, Z_DEFAULT_STRATEGY);
  if (pixels.fastPng) png_set_filter(p, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_set_IHDR(p, png.info(), pixels.width, pixels.height, 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(p, png.info(), PNG_sRGB_INTENT_ABSOLUTE);
  png_set_oFFs(p, png.info(), 0, 0, PNG_OFFSET_PIXEL);
  png_set_text(p, png.info(), texts.data(), static_cast<int>(texts.size()));
  png_write_info(p, png.info());
  png_write_image(p, rows);
  png_write_end(p, png.info());
  return true;
}

}  // namespace

DecodedImage readPng(const std::string& path) {
  const File file(std::fopen(path.c_str(), "rb"));
  if (!file) fail(path, "cannot open");
  PngStruct png(false);
  if (!png.ok()) fail(path, "cannot read image (out of memory)");
  PngLayout layout;
  if (!readLayout(png, file.get(), layout)) {
    fail(path, std::string("cannot read image (PNG: ") + png.errors().message + ")");
  }
  checkDeclaredImageSize(path, "png", layout.width, layout.height, layout.channels, false);
  const std::size_t rowBytes =
      static_cast<std::size_t>(layout.width) * layout.channels * layout.bytesPerSample;
  std::vector<unsigned char> samples(rowBytes * layout.height);
  std::vector<png_bytep> rows(layout.height);
  for (png_uint_32 y = 0; y < layout.height; ++y) rows[y] = samples.data() + y * rowBytes;
  if (!readRows(png, rows.data())) {
    fail(path, std::string("cannot read pixels (PNG: ") + png.errors().message + ")");
  }
  return toRgb(layout, samples);
}

std::string encodePng(const std::string& name, const PixelsToWrite& pixels) {
  PngStruct png(true);
  if (!png.ok()) fail(name, "cannot write (out of memory)");
  std::string colorSpaceKey = "oiio:ColorSpace", colorSpace = "sRGB";
  std::vector<png_text> texts(pixels.attributes.size() + 1);
  for (std::size_t i = 0; i <= pixels.attributes.size(); ++i) {
    const bool last = i == pixels.attributes.size();
    texts[i].compression = PNG_TEXT_COMPRESSION_NONE;
    texts[i].key =
        const_cast<char*>(last ? colorSpaceKey.c_str() : pixels.attributes[i].first.c_str());
    texts[i].text =
        const_cast<char*>(last ? colorSpace.c_str() : pixels.attributes[i].second.c_str());
  }
  std::vector<png_bytep> rows(pixels.height);
  for (int y = 0; y < pixels.height; ++y) {
    rows[y] = const_cast<png_bytep>(pixels.srgb8 + static_cast<std::size_t>(y) * pixels.width * 3);
  }
  std::string out;
  if (!writeRows(png, out, pixels, texts, rows.data())) {
    fail(name, std::string("cannot write (PNG: ") + png.errors().message + ")");
  }
  return out;
}

void writePng(const std::string& path, const PixelsToWrite& pixels) {
  const std::string bytes = encodePng(path, pixels);
  const File file(std::fopen(path.c_str(), "wb"));
  if (!file) fail(path, "cannot write (cannot open)");
  if (std::fwrite(bytes.data(), 1, bytes.size(), file.get()) != bytes.size() ||
      std::fflush(file.get()) != 0) {
    fail(path, "cannot write (disk full?)");
  }
}

}  // namespace sss
