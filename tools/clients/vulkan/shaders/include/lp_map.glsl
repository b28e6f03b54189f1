// The kernel log-polar map between the screen and the log-polar buffer (docs/foveation.md, "The
// mapping" and "Kernel"; Lund eq. 3.7-3.8, Meng eq. 2.9), written from the docs with GLSL's
// native log, exp, log2, atan, cos, sin and pow, in the reference's order of operations
// (ref/log_polar/map.cpp, kernel.cpp). Screen point p, gaze g, r = |p - g|:
//   rho = ln(1 + r) / L
//   forward   u = w (K(rho) - G) / max(1 - G, 2^-24)
//             theta = atan(y', x') (+ 2 pi when < 0), v = h theta / (2 pi) (- h when >= h)
//   inverse   rho = K^-1(G + (1 - G) (u / w)), r = e^(L rho) - 1, theta = 2 pi v / h,
//             p = g + r (cos theta, sin theta)
//   Jacobian  s_u = w K'(rho) / ((1 + r) L max(1 - G, 2^-24)), s_v = h / (2 pi r)
// The constants (R, L = ln(1 + R), r_G, G, 1/alpha) come from the host, computed once per frame
// as a renderer would. `precise` keeps every a b + c of the reference unfused (the reference is
// built with -ffp-contract=off). Include it and bind an LpMap, e.g.
//   layout(std430, binding = 0) readonly buffer MapBlock { LpMap map; };
// No #ifdef INJECT_BUG here: this map is shared by several passes.

// The map of one frame (std430: 31 words; the host mirrors it word for word).
struct LpMap {
    float gaze_x, gaze_y;            // g, screen pixels
    int screen_width, screen_height; // W, H (one eye's in stereo)
    int width, height;               // the buffer: w columns (u), h rows (v)
    float radius_max;                // R
    float log_radius_max;            // L = ln(1 + R)
    float gaze_radius;               // r_G (0: no gaze buffer)
    float composite;                 // G = min(1, K(ln(1 + r_G) / L)) (0: no gaze buffer)
    int kernel_kind;                 // 0: x^alpha, 1: polynomial sum beta_i x^i
    float alpha;                     // the power kernel's exponent
    float inverse_alpha;             // 1 / alpha, rounded to float
    int beta_count;                  // n + 1 coefficients beta_0..beta_n (polynomial)
    float beta[17];                  // beta_0..beta_16 (beta_0 = 0; n <= 16)
};

const float LP_TWO_PI = 6.28318530717958647692;

// |p - g| = sqrt(x' x' + y' y') (the reference's gaze_distance)
float lp_gaze_distance(LpMap m, vec2 p) {
    precise float dx = p.x - m.gaze_x, dy = p.y - m.gaze_y;
    precise float r2 = dx * dx + dy * dy;
    return sqrt(r2);
}

// K(x) for x clamped to [0, 1]: x^alpha (x itself for alpha = 1), or Horner from beta_n down,
// times x
float lp_kernel_forward(LpMap m, float x) {
    x = clamp(x, 0.0, 1.0);
    if (m.kernel_kind == 0) return m.alpha == 1.0 ? x : pow(x, m.alpha);
    precise float sum = 0.0;
    for (int i = m.beta_count - 1; i >= 1; --i) sum = sum * x + m.beta[i];
    precise float k = sum * x;
    return k;
}

// K^-1(t) for t clamped to [0, 1]: t^(1/alpha), or the reference's bisection (at most 64 steps,
// stopping when the midpoint equals an end)
float lp_kernel_inverse(LpMap m, float t) {
    t = clamp(t, 0.0, 1.0);
    if (m.kernel_kind == 0) return m.alpha == 1.0 ? t : pow(t, m.inverse_alpha);
    float lo = 0.0, hi = 1.0, mid = 0.5;
    for (int step = 0; step < 64; ++step) {
        mid = (lo + hi) * 0.5;
        if (mid == lo || mid == hi) break;
        if (lp_kernel_forward(m, mid) < t)
            lo = mid;
        else
            hi = mid;
    }
    return mid;
}

// K'(x) for x clamped to [0, 1]: alpha x^(alpha - 1), or sum i beta_i x^(i-1) by Horner
float lp_kernel_derivative(LpMap m, float x) {
    x = clamp(x, 0.0, 1.0);
    if (m.kernel_kind == 0) return m.alpha == 1.0 ? 1.0 : m.alpha * pow(x, m.alpha - 1.0);
    precise float sum = 0.0;
    for (int i = m.beta_count - 1; i >= 1; --i) sum = sum * x + float(i) * m.beta[i];
    return sum;
}

// max(1 - G, 2^-24): the composite renormalisation's guarded denominator
float lp_composite_span(LpMap m) { return max(1.0 - m.composite, 1.0 / 16777216.0); }

// Forward map (screen -> buffer): the continuous buffer coordinates (u, v) of screen point p
vec2 lp_forward(LpMap m, vec2 p) {
    precise float dx = p.x - m.gaze_x, dy = p.y - m.gaze_y;
    precise float r2 = dx * dx + dy * dy;
    const float r = sqrt(r2);
    const float rho = log(1.0 + r) / m.log_radius_max;
    const float k = lp_kernel_forward(m, rho);
    const float u = float(m.width) * (k - m.composite) / lp_composite_span(m);
    float theta = atan(dy, dx);
    if (theta < 0.0) theta += LP_TWO_PI;
    const float h = float(m.height);
    float v = h * theta / LP_TWO_PI;
    if (v >= h) v -= h;
    return vec2(u, v);
}

// The inverse map's radius of column coordinate u: e^(L K^-1(G + (1 - G) (u / w))) - 1
float lp_inverse_radius(LpMap m, float u) {
    precise float t = m.composite + (1.0 - m.composite) * (u / float(m.width));
    const float rho = lp_kernel_inverse(m, t);
    return exp(m.log_radius_max * rho) - 1.0;
}

// The inverse map's angle of row coordinate v: 2 pi v / h
float lp_inverse_angle(LpMap m, float v) { return LP_TWO_PI * v / float(m.height); }

// Inverse map (buffer -> screen): the screen point of buffer coordinates (u, v)
vec2 lp_inverse(LpMap m, vec2 uv) {
    const float r = lp_inverse_radius(m, uv.x);
    const float theta = lp_inverse_angle(m, uv.y);
    precise vec2 p = vec2(m.gaze_x + r * cos(theta), m.gaze_y + r * sin(theta));
    return p;
}

// Buffer texels per screen pixel at distance r > 0 from the gaze (the mip level's footprint):
// (radial s_u = du/dr, angular s_v = dv per pixel along the circle)
vec2 lp_texels_per_pixel(LpMap m, float r) {
    const float rho = log(1.0 + r) / m.log_radius_max;
    const float radial = float(m.width) * lp_kernel_derivative(m, rho) /
                         ((1.0 + r) * m.log_radius_max * lp_composite_span(m));
    const float angular = float(m.height) / (LP_TWO_PI * r);
    return vec2(radial, angular);
}

// Whether screen point p lies in [0, W) x [0, H) (false for NaN)
bool lp_on_screen(LpMap m, vec2 p) {
    return p.x >= 0.0 && p.x < float(m.screen_width) && p.y >= 0.0 && p.y < float(m.screen_height);
}
