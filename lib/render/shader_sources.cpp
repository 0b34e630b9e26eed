#include "render/shader_sources.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "render/gl.h"

namespace sss {

std::string ShaderSources::load(const std::string& name) const {
  if (directory_.empty()) {
    for (const EmbeddedShader& s : embeddedShaders()) {
      if (name == s.name) return s.text;
    }
    fail(name, "no such embedded shader");
  }
  const std::string path = directory_ + "/" + name;
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open shader file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string ShaderSources::describe(const std::string& name) const {
  return directory_.empty() ? name + " (embedded)" : directory_ + "/" + name;
}

namespace {

// A shader's or program's info log (glGetShaderiv + glGetShaderInfoLog, or the program pair),
// without trailing NULs and newlines.
std::string infoLog(GLuint object, void (*getParameter)(GLuint, GLenum, GLint*),
                    void (*getLog)(GLuint, GLsizei, GLsizei*, GLchar*)) {
  GLint length = 0;
  getParameter(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  getLog(object, length, nullptr, log.data());
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  return log;
}

GLuint compileStage(const ShaderSources& sources, GLenum stage, const std::string& file,
                    const std::string& defines) {
  // #line resets keep the driver's line numbers pointing into each file (source string 1 is
  // common.glsl, 2 is the stage's file).
  const std::string text = "#version 450 core\n" + defines + "#line 1 1\n" +
                           sources.load("common.glsl") + "\n#line 1 2\n" + sources.load(file);
  const GLuint shader = glCreateShader(stage);
  const char* ptr = text.c_str();
  glShaderSource(shader, 1, &ptr, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
    glDeleteShader(shader);
    fail(sources.describe(file),
         "GLSL compile error (source 1 = common.glsl, 2 = this file):\n" + log);
  }
  return shader;
}

}  // namespace

unsigned buildProgram(const ShaderSources& sources, const std::string& vertexFile,
                      const std::string& fragmentFile, const std::string& defines) {
  const GLuint vs = compileStage(sources, GL_VERTEX_SHADER, vertexFile, defines);
  GLuint fs = 0;
  try {
    fs = compileStage(sources, GL_FRAGMENT_SHADER, fragmentFile, defines);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    fail(sources.describe(vertexFile) + " + " + fragmentFile, "GLSL link error:\n" + log);
  }
  return program;
}

}  // namespace sss
