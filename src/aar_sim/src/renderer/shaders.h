#pragma once

// The renderer's GLSL programs: their source files (the package's shaders/ directory) and their
// compilation. Private to the library.

#include <epoxy/gl.h>

#include <string>

namespace aar_sim::render {

// Where the GLSL files are: $AAR_SIM_SHADER_DIR when set (the override, e.g. for a relocated
// install); else the package's source tree when it exists (a build from source, the devel space);
// else the install space's share/aar_sim/shaders. Both defaults are compiled in by CMake.
std::string ShaderDirectory();

// The text of a GLSL file of ShaderDirectory(), e.g. "mesh_vertex.glsl". Throws RenderError
// naming the file's path if it cannot be read.
std::string LoadShader(const std::string& file);

// The same shader source with SUN defined after its #version line.
std::string WithSun(const std::string& source);

// Compiles and links a program; throws RenderError with the compiler's log.
GLuint Link(const std::string& vertex_source, const std::string& fragment_source);

// Link() of two GLSL files of ShaderDirectory().
GLuint LinkFiles(const std::string& vertex_file, const std::string& fragment_file);

}  // namespace aar_sim::render
