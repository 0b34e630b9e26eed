// The renderer against analytic values on llvmpipe: linear float output, no tonemap, 1 sample,
// so that every pixel can be predicted from the camera ray.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "envmap/cubemap.h"
#include "envmap/environment.h"
#include "envmap/equirect.h"
#include "material/directional_albedo_weight.h"
#include "mesh/primitives.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "render/camera.h"
#include "render/gl_context.h"
#include "render/renderer.h"

namespace sss {
namespace {

class RenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = std::make_unique<GlContext>(); }
  static void TearDownTestSuite() { context_.reset(); }
  static std::unique_ptr<GlContext> context_;
};
std::unique_ptr<GlContext> RenderTest::context_;

RenderMesh toRenderMesh(const TriangleMesh& mesh, glm::vec3 value) {
  RenderMesh r;
  r.positions = mesh.positions;
  r.normals = mesh.normals;
  r.values.assign(mesh.positions.size(), value);
  for (const glm::uvec3& t : mesh.triangles) r.indices.insert(r.indices.end(), {t.x, t.y, t.z});
  return r;
}

// World direction through the centre of pixel (x, y), row 0 at the top.
glm::vec3 pixelRay(const Camera& c, int x, int y, int width, int height) {
  const glm::vec3 f = glm::normalize(c.target - c.eye);
  const glm::vec3 r = glm::normalize(glm::cross(f, c.up));
  const glm::vec3 u = glm::cross(r, f);
  const float t = std::tan(glm::radians(c.fovYDeg) * 0.5f);
  const float aspect = static_cast<float>(width) / height;
  const float nx = (x + 0.5f) / width * 2.0f - 1.0f, ny = 1.0f - (y + 0.5f) / height * 2.0f;
  return glm::normalize(f + nx * t * aspect * r + ny * t * u);
}

// Nearest hit of a ray with the sphere |p| = radius, or a negative distance.
float hitSphere(glm::vec3 origin, glm::vec3 dir, float radius) {
  const float b = glm::dot(origin, dir), c = glm::dot(origin, origin) - radius * radius;
  const float disc = b * b - c;
  return disc < 0.0f ? -1.0f : -b - std::sqrt(disc);
}

glm::vec3 pixel(const RenderedImage& image, int x, int y) {
  const float* p = &image.linearRgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
  return glm::vec3(p[0], p[1], p[2]);
}

// A smooth environment that tells directions apart: 0.5 + 0.5 d.
Cubemap directionColouredCubemap(int size) {
  Cubemap env(size);
  forEachTexel(
      size, [&](int f, int x, int y) { env.at(f, x, y) = 0.5f + 0.5f * env.direction(f, x, y); });
  return env;
}

// One frame of the unit icosphere at `subdivisions`, with the constant value `exitance`, under
// `env`, seen by `camera`.
// With exitSlope set, B leaves through the exit lobe of that slope.
RenderedImage renderUnitSphere(const ShadingOptions& shading, const FrameOptions& frame,
                               int subdivisions, glm::vec3 exitance, const Cubemap& env,
                               const Camera& camera, std::optional<glm::vec3> exitSlope = {}) {
  Renderer renderer(ShaderSources(), frame, shading);
  RenderMesh mesh = toRenderMesh(makeIcosphere(subdivisions, 1.0f), exitance);
  if (exitSlope) mesh.exitSlopes.assign(mesh.positions.size(), *exitSlope);
  renderer.setMesh(mesh);
  renderer.setEnvironment(env, nullptr);
  renderer.setCamera(camera);
  renderer.draw();
  return renderer.readBack();
}

// The unit sphere framed from (azimuth, elevation) in degrees, 35 degree field of view.
Camera unitSphereCamera(float azimuthDeg, float elevationDeg) {
  return orbitCamera(BoundingSphere{glm::vec3(0.0f), 1.0f}, azimuthDeg, elevationDeg, 0.0f, 35.0f,
                     1.0f);
}

