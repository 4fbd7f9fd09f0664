#include "renderer/shaders.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "aar_sim/renderer.h"

namespace aar_sim::render {
namespace {

GLuint Compile(GLenum type, const std::string& source) {
  const GLuint shader = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
    throw RenderError(std::string("shader does not compile: ") + log);
  }
  return shader;
}

}  // namespace

std::string ShaderDirectory() {
  if (const char* dir = std::getenv("AAR_SIM_SHADER_DIR"); dir && *dir) return dir;
  if (std::filesystem::is_directory(AAR_SIM_SHADER_SOURCE_DIR)) return AAR_SIM_SHADER_SOURCE_DIR;
  return AAR_SIM_SHADER_INSTALL_DIR;
}

std::string LoadShader(const std::string& file) {
  const std::string path = ShaderDirectory() + "/" + file;
  std::ifstream in(path);
  if (!in) {
    throw RenderError("cannot read the shader file " + path +
                      " (set AAR_SIM_SHADER_DIR to the directory of aar_sim's shaders)");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A program of its own, so that the ideal world's program stays the one whose images the tests
// compare bit for bit.
std::string WithSun(const std::string& source) {
  const size_t line_end = source.find('\n') + 1;
  return source.substr(0, line_end) + "#define SUN 1\n" + source.substr(line_end);
}

GLuint Link(const std::string& vertex_source, const std::string& fragment_source) {
  const GLuint vs = Compile(GL_VERTEX_SHADER, vertex_source);
  const GLuint fs = Compile(GL_FRAGMENT_SHADER, fragment_source);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  glDeleteShader(vs);
  glDeleteShader(fs);
  if (!linked) throw RenderError("shader program does not link");
  return program;
}

GLuint LinkFiles(const std::string& vertex_file, const std::string& fragment_file) {
  return Link(LoadShader(vertex_file), LoadShader(fragment_file));
}

}  // namespace aar_sim::render
