// The one place that decides which backend reads or writes which image format. OpenEXR, PNG and
// Radiance HDR (the formats of the sample environments, cubemaps and pictures) have readers and
// writers of their own that start in microseconds; every other format (TIFF, PFM, JPEG, ...) goes
// to OpenImageIO, loaded on first use (oiio_file.h), so that a run that needs none of them does
// not pay its ~250 shared libraries (docs/performance.md, "Start-up").
#pragma once

#include <string>

namespace sss {

enum class ImageBackend { OpenExr, Png, RadianceHdr, OpenImageIO };

// By content, as the first bytes identify the three formats of our own (a misnamed file still
// reads); anything else, an unreadable or short file included, is OpenImageIO's.
ImageBackend readerFor(const std::string& path);
// By the extension (lower-cased): exr, png, hdr; anything else is OpenImageIO's.
ImageBackend writerFor(const std::string& path);
// The extensions written as linear float: exr, hdr, pfm, tif, tiff; the rest as 8-bit sRGB.
bool isFloatImageExtension(const std::string& extension);

}  // namespace sss
