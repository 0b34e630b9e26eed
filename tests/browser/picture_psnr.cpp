// The PSNR of a browser's screenshot against sss-render's picture over the object's pixels, in dB
// of 8-bit sRGB values: the object's pixels are those where sss-render's pictures of the same
// view over a black and over a white background agree (the silhouette's mixed pixels and the
// background drop out).
//   picture_psnr SCREENSHOT.png RENDER.png RENDER_ON_BLACK.png RENDER_ON_WHITE.png
// Prints "psnr_db=... object_pixels=... mean_abs=..." on one line.
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "core/srgb.h"
#include "image/image.h"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: picture_psnr SCREENSHOT RENDER RENDER_ON_BLACK RENDER_ON_WHITE\n");
    return 2;
  }
  try {
    const sss::ImageRgb shot = sss::readImage(argv[1]), render = sss::readImage(argv[2]),
                        black = sss::readImage(argv[3]), white = sss::readImage(argv[4]);
    for (const sss::ImageRgb* other : {&render, &black, &white}) {
      if (other->width != shot.width || other->height != shot.height) {
        throw sss::Error("the pictures differ in size");
      }
    }
    double sumSquares = 0.0, sumAbs = 0.0;
    std::size_t pixels = 0;
    for (std::size_t i = 0; i < shot.pixels.size(); ++i) {
      const auto byte = [](float linear) { return double(sss::linearToSrgbByte(linear)); };
      const glm::vec3 b = black.pixels[i], w = white.pixels[i];
      bool object = true;
      for (int c = 0; c < 3; ++c) object = object && byte(b[c]) == byte(w[c]);
      if (!object) continue;
      ++pixels;
      for (int c = 0; c < 3; ++c) {
        const double d = byte(shot.pixels[i][c]) - byte(render.pixels[i][c]);
        sumSquares += d * d;
        sumAbs += std::abs(d);
      }
    }
    if (pixels == 0) throw sss::Error("no object pixel");
    const double mse = sumSquares / (3.0 * pixels);
    const double psnr = mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
    std::printf("psnr_db=%.2f object_pixels=%zu mean_abs=%.3f\n", psnr, pixels,
                sumAbs / (3.0 * pixels));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "picture_psnr: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
