#version 450 core
// Meshes (the receiver, the boom): object frame to the camera's clip space. Compiled twice:
// as it is (the ideal world) and with SUN defined (the sun's lighting and shadows).
layout(location = 0) in vec3 in_position;  // object frame [m]
layout(location = 1) in vec3 in_normal;    // object frame
layout(location = 2) in float in_part;
uniform mat4 u_optical_from_object;
#ifdef SUN
uniform vec3 u_tanker_offset;    // [m] the object's origin in the tanker frame
uniform mat4 u_sun_from_object;  // into the shadow map's clip space
out vec3 v_tanker;
out vec4 v_sun;
flat out float v_up;  // the face normal's object z
#endif
uniform mat3 u_tanker_from_object;
uniform vec4 u_projection;  // 2fx/w, 2(cx+0.5)/w - 1, 2fy/h, 1 - 2(cy+0.5)/h
uniform vec2 u_depth;       // z_clip = a z + b
out vec3 v_object;
out vec3 v_normal;
out float v_depth;
flat out int v_part;
void main() {
  vec3 p = (u_optical_from_object * vec4(in_position, 1.0)).xyz;
  v_object = in_position;
  v_normal = u_tanker_from_object * in_normal;
  v_depth = p.z;
  v_part = int(in_part + 0.5);
#ifdef SUN
  v_tanker = u_tanker_from_object * in_position + u_tanker_offset;
  v_sun = u_sun_from_object * vec4(in_position, 1.0);
  v_up = in_normal.z;
#endif
  gl_Position = vec4(u_projection.x * p.x + u_projection.y * p.z,
                     -u_projection.z * p.y + u_projection.w * p.z,
                     u_depth.x * p.z + u_depth.y, p.z);
}
