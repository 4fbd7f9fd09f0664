#version 450 core
// Propellers (issue 16): a disc quad in the propeller's plane (propeller_fragment.glsl).
uniform mat4 u_optical_from_disc;
uniform vec4 u_projection;
uniform vec2 u_depth;
uniform float u_radius;
out vec2 v_disc;  // [m] disc y, z
out float v_depth;
const vec2 kCorner[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1),
                                vec2(-1, 1));
void main() {
  v_disc = u_radius * kCorner[gl_VertexID];
  vec3 p = (u_optical_from_disc * vec4(0.0, v_disc, 1.0)).xyz;
  v_depth = p.z;
  gl_Position = vec4(u_projection.x * p.x + u_projection.y * p.z,
                     -u_projection.z * p.y + u_projection.w * p.z,
                     u_depth.x * p.z + u_depth.y, p.z);
}