// Untonemapped radiance on a black background: what the tests compare with closed forms.
ShadingOptions linearShading() {
  ShadingOptions shading;
  shading.tonemap = Tonemap::None;
  shading.backgroundColor = glm::vec3(0.0f);
  return shading;
}

FrameOptions linearFrame(int size) {
  FrameOptions frame;
  frame.width = frame.height = size;
  frame.samples = 1;
  frame.linear = true;
  return frame;
}

struct ExitCase {
  FresnelModel fresnel;
  bool normalized;       // exit scale F_t-normalized (exitRadianceScale) rather than 1/pi
  bool calibrated;       // and the angular weights of a skin-like material (ExitModel::Calibrated)
  bool farLobe = false;  // B leaving through a far field's exit lobe (ExitModel::Auto)
};

// The test name's suffix (exact_normalized, schlick_over_pi, exact_calibrated), also what
// ctest -N and a failure print.
std::string exitCaseName(const ExitCase& c) {
  return std::string(c.fresnel == FresnelModel::Exact ? "exact" : "schlick") +
         (c.farLobe      ? "_far_lobe"
          : c.calibrated ? "_calibrated"
          : c.normalized ? "_normalized"
                         : "_over_pi");
}

void PrintTo(const ExitCase& c, std::ostream* out) {
  *out << exitCaseName(c);
}

class ExitModelTest : public RenderTest, public ::testing::WithParamInterface<ExitCase> {};

