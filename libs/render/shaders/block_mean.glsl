#define START vec4(0.0)
#define COMBINE(a, b) ((a) + (b))
#define FINISH(a) ((a) / float(u_k * u_k))
