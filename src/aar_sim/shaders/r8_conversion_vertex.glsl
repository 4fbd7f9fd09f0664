#version 450 core
// Renderer::ConvertLikeR8Attachment: one triangle over the viewport.
void main() {  // one triangle over the whole viewport
  gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0);
}
