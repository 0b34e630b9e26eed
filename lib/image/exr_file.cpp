#include "image/exr_file.h"

#include <ctime>
#include <exception>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompressionAttribute.h>
#include <OpenEXR/ImfEnvmapAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include "core/error.h"
#include "image/exr_header.h"
#include "image/image_limits.h"

namespace sss {
namespace {

// The channels read as RGB: R, G and B, or Y alone (grey), each sampled at every pixel.
// Anything else (luminance-chroma, layers, subsampled channels) is OpenImageIO's, which orders
// and converts channels its own way.
std::optional<std::vector<std::string>> rgbChannels(const Imf::ChannelList& channels) {
  auto full = [&](const char* name) {
    const Imf::Channel* c = channels.findChannel(name);
    return c != nullptr && c->xSampling == 1 && c->ySampling == 1;
  };
  if (full("R") && full("G") && full("B")) return std::vector<std::string>{"R", "G", "B"};
  if (full("Y") && !channels.findChannel("RY") && !channels.findChannel("BY")) {
    return std::vector<std::string>{"Y", "Y", "Y"};
  }
  return std::nullopt;
}

std::optional<DecodedImage> readPixels(const std::string& path, Imf::InputFile& file) {
  const Imath::Box2i window = file.header().dataWindow();
  const auto names = rgbChannels(file.header().channels());
  if (!names) return std::nullopt;
  const long long width = static_cast<long long>(window.max.x) - window.min.x + 1;
  const long long height = static_cast<long long>(window.max.y) - window.min.y + 1;
  checkDeclaredImageSize(path, "openexr", width, height, 3, true);
  DecodedImage decoded;
  ImageRgb& image = decoded.image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.pixels.resize(static_cast<std::size_t>(width) * height);
  // The slices address pixel (x, y) of the data window at base + x xStride + y yStride.
  const std::size_t xStride = sizeof(glm::vec3), yStride = xStride * image.width;
  char* origin = reinterpret_cast<char*>(image.pixels.data()) -
                 static_cast<std::ptrdiff_t>(window.min.x * static_cast<std::ptrdiff_t>(xStride)) -
                 static_cast<std::ptrdiff_t>(window.min.y * static_cast<std::ptrdiff_t>(yStride));
  Imf::FrameBuffer frame;
  for (int k = 0; k < 3; ++k) {
    frame.insert((*names)[k], Imf::Slice(Imf::FLOAT, origin + k * sizeof(float), xStride, yStride));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
  return decoded;
}

// The time of writing as OpenImageIO puts it into capDate: local time, "YYYY:MM:DD HH:MM:SS".
std::string captureDate() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char text[32];
  std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &local);
  return text;
}

// OpenImageIO's names of the compressions that carry float pixels exactly.
Imf::Compression exrCompression(const std::string& path, const std::string& name) {
  if (name == "none") return Imf::NO_COMPRESSION;
  if (name == "zip") return Imf::ZIP_COMPRESSION;
  if (name == "zips") return Imf::ZIPS_COMPRESSION;
  if (name == "piz") return Imf::PIZ_COMPRESSION;
  if (name == "rle") return Imf::RLE_COMPRESSION;
  fail(path, "cannot write (unknown EXR compression '" + name + "': none, zip, zips, piz, rle)");
}

}  // namespace

std::optional<DecodedImage> readExr(const std::string& path) {
  checkExrHeader(path);  // OpenEXR allocates what a header declares before checking it
  try {
    Imf::InputFile file(path.c_str());
    return readPixels(path, file);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, std::string("cannot read image (") + e.what() + ")");
  }
}

void writeExr(const std::string& path, const PixelsToWrite& pixels) {
  try {
    Imf::Header header(pixels.width, pixels.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.insert("capDate", Imf::StringAttribute(captureDate()));
    for (const auto& [name, value] : pixels.attributes) {
      if (name == "compression") {  // OpenImageIO's name for the header's own field
        header.compression() = exrCompression(path, value);
        continue;
      }
      header.insert(name, Imf::StringAttribute(value));
      if (name == "textureformat" && value == "CubeFace Environment") {
        header.insert("envmap", Imf::EnvmapAttribute(Imf::ENVMAP_CUBE));
      }
    }
    for (const char* name : {"R", "G", "B"}) {
      header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    }
    Imf::OutputFile file(path.c_str(), header);
    const std::size_t xStride = 3 * sizeof(float), yStride = xStride * pixels.width;
    char* base = const_cast<char*>(reinterpret_cast<const char*>(pixels.linear));
    Imf::FrameBuffer frame;
    for (int k = 0; k < 3; ++k) {
      frame.insert(std::string(1, "RGB"[k]),
                   Imf::Slice(Imf::FLOAT, base + k * sizeof(float), xStride, yStride));
    }
    file.setFrameBuffer(frame);
    file.writePixels(pixels.height);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, std::string("cannot write (") + e.what() + ")");
  }
}

}  // namespace sss
