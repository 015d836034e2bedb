#include "gl/shader.h"

#include <epoxy/gl.h>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::gl {
namespace {

std::string with_defines(const std::string& src, const std::vector<std::string>& defines) {
  if (defines.empty()) return src;
  std::string extra;
  for (const auto& d : defines) extra += "#define " + d + "\n";
  const auto eol = src.find('\n');
  if (src.rfind("#version", 0) == 0 && eol != std::string::npos) return src.substr(0, eol + 1) + extra + src.substr(eol + 1);
  return extra + src;
}

GLuint compile(GLenum stage, const std::string& file, const std::vector<std::string>& defines) {
  const std::string src = with_defines(shader_source(file), defines);
  GLuint s = glCreateShader(stage);
  const char* p = src.c_str();
  glShaderSource(s, 1, &p, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 1), '\0');
    glGetShaderInfoLog(s, len, nullptr, log.data());
    glDeleteShader(s);
    fail(fmt::format("GLSL: compiling gl/shaders/{} failed:\n{}", file, log));
  }
  return s;
}

GLuint link(const std::vector<GLuint>& shaders, const std::string& what) {
  GLuint prog = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(prog, s);
  glLinkProgram(prog);
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(prog, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 1), '\0');
    glGetProgramInfoLog(prog, len, nullptr, log.data());
    glDeleteProgram(prog);
    fail(fmt::format("GLSL: linking {} failed:\n{}", what, log));
  }
  return prog;
}

}  // namespace

std::string shader_source(const std::string& file) {
  for (const auto& f : embedded_shader_files())
    if (file == f.path) return f.text;
  fail(fmt::format("shader '{}' is not embedded in this binary", file));
}

unsigned build_program(const std::string& vertex_file, const std::string& fragment_file,
                       const std::vector<std::string>& defines) {
  return link({compile(GL_VERTEX_SHADER, vertex_file, defines), compile(GL_FRAGMENT_SHADER, fragment_file, defines)},
              vertex_file + " + " + fragment_file);
}

unsigned build_compute_program(const std::string& compute_file, const std::vector<std::string>& defines) {
  return link({compile(GL_COMPUTE_SHADER, compute_file, defines)}, compute_file);
}

}  // namespace nf::gl