// L = B F_t(mu) w(mu) s + F_r(mu) L_env for a sphere with constant B under a uniform environment
// (w = 1 but for the calibrated case); with a far field's slope, B times the exit lobe's radiance
// per unit exitance (optics/exit_lobe.h) instead of the first term.
TEST_P(ExitModelTest, SphereWithConstantExitanceMatchesTheExitModel) {
  const float eta = 1.4f;
  const glm::vec3 exitance(2.0f, 1.0f, 0.5f), envRadiance(0.7f, 0.5f, 0.3f);
  ShadingOptions shading = linearShading();
  shading.fresnel = GetParam().fresnel;
  shading.eta = eta;
  shading.exitScale = GetParam().normalized ? static_cast<float>(exitRadianceScale(eta))
                                            : static_cast<float>(1.0 / M_PI);
  const DirectionalAlbedoWeight weight(glm::dvec3(0.96, 0.84, 0.68), eta);
  if (GetParam().calibrated) {
    for (int k = 0; k < kExitWeightNodes; ++k)
      shading.exitWeight[k] = weight.at(float(k) / (kExitWeightNodes - 1));
  }
  // Exit lobes of slopes from grazing (-0.6) to forward (2) light.
  const ExitLobe lobe(eta);
  const glm::vec3 slope(-0.6f, 0.3f, 2.0f);
  std::optional<glm::vec3> far;
  if (GetParam().farLobe) {
    far = slope;
    shading.lobeMoment0 = float(lobe.moment(0));
    shading.lobeMoment1 = float(lobe.moment(1));
  }
  const FrameOptions frame = linearFrame(128);
  const Camera camera = unitSphereCamera(20.0f, 10.0f);
  const RenderedImage image =
      renderUnitSphere(shading, frame, 5, exitance, Cubemap(16, envRadiance), camera, far);

  int checked = 0;
  for (int y = 0; y < frame.height; ++y) {
    for (int x = 0; x < frame.width; ++x) {
      const glm::vec3 dir = pixelRay(camera, x, y, frame.width, frame.height);
      const float t = hitSphere(camera.eye, dir, 1.0f);
      const glm::vec3 got = pixel(image, x, y);
      if (t < 0.0f) {
        // Clearly outside the sphere: the background colour.
        if (hitSphere(camera.eye, dir, 1.03f) < 0.0f) {
          EXPECT_EQ(got, glm::vec3(0.0f));
        }
        continue;
      }
      const glm::vec3 n = glm::normalize(camera.eye + t * dir);
      const float mu = -glm::dot(n, dir);
      if (mu < 0.3f) continue;  // silhouette: the polyhedron and the sphere differ
      const float fr = GetParam().fresnel == FresnelModel::Exact ? fresnelDielectric(mu, eta)
                                                                 : fresnelSchlick(mu, eta);
      const glm::vec3 w = GetParam().calibrated ? weight.at(mu) : glm::vec3(1.0f);
      glm::vec3 shape = w;  // the lobe over the normalized model (F_t cancels)
      if (far)
        for (int c = 0; c < 3; ++c)
          shape[c] *= float(lobe.radiance(slope[c], mu) / lobe.radiance(0.0, mu));
      const glm::vec3 expected =
          exitance * shape * (1.0f - fr) * shading.exitScale + fr * envRadiance;
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(got[c], expected[c], 0.01f * expected[c]) << "pixel " << x << "," << y;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 4000);
}

INSTANTIATE_TEST_SUITE_P(FresnelAndExit, ExitModelTest,
                         ::testing::Values(ExitCase{FresnelModel::Exact, true, false},
                                           ExitCase{FresnelModel::Schlick, false, false},
                                           ExitCase{FresnelModel::Exact, true, true},
                                           ExitCase{FresnelModel::Exact, true, false, true}),
                         [](const auto& info) { return exitCaseName(info.param); });

// Linear output, black background, no tonemap, and the unscattered light of this extinction.
ShadingOptions unscatteredShading(float eta, glm::vec3 sigmaT) {
  ShadingOptions shading = linearShading();
  shading.eta = eta;
  shading.unscatteredSigmaT = sigmaT;
  return shading;
}

// What crosses a slab (or a sphere's chord) of optical depth tau whose faces reflect fr: the
// series of internal reflections summed, F_t^2 e^(-tau) / (1 - F_r^2 e^(-2 tau)).
glm::vec3 transmittedThrough(float fr, glm::vec3 tau) {
  const glm::vec3 t = glm::exp(-tau);
  return (1.0f - fr) * (1.0f - fr) * t / (1.0f - fr * fr * t * t);
}

// The light that crosses a slab unscattered, seen through its top face: the environment behind
// along the view ray times F_t^2 e^(-tau) / (1 - F_r^2 e^(-2 tau)), tau = sigma_t h / mu_i (h the
// thickness, mu_i the refracted cosine), beside the reflection. Straight on and at 35 degrees
// (where the straight chord, h / mu_o, would overstate tau by 13 %); a slab of sigma_t 40 lets
// nothing through.
TEST_F(RenderTest, UnscatteredLightThroughASlabMatchesItsClosedForm) {
  const float eta = 1.3f, thickness = 0.5f;
  const TriangleMesh slab = makeSlab(4.0f, thickness, 16);
  const Cubemap env = directionColouredCubemap(64);
  for (const float azimuth : {0.0f, 35.0f})
    for (const glm::vec3 sigmaT : {glm::vec3(0.5f, 1.5f, 4.0f), glm::vec3(40.0f)}) {
      const ShadingOptions shading = unscatteredShading(eta, sigmaT);
      const FrameOptions frame = linearFrame(128);
      const Camera camera =
          orbitCamera(boundingSphere(slab.positions), azimuth, 0.0f, 0.0f, 35.0f, 1.0f);
      Renderer renderer(ShaderSources(), frame, shading);
      renderer.setMesh(toRenderMesh(slab, glm::vec3(0.0f)));
      renderer.setEnvironment(env, nullptr);
      renderer.setCamera(camera);
      renderer.draw();
      const RenderedImage image = renderer.readBack();
      int checked = 0;
      for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
          const glm::vec3 dir = pixelRay(camera, x, y, frame.width, frame.height);
          const float t = (0.5f * thickness - camera.eye.z) / dir.z;
          const glm::vec3 hit = camera.eye + t * dir;
          if (!(t > 0.0f) || std::abs(hit.x) > 1.4f || std::abs(hit.y) > 1.4f) continue;
          const float mu = -dir.z, fr = fresnelDielectric(mu, eta);
          const float muI = std::sqrt(1.0f - (1.0f - mu * mu) / (eta * eta));
          const glm::vec3 through = transmittedThrough(fr, sigmaT * thickness / muI);
          const glm::vec3 expected = fr * (0.5f + 0.5f * glm::reflect(dir, glm::vec3(0, 0, 1))) +
                                     through * (0.5f + 0.5f * dir);
          const glm::vec3 got = pixel(image, x, y);
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], expected[c], 0.01f + 0.01f * expected[c])
                << "azimuth " << azimuth << " sigma_t " << sigmaT[c] << " pixel " << x << "," << y;
          ++checked;
        }
      EXPECT_GT(checked, 2000);
    }
}

