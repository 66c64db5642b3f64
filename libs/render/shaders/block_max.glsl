#define START vec4(0.0)
#define COMBINE(a, b) max(a, b)
#define FINISH(a) (a)
