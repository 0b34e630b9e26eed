// Procedural sun and sky for --sky.
//
// Sky dome: Preetham, Shirley & Smits 1999, "A practical analytic model for daylight": Perez
// distributions of luminance Y and chromaticity x, y (their Appendix A.2 coefficients and zenith
// values), converted xyY -> XYZ -> linear sRGB and scaled by 1/10 (kcd/m^2 -> about 1 at the
// zenith). Sun: a disc of angular radius `sunAngularRadiusDeg` whose colour is the extraterrestrial
// white attenuated along the air mass (Kasten & Young 1989) by Rayleigh (tau = 0.008735
// lambda^-4.08) and Angstrom aerosol (beta = 0.04608 T - 0.04586, alpha = 1.3) optical depths at
// 680, 550 and 440 nm, with irradiance 20 * sunIntensity at normal incidence before attenuation.
// Ground below the horizon: Lambertian, albedo times the horizontal irradiance of sun and sky
// over pi.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "envmap/environment.h"

namespace sss {
namespace {

constexpr double kPi = M_PI;

struct Perez {
  double a, b, c, d, e;
  double operator()(double cosTheta, double gamma) const {
    const double cg = std::cos(gamma);
    return (1.0 + a * std::exp(b / std::max(cosTheta, 0.01))) *
           (1.0 + c * std::exp(d * gamma) + e * cg * cg);
  }
};

class PreethamSky {
 public:
  PreethamSky(const glm::dvec3& sun, double t) : sun_(sun) {
    thetaS_ = std::acos(std::clamp(sun.y, 0.0, 1.0));
    yPerez_ = {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771,
               -0.0670 * t + 0.3703};
    xPerez_ = {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125,
               -0.0641 * t - 0.8989, -0.0033 * t + 0.0452};
    cPerez_ = {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102,
               -0.0441 * t - 1.6537, -0.0109 * t + 0.0529};
    const double th = thetaS_, th2 = th * th, th3 = th2 * th, t2 = t * t;
    const double chi = (4.0 / 9.0 - t / 120.0) * (kPi - 2.0 * th);
    zenithY_ = (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
    zenithX_ = t2 * (0.00166 * th3 - 0.00375 * th2 + 0.00209 * th) +
               t * (-0.02903 * th3 + 0.06377 * th2 - 0.03202 * th + 0.00394) +
               (0.11693 * th3 - 0.21196 * th2 + 0.06052 * th + 0.25886);
    zenithC_ = t2 * (0.00275 * th3 - 0.00610 * th2 + 0.00317 * th) +
               t * (-0.04214 * th3 + 0.08970 * th2 - 0.04153 * th + 0.00516) +
               (0.15346 * th3 - 0.26756 * th2 + 0.06670 * th + 0.26688);
  }

  // Linear sRGB radiance of the sky (without the sun) towards unit direction w, w.y >= 0.
  glm::dvec3 operator()(const glm::dvec3& w) const {
    const double cosTheta = std::max(w.y, 0.0);
    const double gamma = std::acos(std::clamp(glm::dot(w, sun_), -1.0, 1.0));
    const double luminance = 0.1 * zenithY_ * yPerez_(cosTheta, gamma) / yPerez_(1.0, thetaS_);
    const double x = zenithX_ * xPerez_(cosTheta, gamma) / xPerez_(1.0, thetaS_);
    const double y = zenithC_ * cPerez_(cosTheta, gamma) / cPerez_(1.0, thetaS_);
    const double bigX = x * luminance / y, bigZ = (1.0 - x - y) * luminance / y;
    const glm::dvec3 rgb(3.2406 * bigX - 1.5372 * luminance - 0.4986 * bigZ,
                         -0.9689 * bigX + 1.8758 * luminance + 0.0415 * bigZ,
                         0.0557 * bigX - 0.2040 * luminance + 1.0570 * bigZ);
    return glm::max(rgb, glm::dvec3(0.0));
  }

 private:
  glm::dvec3 sun_;
  double thetaS_;
  Perez yPerez_, xPerez_, cPerez_;
  double zenithY_, zenithX_, zenithC_;
};

// Transmittance of the atmosphere towards the sun at 680, 550, 440 nm.
glm::dvec3 sunTransmittance(double cosThetaS, double turbidity) {
  const double zenithDeg = std::acos(std::clamp(cosThetaS, 0.0, 1.0)) * 180.0 / kPi;
  const double airMass = 1.0 / (cosThetaS + 0.50572 * std::pow(96.07995 - zenithDeg, -1.6364));
  const double beta = std::max(0.04608 * turbidity - 0.04586, 0.0);
  const double lambda[3] = {0.68, 0.55, 0.44};
  glm::dvec3 t;
  for (int k = 0; k < 3; ++k) {
    const double tau = 0.008735 * std::pow(lambda[k], -4.08) + beta * std::pow(lambda[k], -1.3);
    t[k] = std::exp(-airMass * tau);
  }
  return t;
}

// Horizontal irradiance of the sky dome (midpoint rule in cos theta and phi) plus the sun's.
glm::dvec3 horizontalIrradiance(const PreethamSky& sky, const glm::dvec3& sun,
                                const glm::dvec3& sunIrradiance) {
  glm::dvec3 horizontal = sunIrradiance * sun.y;
  const int nTheta = 64, nPhi = 128;
  for (int i = 0; i < nTheta; ++i) {
    const double mu = (i + 0.5) / nTheta, s = std::sqrt(1.0 - mu * mu);
    for (int j = 0; j < nPhi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / nPhi;
      horizontal +=
          sky({s * std::cos(phi), mu, s * std::sin(phi)}) * mu * (2.0 * kPi / (nTheta * nPhi));
    }
  }
  return horizontal;
}

// The sky above the horizon and the uniform ground below, averaged over k x k directions per
// texel for the horizon.
void drawSkyAndGround(Cubemap& cube, const PreethamSky& sky, const glm::dvec3& ground,
                      int threads) {
  const int faceSize = cube.size();
  const int k = 3;
  parallelFor(
      6 * static_cast<std::size_t>(faceSize), threads, 8, [&](std::size_t begin, std::size_t end) {
        for (std::size_t row = begin; row < end; ++row) {
          const int f = static_cast<int>(row / faceSize), y = static_cast<int>(row % faceSize);
          for (int x = 0; x < faceSize; ++x) {
            cube.at(f, x, y) = glm::vec3(
                Cubemap::averageOverTexel<glm::dvec3>(f, x, y, faceSize, k, [&](glm::vec3 d) {
                  const glm::dvec3 w = glm::normalize(glm::dvec3(d));
                  return w.y >= 0.0 ? sky(w) : ground;
                }));
          }
        }
      });
}

// The sun: its flux goes to the texels its disc covers. A disc smaller than a few texels is
// deposited whole into the texel holding its centre, so that no flux is lost to sampling; a
// larger one adds its radiance to each texel by the covered fraction (8 x 8 directions).
void addSun(Cubemap& cube, const glm::dvec3& sun, double radius, const glm::dvec3& sunIrradiance) {
  const int faceSize = cube.size();
  const double texelAngle = 2.0 / faceSize;
  if (radius < 3.0 * texelAngle) {
    const CubeCoord c = Cubemap::project(glm::vec3(sun));
    const int x = std::min(static_cast<int>(c.s * faceSize), faceSize - 1);
    const int y = std::min(static_cast<int>(c.t * faceSize), faceSize - 1);
    cube.at(c.face, x, y) +=
        glm::vec3(sunIrradiance / static_cast<double>(cube.solidAngle(c.face, x, y)));
    return;
  }
  const double sunSolidAngle = 2.0 * kPi * (1.0 - std::cos(radius));
  const glm::dvec3 sunRadiance = sunIrradiance / sunSolidAngle;
  const int ks = 8;
  const double cosRadius = std::cos(radius);
  forEachTexel(faceSize, [&](int f, int x, int y) {
    if (glm::dot(glm::dvec3(cube.direction(f, x, y)), sun) < std::cos(radius + 2.0 * texelAngle))
      return;
    int inside = 0;
    for (int j = 0; j < ks; ++j) {
      for (int i = 0; i < ks; ++i) {
        const glm::dvec3 w = glm::normalize(glm::dvec3(Cubemap::unproject(
            f, (x + (i + 0.5f) / ks) / faceSize, (y + (j + 0.5f) / ks) / faceSize)));
        inside += glm::dot(w, sun) >= cosRadius;
      }
    }
    cube.at(f, x, y) += glm::vec3(sunRadiance * (inside / double(ks * ks)));
  });
}

double parseNumber(const std::string& key, const std::string& value) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || value.empty() || !std::isfinite(v)) {
    throw Error(key + "=" + value + " is not a number");
  }
  return v;
}

}  // namespace