// Through a sphere under uniform light the refracted ray's chord is 2 R mu_i, and every internal
// reflection keeps its angle: L = F_r + F_t^2 e^(-tau) / (1 - F_r^2 e^(-2 tau)), tau = sigma_t
// 2 R mu_i, exactly (the straight chord, 2 R mu_o, would leave a pale rim).
TEST_F(RenderTest, UnscatteredLightThroughASphereFollowsTheRefractedChord) {
  const float eta = 1.3f;
  const glm::vec3 sigmaT(0.3f, 1.0f, 3.0f);
  const ShadingOptions shading = unscatteredShading(eta, sigmaT);
  const FrameOptions frame = linearFrame(128);
  const Camera camera = unitSphereCamera(30.0f, 20.0f);
  const RenderedImage image =
      renderUnitSphere(shading, frame, 5, glm::vec3(0.0f), Cubemap(16, glm::vec3(1.0f)), camera);
  int checked = 0;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      const glm::vec3 dir = pixelRay(camera, x, y, frame.width, frame.height);
      const float t = hitSphere(camera.eye, dir, 1.0f);
      if (t < 0.0f) continue;
      const glm::vec3 n = glm::normalize(camera.eye + t * dir);
      const float mu = -glm::dot(n, dir);
      // Near the silhouette the polyhedron's interpolated normals bend the ray off the sphere's.
      if (mu < 0.4f) continue;
      const float fr = fresnelDielectric(mu, eta);
      const float muI = std::sqrt(1.0f - (1.0f - mu * mu) / (eta * eta));
      const glm::vec3 expected = fr + transmittedThrough(fr, sigmaT * 2.0f * muI);
      const glm::vec3 got = pixel(image, x, y);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], expected[c], 0.015f * expected[c]) << "pixel " << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 4000);
}

