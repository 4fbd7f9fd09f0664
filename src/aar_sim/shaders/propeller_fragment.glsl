#version 450 core
// Propellers (issue 16): each pixel's coverage is the fraction of the exposure during which some
// blade lies over it (blades of angular half width atan(chord / 2r) turning from u_angle through
// u_swept). Pass 0 blends the radiance by that coverage; pass 1 writes the label and depth where
// it is at least one half.
in vec2 v_disc;
in float v_depth;
uniform float u_radius, u_hub, u_half_chord, u_angle, u_swept;
uniform int u_blades;
uniform vec2 u_blade;  // radiance of the blade and of its painted tip
uniform int u_pass;
layout(location = 0) out vec4 out_color;
layout(location = 1) out uint out_label;
layout(location = 2) out float out_depth;
const float kTwoPi = 6.28318530718;
void main() {
  float r = length(v_disc);
  if (r > u_radius || r < u_hub) discard;
  float period = kTwoPi / float(u_blades);
  float a = atan(u_half_chord, r);
  float d = mod(atan(v_disc.y, v_disc.x) - u_angle, period);  // behind blade 0's start, [0, period)
  float cover;
  if (u_swept <= 1e-6) {
    cover = min(d, period - d) < a ? 1.0 : 0.0;
  } else if (u_swept >= kTwoPi) {
    cover = min(2.0 * a / period, 1.0);
  } else {  // the blade centres sweep [0, u_swept]: covered while within a of d + m period
    float total = 0.0;
    for (int m = -1; m < 64; ++m) {
      float c = d + float(m) * period;
      if (c - a > u_swept) break;
      total += max(0.0, min(c + a, u_swept) - max(c - a, 0.0));
    }
    cover = min(total / u_swept, 1.0);
  }
  if (cover <= 0.0 || (u_pass == 1 && cover < 0.5)) discard;
  out_color = vec4(r > u_radius - 0.12 ? u_blade.y : u_blade.x, 0.0, 0.0, cover);
  out_label = 5u;
  out_depth = v_depth;
}
