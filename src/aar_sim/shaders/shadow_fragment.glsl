#version 450 core
// The sun's shadow map: depth only.
void main() {}