// A sun's radiance exceeds half floats (65504: the procedural sky's reaches 1.4e5): the cubemap is
// kept in 32-bit floats, so a mirror shows it as it is (in RGBA16F it would become Inf, and the
// tonemap's Inf / Inf a NaN: coloured specks where a sun's reflection falls).
// A relit mesh (ShadingOptions::relightCoefficients): the vertex shader's
// max(sum_k T_k L_k + rest, 0) g b, per vertex from its storage buffer, draws what a mesh whose
// values are that sum, made here, draws; after new values (setValues) and a new light too. The
// transfer, rest and gains vary per vertex and take both signs, so that a wrong vertex index,
// coefficient stride or clamp shows.
TEST_F(RenderTest, RelitInTheShaderAsSummedOnTheCpu) {
  constexpr int kCoefficients = 4;
  const RenderMesh plain = toRenderMesh(makeIcosphere(3, 1.0f), glm::vec3(0.0f));
  const std::size_t n = plain.positions.size();
  const auto wave = [](std::size_t v, int k, float phase) {
    return std::sin(0.37f * float(v) + 1.3f * float(k) + phase);
  };
  RenderMesh relit = plain;
  relit.relightTransfer.resize(n * kCoefficients);
  relit.exitanceGain.resize(n);
  std::vector<glm::vec3> rest(n), otherRest(n);
  for (std::size_t v = 0; v < n; ++v) {
    for (int k = 0; k < kCoefficients; ++k)
      relit.relightTransfer[v * kCoefficients + k] =
          glm::vec3(0.6f + wave(v, k, 0.0f), 0.5f + wave(v, k, 1.0f), 0.4f + wave(v, k, 2.0f));
    relit.exitanceGain[v] = glm::vec3(1.0f + 0.5f * wave(v, 0, 3.0f), 0.8f, 1.2f);
    rest[v] = 0.3f * glm::vec3(wave(v, 1, 4.0f), wave(v, 2, 5.0f), wave(v, 3, 6.0f));
    otherRest[v] = 0.2f * glm::vec3(wave(v, 2, 1.0f), wave(v, 1, 0.5f), 0.5f);
  }
  const std::vector<glm::vec3> light{
      {1.0f, 0.8f, 0.6f}, {0.2f, -0.1f, 0.3f}, {-0.2f, 0.1f, 0.0f}, {0.3f, 0.3f, -0.4f}};
  const std::vector<glm::vec3> otherLight{
      {0.5f, 0.9f, 1.1f}, {-0.3f, 0.2f, 0.1f}, {0.1f, 0.1f, 0.2f}, {0.0f, -0.2f, 0.3f}};
  const auto summed = [&](const std::vector<glm::vec3>& l, const std::vector<glm::vec3>& r) {
    RenderMesh m = plain;
    for (std::size_t v = 0; v < n; ++v) {
      glm::vec3 b = r.empty() ? glm::vec3(0.0f) : r[v];
      for (int k = 0; k < kCoefficients; ++k)
        b += relit.relightTransfer[v * kCoefficients + k] * l[k];
      m.values[v] = glm::max(b, glm::vec3(0.0f)) * relit.exitanceGain[v];
    }
    return m;
  };
  const FrameOptions frame = linearFrame(96);
  const Camera camera = unitSphereCamera(40.0f, 20.0f);
  const Cubemap env(8, glm::vec3(0.2f));
  ShadingOptions shading = linearShading();
  Renderer reference(ShaderSources(), frame, shading);
  reference.setEnvironment(env, nullptr);
  reference.setCamera(camera);
  shading.relightCoefficients = kCoefficients;
  Renderer renderer(ShaderSources(), frame, shading);
  renderer.setMesh(relit);
  renderer.setEnvironment(env, nullptr);
  renderer.setCamera(camera);
  const auto compare = [&](const RenderMesh& expected, const char* what) {
    reference.setMesh(expected);
    reference.draw();
    renderer.draw();
    const RenderedImage want = reference.readBack(), got = renderer.readBack();
    float worst = 0.0f, largest = 0.0f;
    for (std::size_t i = 0; i < want.linearRgb.size(); ++i) {
      worst = std::max(worst, std::abs(got.linearRgb[i] - want.linearRgb[i]));
      largest = std::max(largest, want.linearRgb[i]);
    }
    EXPECT_GT(largest, 0.1f) << what;
    EXPECT_LT(worst, 1e-4f * largest) << what;
  };
  relit.values = rest;
  renderer.setMesh(relit);
  renderer.setSmoothLight(light);
  compare(summed(light, rest), "the first light");
  renderer.setValues(otherRest);
  renderer.setSmoothLight(otherLight);
  compare(summed(otherLight, otherRest), "new values and light");
  renderer.setValues({});
  compare(summed(otherLight, {}), "no rest");
  EXPECT_THROW(renderer.setValues(std::vector<glm::vec3>(n + 1)), Error);
  EXPECT_THROW(renderer.setSmoothLight(std::vector<glm::vec3>(kCoefficients - 1)), Error);
}

TEST_F(RenderTest, RadianceAboveHalfFloatRangeStaysFinite) {
  ShadingOptions shading = linearShading();
  shading.reflectFactor = 1.0f;
  const FrameOptions frame = linearFrame(32);
  const glm::vec3 sun(1.5e5f, 1.2e5f, 8.0e4f);
  const RenderedImage image = renderUnitSphere(shading, frame, 3, glm::vec3(0.0f), Cubemap(8, sun),
                                               unitSphereCamera(0.0f, 0.0f));
  const glm::vec3 centre = pixel(image, 16, 16);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(centre[c], sun[c], 1e-3f * sun[c]) << c;
}