SkyParameters parseSkySpec(const std::string& spec) {
  SkyParameters sky;
  double elevation = std::asin(glm::normalize(sky.sunDirection).y) * 180.0 / kPi;
  const glm::vec3 d0 = glm::normalize(sky.sunDirection);
  double azimuth = std::atan2(d0.x, -d0.z) * 180.0 / kPi;
  std::stringstream items(spec);
  std::string item;
  while (std::getline(items, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw Error("expected key=value, got '" + item + "'");
    const std::string key = item.substr(0, eq);
    const double v = parseNumber(key, item.substr(eq + 1));
    auto check = [&](bool ok, const char* range) {
      if (!ok) throw Error(key + " must be " + range);
    };
    if (key == "elevation") {
      check(v >= 0.0 && v <= 90.0, "in [0, 90] degrees");
      elevation = v;
    } else if (key == "azimuth") {
      azimuth = v;
    } else if (key == "turbidity") {
      check(v >= 1.7 && v <= 10.0, "in [1.7, 10]");
      sky.turbidity = static_cast<float>(v);
    } else if (key == "sun") {
      check(v >= 0.0, ">= 0");
      sky.sunIntensity = static_cast<float>(v);
    } else if (key == "radius") {
      check(v > 0.0 && v <= 20.0, "in (0, 20] degrees");
      sky.sunAngularRadiusDeg = static_cast<float>(v);
    } else if (key == "ground") {
      check(v >= 0.0 && v <= 1.0, "in [0, 1]");
      sky.groundAlbedo = glm::vec3(static_cast<float>(v));
    } else {
      throw Error("unknown key '" + key +
                  "' (known: elevation, azimuth, turbidity, sun, radius, ground)");
    }
  }
  const double e = elevation * kPi / 180.0, a = azimuth * kPi / 180.0;
  sky.sunDirection =
      glm::vec3(static_cast<float>(std::cos(e) * std::sin(a)), static_cast<float>(std::sin(e)),
                static_cast<float>(-std::cos(e) * std::cos(a)));
  return sky;
}

Cubemap makeSky(const SkyParameters& params, int faceSize, int threads) {
  if (faceSize <= 0) throw Error("sky face size must be positive");
  glm::dvec3 sun = glm::normalize(glm::dvec3(params.sunDirection));
  if (sun.y < 0.0) throw Error("the sun must not be below the horizon");
  const PreethamSky sky(sun, params.turbidity);
  const double radius = params.sunAngularRadiusDeg * kPi / 180.0;
  const glm::dvec3 sunIrradiance =
      20.0 * params.sunIntensity * sunTransmittance(sun.y, params.turbidity);
  const glm::dvec3 ground =
      glm::dvec3(params.groundAlbedo) * horizontalIrradiance(sky, sun, sunIrradiance) / kPi;
  Cubemap cube(faceSize);
  drawSkyAndGround(cube, sky, ground, threads);
  addSun(cube, sun, radius, sunIrradiance);
  return cube;
}

SkyParameters rotatedSky(SkyParameters sky, const EnvironmentOrientation& orientation) {
  sky.sunDirection = rotationAboutY(orientation.rotateDeg) * sky.sunDirection;
  return sky;
}

}  // namespace sss
