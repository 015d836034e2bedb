#pragma once
// GLSL programs built from shaders embedded at build time (gl/shaders/*.glsl).
#include <string>
#include <vector>

namespace nf::gl {

struct EmbeddedShader {
  const char* path;  // relative to gl/shaders/
  const char* text;
};
const std::vector<EmbeddedShader>& embedded_shader_files();
std::string shader_source(const std::string& file);

// Compiles and links; throws nf::Error naming the shader file and the full info log.
// `defines` are inserted after the #version line as "#define X".
unsigned build_program(const std::string& vertex_file, const std::string& fragment_file,
                       const std::vector<std::string>& defines = {});
unsigned build_compute_program(const std::string& compute_file, const std::vector<std::string>& defines = {});

}  // namespace nf::gl
