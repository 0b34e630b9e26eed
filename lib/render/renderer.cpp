#include "render/renderer.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "core/bounds.h"
#include "core/error.h"
#include "core/median.h"
#include "core/timer.h"
#include "envmap/cubemap.h"
#include "image/image.h"
#include "render/gl.h"
#include "render/gl_context.h"

namespace sss {
namespace {

// Per vertex: position, normal, value, exit slope (RenderMesh; shaders/surface.vert), interleaved.
constexpr GLuint kVertexAttributes = 4;
constexpr std::size_t kVertexFloats = 3 * kVertexAttributes;
constexpr std::size_t kValueOffset = 2 * sizeof(glm::vec3);

void checkGl(const char* what) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", e);
    throw Error(std::string("OpenGL error ") + code + " while " + what);
  }
}

std::string programDefines(const ShadingOptions& s) {
  std::string d;
  switch (s.mode) {
    case ShadingMode::Sss:
      d += "#define MODE_SSS\n";
      break;
    case ShadingMode::Brdf:
      d += "#define MODE_BRDF\n";
      break;
    case ShadingMode::Irradiance:
      d += "#define MODE_IRRADIANCE\n";
      break;
    case ShadingMode::Normals:
      d += "#define MODE_NORMALS\n";
      break;
  }
  if (s.fresnel == FresnelModel::Schlick) d += "#define FRESNEL_SCHLICK\n";
  if (s.reflectFactor) d += "#define REFLECT_MIX\n";
  if (s.tonemap == Tonemap::Reinhard) d += "#define TONEMAP_REINHARD\n";
  if (s.tonemap == Tonemap::Aces) d += "#define TONEMAP_ACES\n";
  if (s.drawsUnscattered()) d += "#define UNSCATTERED\n";
  if (s.relights())
    d += "#define RELIGHT_COEFFICIENTS " + std::to_string(s.relightCoefficients) + "\n";
  return d;
}

double processCpuMs() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return (usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) * 1e3 +
         (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-3;
}

GLuint uploadCubemap(const Cubemap& cubemap) {
  const int n = cubemap.size();
  int levels = 1;
  while ((n >> levels) > 0) ++levels;
  GLuint tex = 0;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &tex);
  // 32-bit floats: a sun exceeds half floats' 65504 (the procedural sky's reaches 1.4e5), which
  // would turn its reflection into Inf and, through the tonemap, NaN.
  glTextureStorage2D(tex, levels, GL_RGBA32F, n, n);
  for (int face = 0; face < 6; ++face) {
    // Faces are stored in GL orientation, row 0 = t = 0: uploaded as they are.
    glTextureSubImage3D(tex, 0, 0, 0, face, n, n, 1, GL_RGB, GL_FLOAT,
                        cubemap.data() + static_cast<std::size_t>(face) * n * n);
  }
  glGenerateTextureMipmap(tex);
  glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  checkGl("uploading a cubemap");
  return tex;
}

}  // namespace

struct Renderer::Gl {
  GLuint surface = 0, background = 0, backDepthProgram = 0;
  GLuint meshVao = 0, emptyVao = 0, vertexBuffer = 0, indexBuffer = 0;
  GLuint relightBuffer = 0;  // per vertex g b, then T_0 ... T_(K-1) (RenderMesh), as floats
  GLuint radiance = 0, irradiance = 0;
  int radianceSize = 0;
  GLuint drawFbo = 0, resolveFbo = 0;
  GLuint drawColor = 0, drawDepth = 0, resolveColor = 0;
  GLuint backFbo = 0, backDepth = 0;  // the back faces' depth (unscattered light)

  ~Gl() {
    glDeleteProgram(surface);
    glDeleteProgram(background);
    glDeleteProgram(backDepthProgram);
    glDeleteFramebuffers(1, &backFbo);
    glDeleteTextures(1, &backDepth);
    glDeleteVertexArrays(1, &meshVao);
    glDeleteVertexArrays(1, &emptyVao);
    glDeleteBuffers(1, &vertexBuffer);
    glDeleteBuffers(1, &indexBuffer);
    glDeleteBuffers(1, &relightBuffer);
    glDeleteTextures(1, &radiance);
    glDeleteTextures(1, &irradiance);
    glDeleteFramebuffers(1, &drawFbo);
    glDeleteFramebuffers(1, &resolveFbo);
    glDeleteRenderbuffers(1, &drawColor);
    glDeleteRenderbuffers(1, &drawDepth);
    glDeleteRenderbuffers(1, &resolveColor);
  }
  GLuint outputFbo() const { return resolveFbo ? resolveFbo : drawFbo; }
};