// With MSAA a silhouette pixel is shaded once; at its centre, outside the triangle, the exit term
// (0 at grazing exit) would be extrapolated below 0. The varyings are centroid-sampled: no pixel
// of a sphere on black goes negative.
TEST_F(RenderTest, MultisampledSilhouettesStayNonNegative) {
  const ShadingOptions shading = linearShading();
  FrameOptions frame = linearFrame(96);
  frame.samples = 4;
  const RenderedImage image =
      renderUnitSphere(shading, frame, 2, glm::vec3(1.0f), Cubemap(8, glm::vec3(0.0f)),
                       unitSphereCamera(0.0f, 0.0f));
  float lowest = 0.0f;
  for (float v : image.linearRgb) lowest = std::min(lowest, v);
  EXPECT_GE(lowest, 0.0f);
}
// The paper's constant mix with factor 1 is a perfect mirror: each pixel shows the environment
// along the reflected view ray (a mirrored lookup would swap sides).
TEST_F(RenderTest, MirrorShowsTheEnvironmentAlongTheReflectedRay) {
  ShadingOptions shading = linearShading();
  shading.reflectFactor = 1.0f;
  const FrameOptions frame = linearFrame(128);
  const Camera camera = unitSphereCamera(60.0f, 25.0f);
  const RenderedImage image =
      renderUnitSphere(shading, frame, 5, glm::vec3(0.0f), directionColouredCubemap(64), camera);
  int checked = 0;
  for (int y = 0; y < frame.height; ++y) {
    for (int x = 0; x < frame.width; ++x) {
      const glm::vec3 dir = pixelRay(camera, x, y, frame.width, frame.height);
      const float t = hitSphere(camera.eye, dir, 1.0f);
      if (t < 0.0f) continue;
      const glm::vec3 n = glm::normalize(camera.eye + t * dir);
      if (-glm::dot(n, dir) < 0.4f) continue;
      const glm::vec3 expected = 0.5f + 0.5f * glm::reflect(dir, n);
      const glm::vec3 got = pixel(image, x, y);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 0.02f) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
}

// The background shows an equirect image the way sss-irrmap reads it: from the origin looking
// at -Z, the image centre; +X to the right; every pixel the environment along its view ray.
TEST_F(RenderTest, BackgroundFollowsTheEquirectConvention) {
  ImageRgb equirect;
  equirect.width = 256;
  equirect.height = 128;
  equirect.pixels.resize(256 * 128);
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 256; ++x)
      equirect.at(x, y) = 0.5f + 0.5f * equirectDirection((x + 0.5f) / 256, (y + 0.5f) / 128);
  const Cubemap env = cubemapFromImage(equirect, EnvironmentLayout::Equirect, 64);

  ShadingOptions shading;
  shading.tonemap = Tonemap::None;
  const FrameOptions frame = linearFrame(64);
  Renderer renderer(ShaderSources(), frame, shading);
  renderer.setEnvironment(env, nullptr);
  for (const glm::vec3& forward :
       {glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(0.3f, 0.8f, 0.2f)}) {
    Camera camera;
    camera.eye = glm::vec3(0.0f);
    camera.target = forward;
    camera.fovYDeg = 60.0f;
    renderer.setCamera(camera);
    renderer.draw();
    const RenderedImage image = renderer.readBack();
    for (int y = 0; y < frame.height; ++y) {
      for (int x = 0; x < frame.width; ++x) {
        const glm::vec3 expected = 0.5f + 0.5f * pixelRay(camera, x, y, frame.width, frame.height);
        const glm::vec3 got = pixel(image, x, y);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[c], expected[c], 0.01f) << x << "," << y;
      }
    }
  }
  // Explicitly: the image centre is ahead when looking at -Z, and +X is on the right.
  Camera camera;
  camera.eye = glm::vec3(0.0f);
  camera.target = glm::vec3(0, 0, -1);
  renderer.setCamera(camera);
  renderer.draw();
  const RenderedImage image = renderer.readBack();
  const glm::vec3 centre = pixel(image, 32, 32);
  EXPECT_NEAR(centre.b, equirect.at(128, 64).b, 0.02f);
  EXPECT_GT(pixel(image, 60, 32).r, pixel(image, 3, 32).r + 0.2f);
}

