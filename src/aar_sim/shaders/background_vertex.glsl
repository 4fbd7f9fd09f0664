#version 450 core
// Background pass (issue 16, docs/realism/scene.md): one triangle over the viewport; the
// fragment shader does the work.
void main() {  // one triangle over the whole viewport
  vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
  gl_Position = vec4(p, 0.999, 1.0);
}
