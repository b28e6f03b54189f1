// The end-to-end frame pass's shared declarations (passes/frame.cpp fills them): the frame's
// parameters (binding 0) and the record each traced texel or gaze pixel writes. Arithmetic
// helpers that the reference computes without contraction (a*b + c never fused into an FMA)
// declare their results `precise`.

// Binding 0: the frame (FrameParams in passes/frame.cpp, the same std430 layout).
layout(std430, binding = 0) readonly buffer Frame {
    vec4 camera_position;  // w: tan(vfov / 2)
    vec4 camera_right;
    vec4 camera_up;
    vec4 camera_forward;
    vec4 previous_position;  // the previous frame's camera (motion vectors); w: its tan(vfov / 2)
    vec4 previous_right;
    vec4 previous_up;
    vec4 previous_forward;
    ivec4 screen;   // W, H, the log-polar buffer's w, h
    ivec4 window;   // the gaze window: x0, y0, width, height
    ivec4 counts;   // lights, frame number, kernel (0: x^alpha, 1: polynomial), beta count
    ivec4 launch;   // 0: log-polar texels, 1: gaze-window pixels; has a gaze buffer
    vec4 map;       // gaze x, gaze y, L = ln(1 + R), G
    vec4 map2;      // r_G, alpha, 1 / alpha, max(1 - G, 2^-24)
    vec4 scene;     // shadow-ray offset (1e-4 x scene scale), box padding, shadow t_max, 0
    float beta[20];
} P;

// The record of one texel (log-polar buffer) or pixel (gaze window), RECORD floats each.
const int RECORD = 25;
const int R_VIEW_DEPTH = 0, R_HIT_DISTANCE = 1, R_POSITION = 2, R_SHADING_NORMAL = 5,
          R_GEOMETRIC_NORMAL = 8, R_ALBEDO = 11, R_MATERIAL = 14, R_PRIMITIVE = 15, R_MOTION = 16,
          R_VALID = 18, R_SCREEN_POINT = 19, R_COLOR = 21, R_STATUS = 24;
// R_STATUS: what the texel or pixel did
const float TRACED = 0.0, OFF_SCREEN = 1.0, INSIDE_GAZE = 2.0, OUTSIDE_CIRCLE = 3.0;

// a . b summed left to right, without contraction (glm's dot)
float dot3(vec3 a, vec3 b) {
    precise float d = a.x * b.x + a.y * b.y + a.z * b.z;
    return d;
}

// glm's cross, without contraction
vec3 cross3(vec3 a, vec3 b) {
    precise vec3 c = vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
    return c;
}
