#version 330 core
uniform sampler2DMS u_samples;
uniform int u_k;
uniform int u_sample_of[16];  // sample index of sub-pixel x + k y
out vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 sub = p % u_k;
  o_color = texelFetch(u_samples, p / u_k, u_sample_of[sub.x + u_k * sub.y]);
}
