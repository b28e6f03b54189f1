// BMFR's bilinear taps around a reprojected pixel index (docs/bmfr.md, "Phase I": "Taps"),
// shared by the shaders of phase I, phase III and the TAA: pixel indices are integers at pixel
// centres, x0 = floor(q.x), fx = q.x - x0 (y alike), taps (x0, y0), (x0 + 1, y0), (x0, y0 + 1),
// (x0 + 1, y0 + 1) with weights (1 - fx)(1 - fy), fx (1 - fy), (1 - fx) fy, fx fy. A plain
// function of its argument (no buffers), so it reads like the docs.

struct BmfrTaps {
    ivec2 xy[4];
    float w[4];
};

// The taps of q; q is clamped to +-1e6 first (NaN: -1e6), far off the image, where every tap
// is outside anyway and the int conversion stays defined.
BmfrTaps bmfr_taps(vec2 q) {
    BmfrTaps t;
    q.x = isnan(q.x) || isinf(q.x) ? -1e6 : clamp(q.x, -1e6, 1e6);
    q.y = isnan(q.y) || isinf(q.y) ? -1e6 : clamp(q.y, -1e6, 1e6);
    const vec2 corner = floor(q);
    const vec2 f = q - corner;
    const ivec2 origin = ivec2(corner);
    t.xy[0] = origin;
    t.xy[1] = origin + ivec2(1, 0);
    t.xy[2] = origin + ivec2(0, 1);
    t.xy[3] = origin + ivec2(1, 1);
    // precise: each weight is one binary32 product of the two factors (no contraction)
    precise float w0 = (1.0 - f.x) * (1.0 - f.y);
    precise float w1 = f.x * (1.0 - f.y);
    precise float w2 = (1.0 - f.x) * f.y;
    precise float w3 = f.x * f.y;
    t.w[0] = w0;
    t.w[1] = w1;
    t.w[2] = w2;
    t.w[3] = w3;
    return t;
}

// Whether pixel index xy lies on the W x H image.
bool bmfr_inside(ivec2 xy, int width, int height) {
    return xy.x >= 0 && xy.y >= 0 && xy.x < width && xy.y < height;
}