// Exposure, tonemap and encoding, checked on a uniform background of radiance 1 seen at +1 EV.
TEST_F(RenderTest, ExposureAndTonemapsFollowTheirFormulas) {
  const float x = 2.0f;  // 1 at +1 EV
  const float aces = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
  struct Case {
    Tonemap tonemap;
    float expected;
  };
  for (const Case& c : {Case{Tonemap::None, x}, Case{Tonemap::Reinhard, x / (1.0f + x)},
                        Case{Tonemap::Aces, std::min(aces, 1.0f)}}) {
    ShadingOptions shading;
    shading.tonemap = c.tonemap;
    shading.exposureEv = 1.0f;
    for (bool linear : {true, false}) {
      FrameOptions frame = linearFrame(8);
      frame.linear = linear;
      Renderer renderer(ShaderSources(), frame, shading);
      renderer.setEnvironment(Cubemap(4, glm::vec3(1.0f)), nullptr);
      renderer.setCamera(Camera());
      renderer.draw();
      const RenderedImage image = renderer.readBack();
      if (linear) {
        EXPECT_NEAR(image.linearRgb[0], c.expected, 2e-3f * c.expected);
      } else {
        const float v = std::min(c.expected, 1.0f);
        const float srgb = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
        EXPECT_NEAR(image.srgb8[0], std::lround(255.0f * srgb), 1);
      }
    }
  }
}

// The normals view encodes n * 0.5 + 0.5: a sphere seen from +Z shows +Z (0.5, 0.5, 1) in its
// middle, and back faces are culled (front faces are counter-clockwise).
TEST_F(RenderTest, NormalsViewAndCounterClockwiseFrontFaces) {
  ShadingOptions shading;
  shading.mode = ShadingMode::Normals;
  shading.backgroundColor = glm::vec3(0.0f);
  const RenderedImage image =
      renderUnitSphere(shading, linearFrame(64), 3, glm::vec3(0.0f), Cubemap(4, glm::vec3(1.0f)),
                       unitSphereCamera(0.0f, 0.0f));
  const glm::vec3 middle = 0.5f * (pixel(image, 31, 31) + pixel(image, 32, 32));
  EXPECT_NEAR(middle.x, 0.5f, 0.03f);
  EXPECT_NEAR(middle.y, 0.5f, 0.03f);
  EXPECT_NEAR(middle.z, 1.0f, 0.01f);
  // Upper part of the picture: normals point up.
  EXPECT_GT(pixel(image, 32, 12).y, 0.75f);
}

TEST(CameraTest, OrbitFramesTheSphereAndLooksFromTheGivenSide) {
  const BoundingSphere bounds{glm::vec3(1.0f, 2.0f, 3.0f), 2.0f};
  const Camera c = orbitCamera(bounds, 90.0f, 0.0f, 0.0f, 40.0f, 2.0f);
  EXPECT_NEAR(c.eye.y, 2.0f, 1e-5f);
  EXPECT_NEAR(c.eye.z, 3.0f, 1e-4f);
  EXPECT_GT(c.eye.x, 1.0f + 2.0f / std::sin(glm::radians(20.0f)));  // from +X, sphere fits
  EXPECT_LT(c.nearPlane, glm::length(c.eye - bounds.centre) - bounds.radius);
  EXPECT_GT(c.farPlane, glm::length(c.eye - bounds.centre) + bounds.radius);
}

}  // namespace
}  // namespace sss
