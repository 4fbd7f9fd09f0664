#version 450 core
// The sun's shadow map: depth along the sun's direction, orthographic, fitted to what is drawn.
layout(location = 0) in vec3 in_position;
uniform mat4 u_clip_from_object;
void main() { gl_Position = u_clip_from_object * vec4(in_position, 1.0); }