Renderer::Renderer(const ShaderSources& shaders, const FrameOptions& frame,
                   const ShadingOptions& shading)
    : gl_(new Gl), frame_(frame), shading_(shading) {
  try {
    if (frame.width < 1 || frame.height < 1) throw Error("image size must be at least 1x1");
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    if (frame.width > maxSize || frame.height > maxSize) {
      throw Error("image size " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                  " exceeds this GL's limit of " + std::to_string(maxSize));
    }
    const std::string defines = programDefines(shading);
    gl_->surface = buildProgram(shaders, "surface.vert", "surface.frag", defines);
    gl_->background = buildProgram(shaders, "background.vert", "background.frag", defines);

    // 8-bit output is sRGB: the framebuffer encodes on store and resolves MSAA linearly.
    const GLenum colorFormat = frame.linear ? GL_RGBA32F : GL_SRGB8_ALPHA8;
    const int samples = std::max(frame.samples, 1);
    glCreateFramebuffers(1, &gl_->drawFbo);
    glCreateRenderbuffers(1, &gl_->drawColor);
    glCreateRenderbuffers(1, &gl_->drawDepth);
    glNamedRenderbufferStorageMultisample(gl_->drawColor, samples > 1 ? samples : 0, colorFormat,
                                          frame.width, frame.height);
    glNamedRenderbufferStorageMultisample(gl_->drawDepth, samples > 1 ? samples : 0,
                                          GL_DEPTH_COMPONENT24, frame.width, frame.height);
    glNamedFramebufferRenderbuffer(gl_->drawFbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                   gl_->drawColor);
    glNamedFramebufferRenderbuffer(gl_->drawFbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                   gl_->drawDepth);
    if (glCheckNamedFramebufferStatus(gl_->drawFbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      throw Error("the GL cannot render into a " + std::to_string(samples) + "-sample " +
                  (frame.linear ? "float" : "8-bit") + " framebuffer");
    }
    if (samples > 1) {
      glCreateFramebuffers(1, &gl_->resolveFbo);
      glCreateRenderbuffers(1, &gl_->resolveColor);
      glNamedRenderbufferStorage(gl_->resolveColor, colorFormat, frame.width, frame.height);
      glNamedFramebufferRenderbuffer(gl_->resolveFbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                     gl_->resolveColor);
    }
    if (shading.drawsUnscattered()) createBackDepthPass(shaders, defines);
    glCreateVertexArrays(1, &gl_->emptyVao);
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    checkGl("creating the framebuffers");
  } catch (...) {
    delete gl_;
    throw;
  }
}

Renderer::~Renderer() {
  delete gl_;
}

bool ShadingOptions::relights() const {
  return mode == ShadingMode::Sss && relightCoefficients > 0;
}

bool ShadingOptions::drawsUnscattered() const {
  return mode == ShadingMode::Sss && cullBackFaces && !reflectFactor &&
         std::max({unscatteredSigmaT.x, unscatteredSigmaT.y, unscatteredSigmaT.z}) > 0.0f;
}

// One sample per pixel: the nearest back face's depth behind each pixel, in a texture the surface
// pass reads (a sample of a multisampled pixel takes its pixel's).
void Renderer::createBackDepthPass(const ShaderSources& shaders, const std::string& defines) {
  gl_->backDepthProgram = buildProgram(shaders, "back_depth.vert", "back_depth.frag", defines);
  glCreateTextures(GL_TEXTURE_2D, 1, &gl_->backDepth);
  glTextureStorage2D(gl_->backDepth, 1, GL_DEPTH_COMPONENT32F, frame_.width, frame_.height);
  glTextureParameteri(gl_->backDepth, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(gl_->backDepth, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glCreateFramebuffers(1, &gl_->backFbo);
  glNamedFramebufferTexture(gl_->backFbo, GL_DEPTH_ATTACHMENT, gl_->backDepth, 0);
  glNamedFramebufferDrawBuffer(gl_->backFbo, GL_NONE);
  if (glCheckNamedFramebufferStatus(gl_->backFbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("the GL cannot render the back faces' depth into a texture");
}

namespace {

// The floats per vertex of a relit mesh's storage buffer: g b and `coefficients` transfer entries,
// 3 each (surface.vert, relitExitance).
std::size_t relightFloatsPerVertex(std::size_t coefficients) {
  return 3 * (coefficients + 1);
}

// A relit mesh's transfer and gains as the vertex shader reads them, g b first.
std::vector<float> relightStorage(const RenderMesh& mesh, std::size_t coefficients) {
  const std::size_t n = mesh.positions.size(), stride = relightFloatsPerVertex(coefficients);
  if (mesh.exitanceGain.size() != n || mesh.relightTransfer.size() != n * coefficients)
    throw Error("render mesh: a relit mesh's transfer or gains differ in length");
  std::vector<float> out(n * stride);
  for (std::size_t v = 0; v < n; ++v) {
    std::memcpy(&out[v * stride], &mesh.exitanceGain[v], sizeof(glm::vec3));
    std::memcpy(&out[v * stride + 3], &mesh.relightTransfer[v * coefficients],
                coefficients * sizeof(glm::vec3));
  }
  return out;
}

}  // namespace

std::size_t relightStorageBytes(std::size_t vertices, std::size_t coefficients) {
  return vertices * relightFloatsPerVertex(coefficients) * sizeof(float);
}

void Renderer::setMesh(const RenderMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  const auto sized = [n](const std::vector<glm::vec3>& v) { return v.empty() || v.size() == n; };
  if (mesh.normals.size() != n || !sized(mesh.values) || !sized(mesh.exitSlopes)) {
    throw Error("render mesh: attribute arrays differ in length");
  }
  glDeleteBuffers(1, &gl_->relightBuffer);
  gl_->relightBuffer = 0;
  if (shading_.relights()) {
    const std::size_t bytes = relightStorageBytes(n, shading_.relightCoefficients);
    const std::size_t limit = currentMaxVertexStorageBytes();
    if (bytes > limit)
      throw Error("render mesh: a relit mesh's transfer takes " + std::to_string(bytes) +
                  " bytes, over the " + std::to_string(limit) +
                  " this GL's vertex shaders read from a storage buffer");
    const std::vector<float> storage = relightStorage(mesh, shading_.relightCoefficients);
    glCreateBuffers(1, &gl_->relightBuffer);
    glNamedBufferStorage(gl_->relightBuffer,
                         std::max<std::size_t>(storage.size(), 1) * sizeof(float),
                         storage.empty() ? nullptr : storage.data(), 0);
  }
  // Interleaved position, normal, value, exit slope: 48 bytes per vertex.
  std::vector<float> interleaved(n * kVertexFloats);
  const auto at = [](const std::vector<glm::vec3>& v, std::size_t i) {
    return v.empty() ? glm::vec3(0.0f) : v[i];
  };
  for (std::size_t i = 0; i < n; ++i) {
    float* v = &interleaved[i * kVertexFloats];
    const glm::vec3 attributes[kVertexAttributes] = {mesh.positions[i], mesh.normals[i],
                                                     at(mesh.values, i), at(mesh.exitSlopes, i)};
    std::memcpy(v, attributes, sizeof attributes);
  }
  glDeleteVertexArrays(1, &gl_->meshVao);
  glDeleteBuffers(1, &gl_->vertexBuffer);
  glDeleteBuffers(1, &gl_->indexBuffer);
  glCreateBuffers(1, &gl_->vertexBuffer);
  glCreateBuffers(1, &gl_->indexBuffer);
  // Mapped for writing by setValues (a relit mesh's new light).
  glNamedBufferStorage(gl_->vertexBuffer, interleaved.size() * sizeof(float), interleaved.data(),
                       GL_MAP_WRITE_BIT);
  vertexCount_ = n;
  glNamedBufferStorage(gl_->indexBuffer, mesh.indices.size() * sizeof(uint32_t),
                       mesh.indices.data(), 0);
  glCreateVertexArrays(1, &gl_->meshVao);
  glVertexArrayVertexBuffer(gl_->meshVao, 0, gl_->vertexBuffer, 0, kVertexFloats * sizeof(float));
  for (GLuint attrib = 0; attrib < kVertexAttributes; ++attrib) {
    glEnableVertexArrayAttrib(gl_->meshVao, attrib);
    glVertexArrayAttribFormat(gl_->meshVao, attrib, 3, GL_FLOAT, GL_FALSE,
                              attrib * 3 * sizeof(float));
    glVertexArrayAttribBinding(gl_->meshVao, attrib, 0);
  }
  glVertexArrayElementBuffer(gl_->meshVao, gl_->indexBuffer);
  indexCount_ = mesh.indices.size();
  // The unscattered light's march (surface.frag): no path inside is longer than the diagonal.
  const Bounds3 bounds = boundsOf(mesh.positions);
  glProgramUniform1f(gl_->surface, glGetUniformLocation(gl_->surface, "uMaxPath"),
                     bounds.empty() ? 0.0f : glm::length(bounds.extent()));
  checkGl("uploading the mesh");
}

void Renderer::setValues(const std::vector<glm::vec3>& values) {
  if (!values.empty() && values.size() != vertexCount_)
    throw Error("render mesh: the new values differ in length from the mesh's vertices");
  if (vertexCount_ == 0) return;
  const std::size_t stride = kVertexFloats * sizeof(float);
  auto* mapped = static_cast<char*>(glMapNamedBufferRange(
      gl_->vertexBuffer, 0, GLsizeiptr(vertexCount_ * stride), GL_MAP_WRITE_BIT));
  if (!mapped) throw Error("OpenGL could not map the vertex buffer for new values");
  const glm::vec3 zero(0.0f);
  for (std::size_t i = 0; i < vertexCount_; ++i)
    std::memcpy(mapped + i * stride + kValueOffset, values.empty() ? &zero : &values[i],
                sizeof(glm::vec3));
  glUnmapNamedBuffer(gl_->vertexBuffer);
  checkGl("writing the mesh's new values");
}

void Renderer::setSmoothLight(const std::vector<glm::vec3>& coefficients) {
  if (!shading_.relights() || int(coefficients.size()) < shading_.relightCoefficients)
    throw Error("the smooth light has fewer SH coefficients than the relit mesh's transfer");
  glProgramUniform3fv(gl_->surface, glGetUniformLocation(gl_->surface, "uSmoothLight"),
                      shading_.relightCoefficients, glm::value_ptr(coefficients[0]));
  checkGl("setting the smooth light");
}

void Renderer::setEnvironment(const Cubemap& radiance, const Cubemap* irradiance) {
  if (radiance.empty()) throw Error("empty radiance cubemap");
  if (shading_.mode == ShadingMode::Brdf && (!irradiance || irradiance->empty())) {
    throw Error("the brdf mode needs an irradiance cubemap");
  }
  glDeleteTextures(1, &gl_->radiance);
  glDeleteTextures(1, &gl_->irradiance);
  gl_->radiance = uploadCubemap(radiance);
  gl_->radianceSize = radiance.size();
  gl_->irradiance = irradiance && !irradiance->empty() ? uploadCubemap(*irradiance) : 0;
}

void Renderer::setCamera(const Camera& camera) {
  camera_ = camera;
  const float aspect = static_cast<float>(frame_.width) / static_cast<float>(frame_.height);
  const glm::mat4 projection = camera.projection(aspect);
  const glm::mat4 view = camera.view();
  const glm::mat4 viewProjection = projection * view;
  const glm::mat4 inverseSky = glm::inverse(projection * glm::mat4(glm::mat3(view)));
  const float exposure = std::exp2(shading_.exposureEv);

  const GLuint s = gl_->surface;
  glProgramUniformMatrix4fv(s, glGetUniformLocation(s, "uViewProjection"), 1, GL_FALSE,
                            glm::value_ptr(viewProjection));
  glProgramUniform3fv(s, glGetUniformLocation(s, "uEye"), 1, glm::value_ptr(camera.eye));
  glProgramUniform1i(s, glGetUniformLocation(s, "uRadiance"), 0);
  glProgramUniform1i(s, glGetUniformLocation(s, "uIrradiance"), 1);
  glProgramUniform1f(s, glGetUniformLocation(s, "uEta"), shading_.eta);
  glProgramUniform1f(s, glGetUniformLocation(s, "uExitScale"), shading_.exitScale);
  glProgramUniform3fv(s, glGetUniformLocation(s, "uExitWeight"), kExitWeightNodes,
                      glm::value_ptr(shading_.exitWeight[0]));
  glProgramUniform2f(s, glGetUniformLocation(s, "uLobeMoments"), shading_.lobeMoment0,
                     shading_.lobeMoment1);
  glProgramUniform1f(s, glGetUniformLocation(s, "uReflectFactor"),
                     shading_.reflectFactor.value_or(0.0f));
  glProgramUniform3fv(s, glGetUniformLocation(s, "uAlbedo"), 1, glm::value_ptr(shading_.albedo));
  glProgramUniform1f(s, glGetUniformLocation(s, "uExposure"), exposure);
  if (gl_->backDepthProgram) {
    glProgramUniformMatrix4fv(gl_->backDepthProgram,
                              glGetUniformLocation(gl_->backDepthProgram, "uViewProjection"), 1,
                              GL_FALSE, glm::value_ptr(viewProjection));
    glProgramUniform1i(s, glGetUniformLocation(s, "uBackDepth"), 2);
    glProgramUniform2f(s, glGetUniformLocation(s, "uViewport"), float(frame_.width),
                       float(frame_.height));
    glProgramUniform3fv(s, glGetUniformLocation(s, "uSigmaT"), 1,
                        glm::value_ptr(shading_.unscatteredSigmaT));
  }

  const GLuint b = gl_->background;
  glProgramUniformMatrix4fv(b, glGetUniformLocation(b, "uInverseViewProjection"), 1, GL_FALSE,
                            glm::value_ptr(inverseSky));
  glProgramUniform1i(b, glGetUniformLocation(b, "uRadiance"), 0);
  // Background level of detail: log2 of a pixel's angle over a texel's (pi/2 per face).
  const float pixelAngle = glm::radians(camera.fovYDeg) / static_cast<float>(frame_.height);
  const float texelAngle = 1.5707963f / static_cast<float>(std::max(gl_->radianceSize, 1));
  glProgramUniform1f(b, glGetUniformLocation(b, "uLod"),
                     std::max(0.0f, std::log2(pixelAngle / texelAngle)));
  glProgramUniform1f(b, glGetUniformLocation(b, "uExposure"), exposure);
  checkGl("setting the camera");
}

void Renderer::draw() {
  // An 8-bit framebuffer is sRGB: stores encode and the resolve averages linearly, so the
  // background colour, given as display values, is decoded first. The normals view stores
  // n * 0.5 + 0.5 as it is.
  const bool srgb = !frame_.linear;
  const auto setSrgb = [](bool on) {
    on ? glEnable(GL_FRAMEBUFFER_SRGB) : glDisable(GL_FRAMEBUFFER_SRGB);
  };
  glm::vec3 bg = shading_.backgroundColor.value_or(glm::vec3(0.0f));
  if (srgb) {
    for (int c = 0; c < 3; ++c) {
      bg[c] = srgbToLinear(std::clamp(bg[c], 0.0f, 1.0f));
    }
  }
  setSrgb(srgb);
  const GLfloat clearColor[4] = {bg.r, bg.g, bg.b, 1.0f};
  const GLfloat clearDepth = 1.0f;
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl_->drawFbo);
  glViewport(0, 0, frame_.width, frame_.height);
  glDepthMask(GL_TRUE);  // clears obey the mask, and the background pass turns it off
  // The environment background writes every sample the mesh leaves: no colour clear then.
  if (shading_.backgroundColor) glClearNamedFramebufferfv(gl_->drawFbo, GL_COLOR, 0, clearColor);
  glClearNamedFramebufferfv(gl_->drawFbo, GL_DEPTH, 0, &clearDepth);
  glBindTextureUnit(0, gl_->radiance);
  glBindTextureUnit(1, gl_->irradiance);
  glEnable(GL_DEPTH_TEST);

  if (indexCount_ > 0 && gl_->backDepthProgram) drawBackDepth();
  if (indexCount_ > 0) {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl_->drawFbo);
    glBindTextureUnit(2, gl_->backDepth);
    glDepthFunc(GL_LESS);
    if (shading_.cullBackFaces) {
      glEnable(GL_CULL_FACE);
      glFrontFace(GL_CCW);
      glCullFace(GL_BACK);
    } else {
      glDisable(GL_CULL_FACE);
    }
    setSrgb(srgb && shading_.mode != ShadingMode::Normals);
    glUseProgram(gl_->surface);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, gl_->relightBuffer);
    glBindVertexArray(gl_->meshVao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(indexCount_), GL_UNSIGNED_INT, nullptr);
    setSrgb(srgb);
  }
  if (!shading_.backgroundColor) {
    // Only the pixels the mesh left at the far plane pass.
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    glUseProgram(gl_->background);
    glBindVertexArray(gl_->emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  if (gl_->resolveFbo) {
    glBlitNamedFramebuffer(gl_->drawFbo, gl_->resolveFbo, 0, 0, frame_.width, frame_.height, 0, 0,
                           frame_.width, frame_.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
}

void Renderer::drawBackDepth() {
  const GLfloat clearDepth = 1.0f;
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl_->backFbo);
  glClearNamedFramebufferfv(gl_->backFbo, GL_DEPTH, 0, &clearDepth);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glFrontFace(GL_CCW);
  glCullFace(GL_FRONT);
  glUseProgram(gl_->backDepthProgram);
  glBindVertexArray(gl_->meshVao);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(indexCount_), GL_UNSIGNED_INT, nullptr);
}

RenderedImage Renderer::readBack() {
  RenderedImage image;
  image.width = frame_.width;
  image.height = frame_.height;
  image.linear = frame_.linear;
  const std::size_t w = frame_.width, h = frame_.height;
  // The stored (encoded) bytes, not converted back to linear.
  glDisable(GL_FRAMEBUFFER_SRGB);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl_->outputFbo());
  glNamedFramebufferReadBuffer(gl_->outputFbo(), GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  // GL rows come bottom-up: flip to top row first.
  if (frame_.linear) {
    std::vector<float> rows(w * h * 3);
    glReadPixels(0, 0, frame_.width, frame_.height, GL_RGB, GL_FLOAT, rows.data());
    image.linearRgb.resize(rows.size());
    for (std::size_t y = 0; y < h; ++y) {
      std::memcpy(&image.linearRgb[y * w * 3], &rows[(h - 1 - y) * w * 3], w * 3 * sizeof(float));
    }
  } else {
    std::vector<uint8_t> rows(w * h * 3);
    glReadPixels(0, 0, frame_.width, frame_.height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
    image.srgb8.resize(rows.size());
    for (std::size_t y = 0; y < h; ++y) {
      std::memcpy(&image.srgb8[y * w * 3], &rows[(h - 1 - y) * w * 3], w * 3);
    }
  }
  checkGl("reading the image back");
  return image;
}

FrameTimings Renderer::timeFrames(int frames, int warmup) {
  FrameTimings t;
  if (frames < 1) return t;
  for (int i = 0; i < warmup; ++i) draw();
  glFinish();

  std::vector<GLuint> queries(frames);
  glCreateQueries(GL_TIME_ELAPSED, frames, queries.data());
  std::vector<double> wall(frames);
  const double cpuStart = processCpuMs();
  for (int i = 0; i < frames; ++i) {
    Stopwatch clock;
    glBeginQuery(GL_TIME_ELAPSED, queries[i]);
    draw();
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    wall[i] = clock.milliseconds();
  }
  t.cpuMs = (processCpuMs() - cpuStart) / frames;
  std::vector<double> gpu(frames);
  for (int i = 0; i < frames; ++i) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(queries[i], GL_QUERY_RESULT, &ns);
    gpu[i] = static_cast<double>(ns) * 1e-6;
  }
  glDeleteQueries(frames, queries.data());

  Stopwatch pipelined;
  for (int i = 0; i < frames; ++i) draw();
  glFinish();
  t.pipelinedMs = pipelined.milliseconds() / frames;

  t.frames = frames;
  t.medianWallMs = median(wall);
  t.minWallMs = *std::min_element(wall.begin(), wall.end());
  t.maxWallMs = *std::max_element(wall.begin(), wall.end());
  t.medianGpuMs = median(gpu);
  checkGl("timing frames");
  return t;
}

}  // namespace sss
