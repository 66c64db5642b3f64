#version 330 core
uniform sampler2D u_color;
uniform sampler2D u_depth;
uniform int u_k;
uniform ivec2 u_sub;
out vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy) * u_k + u_sub;
  o_color = texelFetch(u_color, p, 0);
  gl_FragDepth = texelFetch(u_depth, p, 0).r;
}
