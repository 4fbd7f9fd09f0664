#version 450 core
// Background pass (issue 16, docs/realism/scene.md): each pixel's ray meets the ground plane and
// the cloud layer in the tanker frame; texture in tanker x/y [m] (the same for both cameras),
// octaves faded by the pixel footprint, haze towards the sky with distance. Writes its own label
// and optical-z depth; drawn before the meshes with depth writes off, so meshes cover it.
uniform vec4 u_intrinsics;  // fx, fy, cx, cy [px]
uniform float u_height;     // [px] image height
uniform mat3 u_tanker_from_optical;
uniform vec3 u_camera;      // [m] camera centre in the tanker frame
uniform float u_sky;        // sky radiance
uniform float u_shade;      // Lambert shade of a level surface
uniform int u_kind;         // 1 sea, 2 terrain
uniform float u_ground_z;   // [m] ground plane z in the tanker frame
uniform float u_cloud_z;    // [m] cloud layer z in the tanker frame
uniform float u_coverage;   // [0, 1]
uniform float u_cloud_min_range;  // [m]
uniform float u_visibility;       // [m]
layout(location = 0) out float out_intensity;
layout(location = 1) out uint out_label;
layout(location = 2) out float out_depth;

// 2-D lattice hash (lowbias32 of a linear mix): cheaper than PCG3D, which cost a third of the speed.
float Lattice(ivec2 i, uint salt) {
  uint h = uint(i.x) * 0x8da6b343u ^ uint(i.y) * 0xd8163841u ^ salt * 0xcb1ab31fu;
  h ^= h >> 16u; h *= 0x7feb352du; h ^= h >> 15u; h *= 0x846ca68bu; h ^= h >> 16u;
  return float(h & 0xffffu) / 65535.0;
}
float ValueNoise(vec2 p, uint salt) {
  ivec2 i = ivec2(floor(p));
  vec2 f = fract(p);
  vec2 s = f * f * (3.0 - 2.0 * f);
  return mix(mix(Lattice(i, salt), Lattice(i + ivec2(1, 0), salt), s.x),
             mix(Lattice(i + ivec2(0, 1), salt), Lattice(i + ivec2(1, 1), salt), s.x), s.y);
}
float Visible(float size, float footprint) { return 1.0 - smoothstep(0.5 * size, 1.5 * size, footprint); }
// Zero-mean fbm: octaves of size base / 3^i, each faded out once it is below a pixel.
float Fbm(vec2 p, float base, int octaves, float footprint, uint salt) {
  float sum = 0.0, amp = 0.5, size = base;
  for (int i = 0; i < octaves; ++i) {
    if (footprint >= 1.5 * size) break;  // this and all finer octaves are below a pixel
    sum += amp * (ValueNoise(p / size, salt + uint(i)) - 0.5) * Visible(size, footprint);
    amp *= 0.6;
    size /= 3.0;
  }
  return sum;
}

void main() {
  float u = gl_FragCoord.x - 0.5, v = u_height - 0.5 - gl_FragCoord.y;
  vec3 d = u_tanker_from_optical * vec3((u - u_intrinsics.z) / u_intrinsics.x,
                                        (v - u_intrinsics.w) / u_intrinsics.y, 1.0);
  // Ray parameters (= optical z, as the ray's optical z is 1); clamped above the horizon so that
  // the derivatives below are taken in uniform control flow.
  float dz = min(d.z, -1e-6);
  float t_ground = (u_ground_z - u_camera.z) / dz;
  float t_cloud = (u_cloud_z - u_camera.z) / dz;
  vec2 g = u_camera.xy + t_ground * d.xy;
  vec2 c = u_camera.xy + t_cloud * d.xy;
  float foot_g = max(length(fwidth(g)), 1e-3);  // [m] per pixel
  float foot_c = max(length(fwidth(c)), 1e-3);
  if (d.z >= -1e-6) {  // above the horizon: empty sky
    out_intensity = u_sky;
    out_label = 0u;
    out_depth = 0.0;
    return;
  }
  float albedo;
  if (u_kind == 1) {  // sea: dark, swell along y and wind ripples
    albedo = 0.16 + 0.5 * Fbm(vec2(g.x, 2.5 * g.y), 400.0, 6, foot_g, 31u);
  } else {  // terrain: fields and forest patches over large-scale relief shading
    albedo = 0.34 + 0.55 * Fbm(g, 4000.0, 7, foot_g, 17u);
  }
  float len = length(d);
  float haze_g = exp(-t_ground * len / u_visibility);
  float ground = mix(u_sky, clamp(albedo, 0.02, 0.9) * u_shade, haze_g);

  float alpha = 0.0;
  if (u_coverage > 0.0) {
    float density = Fbm(c, 6000.0, 5, foot_c, 53u) + 0.5;  // about 0.5 +- 0.3
    float threshold = mix(0.85, 0.15, u_coverage);
    alpha = smoothstep(threshold - 0.05, threshold + 0.05, density) *
            smoothstep(u_cloud_min_range, 1.1 * u_cloud_min_range, length(c));
  }
  out_intensity = ground;
  if (alpha > 0.0) {
    float cloud_albedo = 0.88 + 0.4 * Fbm(c, 800.0, 4, foot_c, 71u);
    float cloud = mix(u_sky, cloud_albedo, exp(-t_cloud * len / u_visibility));
    out_intensity = mix(ground, cloud, alpha);
  }
  bool is_cloud = alpha >= 0.5;
  out_label = is_cloud ? 4u : 3u;
  out_depth = is_cloud ? t_cloud : t_ground;
}
