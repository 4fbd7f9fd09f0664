#version 450 core
// Renderer::ConvertLikeR8Attachment: the float radiance written to an 8-bit normalised
// attachment, which OpenGL converts as the renderer's mono8 output once did.
uniform sampler2D u_radiance;
layout(location = 0) out float out_intensity;
void main() { out_intensity = texelFetch(u_radiance, ivec2(gl_FragCoord.xy), 0).r; }
