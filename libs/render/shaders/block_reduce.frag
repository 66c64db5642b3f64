#version 330 core

uniform sampler2D u_source;
uniform int u_k;
out vec4 o_color;
void main() {
  ivec2 base = ivec2(gl_FragCoord.xy) * u_k;
  vec4 a = START;
  for (int y = 0; y < u_k; ++y)
    for (int x = 0; x < u_k; ++x) a = COMBINE(a, texelFetch(u_source, base + ivec2(x, y), 0));
  o_color = FINISH(a);
}
