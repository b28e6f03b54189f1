// The kernel log-polar map (docs/foveation.md, "The mapping"; Lund eq. 3.7-3.8) with GLSL's
// native log, exp, atan, cos, sin and pow, in the reference's order of operations:
//   rho = ln(1 + r) / L;  forward u = w (K(rho) - G) / max(1 - G, 2^-24),
//   theta = atan(y', x') (+ 2 pi when < 0), v = h theta / (2 pi) (- h when >= h);
//   inverse t = G + (1 - G) (u / w), rho = K^-1(t), r = e^(L rho) - 1, theta = 2 pi v / h,
//   p = g + r (cos theta, sin theta).
// Needs frame_common.glsl.

const float TWO_PI = 6.28318548;

// K(x) on [0, 1]: x^alpha, or Meng's polynomial by Horner's rule from beta_n down, times x
float kernel_forward(float x) {
    x = clamp(x, 0.0, 1.0);
    if (P.counts.z == 0) return P.map2.y == 1.0 ? x : pow(x, P.map2.y);
    precise float sum = 0.0;
    for (int i = P.counts.w - 1; i >= 1; --i) sum = sum * x + P.beta[i];
    precise float k = sum * x;
    return k;
}

// K^-1(t): t^(1/alpha) (1/alpha rounded to float on the host), or the reference's bisection
float kernel_inverse(float t) {
    t = clamp(t, 0.0, 1.0);
    if (P.counts.z == 0) return P.map2.y == 1.0 ? t : pow(t, P.map2.z);
    float lo = 0.0, hi = 1.0, mid = 0.5;
    for (int step = 0; step < 64; ++step) {
        mid = (lo + hi) * 0.5;
        if (mid == lo || mid == hi) break;
        if (kernel_forward(mid) < t)
            lo = mid;
        else
            hi = mid;
    }
    return mid;
}

// |p - g|: x' = x - gx, y' = y - gy, sqrt(x' x' + y' y') (the reference's gaze_distance)
float gaze_distance(vec2 p) {
    precise float dx = p.x - P.map.x, dy = p.y - P.map.y;
    precise float r = sqrt(dx * dx + dy * dy);
    return r;
}

// Forward map: the buffer coordinates (u, v) of screen point p
vec2 lp_forward(vec2 p) {
    precise float dx = p.x - P.map.x, dy = p.y - P.map.y;
    precise float r = sqrt(dx * dx + dy * dy);
    const float rho = log(1.0 + r) / P.map.z;
    const float u = float(P.screen.z) * (kernel_forward(rho) - P.map.w) / P.map2.w;
    float theta = atan(dy, dx);
    if (theta < 0.0) theta += TWO_PI;
    const float h = float(P.screen.w);
    float v = h * theta / TWO_PI;
    if (v >= h) v -= h;
    return vec2(u, v);
}

// Inverse map: the screen point of buffer coordinates (u, v)
vec2 lp_inverse(vec2 uv) {
    precise float t = P.map.w + (1.0 - P.map.w) * (uv.x / float(P.screen.z));
    const float rho = kernel_inverse(t);
    precise float r = exp(P.map.z * rho) - 1.0;
    const float theta = TWO_PI * uv.y / float(P.screen.w);
    precise vec2 p = vec2(P.map.x + r * cos(theta), P.map.y + r * sin(theta));
    return p;
}

// Whether screen point p is inside the gaze circle (strictly; never without a gaze buffer)
bool inside_gaze_circle(vec2 p) { return P.launch.y != 0 && gaze_distance(p) < P.map2.x; }
