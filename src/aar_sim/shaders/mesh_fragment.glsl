#version 450 core
// Procedural texture from object-space position: no UVs, identical for both cameras, and faded
// octave by octave as the pixel footprint grows so that distant surfaces do not alias.
// With SUN defined: skylight, direct sun through the shadow map, and glare (docs/realism/sun.md).
in vec3 v_object;
in vec3 v_normal;
in float v_depth;
flat in int v_part;
uniform int u_label;
uniform int u_surface;  // 0 aircraft paint, 1 boom stripes
uniform vec3 u_sun;
#ifdef SUN
in vec3 v_tanker;
in vec4 v_sun;
flat in float v_up;
uniform vec3 u_glass_min, u_glass_max;  // [m] object frame: the windscreen (empty: none)
uniform vec3 u_camera;  // [m] camera centre, tanker frame
uniform float u_direct, u_ambient;
uniform vec3 u_specular;  // paint, metal, glass
uniform int u_shadows;
uniform sampler2DShadow u_shadow_map;
uniform float u_shadow_texel;  // 1 / map size
uniform vec2 u_shadow_bias;    // [m] one texel's size; depth per metre
#endif
layout(location = 0) out float out_intensity;
layout(location = 1) out uint out_label;
layout(location = 2) out float out_depth;

uint Hash(uvec3 v) {  // PCG3D
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  v ^= v >> 16u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  return v.x ^ v.y ^ v.z;
}
float Lattice(ivec3 i, uint salt) { return float(Hash(uvec3(i) + uvec3(salt, 7u * salt, 13u * salt)) & 0xffffu) / 65535.0; }
float ValueNoise(vec3 p, uint salt) {
  ivec3 i = ivec3(floor(p));
  vec3 f = fract(p);
  vec3 s = f * f * (3.0 - 2.0 * f);
  float x00 = mix(Lattice(i, salt), Lattice(i + ivec3(1, 0, 0), salt), s.x);
  float x10 = mix(Lattice(i + ivec3(0, 1, 0), salt), Lattice(i + ivec3(1, 1, 0), salt), s.x);
  float x01 = mix(Lattice(i + ivec3(0, 0, 1), salt), Lattice(i + ivec3(1, 0, 1), salt), s.x);
  float x11 = mix(Lattice(i + ivec3(0, 1, 1), salt), Lattice(i + ivec3(1, 1, 1), salt), s.x);
  return mix(mix(x00, x10, s.y), mix(x01, x11, s.y), s.z);
}
// Octave weight: 1 while the feature size spans several pixels, 0 once it is below one.
float Visible(float size, float footprint) { return 1.0 - smoothstep(0.5 * size, 1.5 * size, footprint); }
// 1 on a line of width w repeating every `period` along coordinate c, antialiased.
float Line(float c, float period, float w, float footprint) {
  float d = abs(fract(c / period + 0.5) - 0.5) * period;
  return (1.0 - smoothstep(0.5 * w, 0.5 * w + footprint, d)) * Visible(w, footprint);
}

void main() {
  float footprint = max(length(fwidth(v_object)), 1e-5);  // [m] per pixel
  uint salt = uint(v_part) * 97u + 11u;
  float albedo;
  if (u_surface == 1) {
    // Boom: light grey with dark bands every 1.2 m along the boom, then wear.
    float band = Line(v_object.x, 1.2, 0.4, footprint);
    albedo = mix(0.80, 0.22, band);
  } else {
    // Aircraft paint: a grey per part, a darker cheat line along the fuselage, panel lines.
    albedo = 0.70 + 0.06 * (float(Hash(uvec3(salt)) & 255u) / 255.0 - 0.5);
    albedo -= 0.30 * (1.0 - smoothstep(0.08, 0.08 + footprint, abs(v_object.z - 0.15)))
              * float(v_part <= 1);
    float panels = max(Line(v_object.x, 0.55, 0.015, footprint), Line(v_object.y, 0.85, 0.015, footprint));
    panels = max(panels, Line(v_object.z, 0.45, 0.012, footprint));
    albedo -= 0.35 * panels;
  }
  // Paint variation and grime at 1.5 m, 0.4 m, 0.12 m and 0.04 m.
  float n = 0.0;
  n += 0.16 * (ValueNoise(v_object / 1.5, salt) - 0.5);
  n += 0.16 * (ValueNoise(v_object / 0.4, salt + 1u) - 0.5) * Visible(0.4, footprint);
  n += 0.20 * (ValueNoise(v_object / 0.12, salt + 2u) - 0.5) * Visible(0.12, footprint);
  n += 0.20 * (ValueNoise(v_object / 0.04, salt + 3u) - 0.5) * Visible(0.04, footprint);
  albedo = clamp(albedo + n, 0.05, 0.95);

#ifdef SUN
  // Skylight, the sun where the shadow map sees this point, and Blinn-Phong glare; the radiance is
  // not clipped here (glare above 1 saturates in the sensor).
  vec3 nrm = normalize(v_normal);
  vec3 to_camera = normalize(u_camera - v_tanker);
  if (dot(nrm, to_camera) < 0.0) nrm = -nrm;  // the side the camera sees
  float specular = u_surface == 1 ? u_specular.y : u_specular.x;
  float shininess = u_surface == 1 ? 60.0 : 25.0;
  bool glass = all(greaterThanEqual(v_object, u_glass_min)) &&
               all(lessThanEqual(v_object, u_glass_max)) && v_up > 0.2;
  if (glass) {  // windscreen: dark tinted glass, a sharp reflection of the sun
    albedo = 0.10 + 0.2 * (albedo - 0.5);
    specular = u_specular.z;
    shininess = 500.0;
  }
  float ns = dot(nrm, u_sun);
  float lit = ns > 0.0 ? 1.0 : 0.0;
  if (u_shadows != 0 && ns > 0.0) {
    vec3 m = v_sun.xyz * 0.5 + 0.5;
    // A grazing sun needs more bias: the surface spans more depth across one texel.
    float slope = sqrt(max(1.0 - ns * ns, 0.0)) / max(ns, 0.2);
    float ref = m.z - u_shadow_bias.y * u_shadow_bias.x * (1.5 + 2.0 * slope);
    float sum = 0.0;  // 3x3 percentage-closer filter of 2x2 hardware comparisons
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        sum += texture(u_shadow_map, vec3(m.xy + vec2(i, j) * u_shadow_texel, ref));
    lit = sum / 9.0;
  }
  vec3 h = normalize(u_sun + to_camera);
  float glare = specular * pow(max(dot(nrm, h), 0.0), shininess) * lit;
  out_intensity = albedo * (u_ambient + u_direct * max(ns, 0.0) * lit) + u_direct * glare;
#else
  float shade = 0.45 + 0.55 * abs(dot(normalize(v_normal), u_sun));
  out_intensity = clamp(albedo * shade, 0.0, 1.0);
#endif
  out_label = uint(u_label);
  out_depth = v_depth;
}
