#include "ref/log_polar/kernel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ref/core/dmath.h"
#include "ref/core/error.h"

namespace fovref {

namespace {

std::string number_text(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
    return text;
}

}  // namespace

Kernel power_kernel(float alpha, const std::string& what) {
    if (!std::isfinite(alpha) || alpha < 1.0f || alpha > 64.0f)
        throw Error(what + ": kernel exponent " + number_text(alpha) +
                    " is outside [1, 64] (K(x) = x^alpha must not pull samples towards the gaze "
                    "point, SPEC §5.1)");
    Kernel k;
    k.kind = KernelKind::power;
    k.alpha = alpha;
    return k;
}

Kernel polynomial_kernel(const std::vector<float>& beta, const std::string& what) {
    if (beta.size() < 2 || beta.size() > 17)
        throw Error(what + ": a polynomial kernel needs beta_0..beta_n with 1 <= n <= 16, got " +
                    std::to_string(beta.size()) + " coefficient(s)");
    double sum = 0.0;
    for (std::size_t i = 0; i < beta.size(); ++i) {
        if (!std::isfinite(beta[i]))
            throw Error(what + ": beta_" + std::to_string(i) + " is not a finite number");
        sum += beta[i];
    }
    if (beta[0] != 0.0f)
        throw Error(what + ": beta_0 must be 0 (K(0) = 0), got " + number_text(beta[0]));
    if (std::fabs(sum - 1.0) > 1e-5)
        throw Error(what + ": the coefficients must sum to 1 (K(1) = 1), they sum to " +
                    number_text(static_cast<float>(sum)));
    // K'(x) = sum i beta_i x^(i-1) >= 0 on [0, 1], on a grid of 65537 points.
    for (int k = 0; k <= 65536; ++k) {
        const double x = k / 65536.0;
        double derivative = 0.0;
        for (std::size_t i = beta.size() - 1; i >= 1; --i)
            derivative = derivative * x + static_cast<double>(i) * beta[i];
        if (derivative < 0.0)
            throw Error(what + ": K'(" + number_text(static_cast<float>(x)) +
                        ") = " + number_text(static_cast<float>(derivative)) +
                        " < 0: the kernel must be monotone on [0, 1] (SPEC §5.1)");
    }
    Kernel kernel;
    kernel.kind = KernelKind::polynomial;
    kernel.beta = beta;
    return kernel;
}

namespace {

constexpr float half_pi = 1.5707964f;       // pi/2 rounded to binary32
constexpr float two_over_pi = 0.63661975f;  // 2/pi rounded to binary32
constexpr float e_minus_1 = 1.7182817f;     // e - 1 rounded to binary32

float unit(float v) { return std::clamp(v, 0.0f, 1.0f); }

}  // namespace

Kernel named_kernel(KernelKind kind) {
    FOVREF_CHECK(kind == KernelKind::sine || kind == KernelKind::exponential,
                 "named_kernel: sine or exponential");
    Kernel k;
    k.kind = kind;
    return k;
}

float kernel_forward(const Kernel& kernel, float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    if (kernel.kind == KernelKind::power)
        return kernel.alpha == 1.0f ? x : dm::pow(x, kernel.alpha);
    if (kernel.kind == KernelKind::sine) return unit(dm::sin(x * half_pi));
    if (kernel.kind == KernelKind::exponential) return unit((dm::exp(x) - 1.0f) / e_minus_1);
    // Horner from beta_n down to beta_1, then the final factor x (beta_0 = 0).
    float sum = 0.0f;
    for (std::size_t i = kernel.beta.size() - 1; i >= 1; --i) sum = sum * x + kernel.beta[i];
    return sum * x;
}

float kernel_inverse(const Kernel& kernel, float t) {
    t = std::clamp(t, 0.0f, 1.0f);
    if (kernel.kind == KernelKind::power)
        return kernel.alpha == 1.0f ? t : dm::pow(t, 1.0f / kernel.alpha);
    if (kernel.kind == KernelKind::sine) return unit(dm::asin(t) * two_over_pi);
    if (kernel.kind == KernelKind::exponential) return unit(dm::log(1.0f + t * e_minus_1));
    float lo = 0.0f, hi = 1.0f, mid = 0.5f;
    for (int step = 0; step < 64; ++step) {
        mid = (lo + hi) * 0.5f;
        if (mid == lo || mid == hi) break;
        if (kernel_forward(kernel, mid) < t)
            lo = mid;
        else
            hi = mid;
    }
    return mid;
}

float kernel_derivative(const Kernel& kernel, float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    if (kernel.kind == KernelKind::power)
        return kernel.alpha == 1.0f ? 1.0f : kernel.alpha * dm::pow(x, kernel.alpha - 1.0f);
    if (kernel.kind == KernelKind::sine) return half_pi * dm::cos(x * half_pi);
    if (kernel.kind == KernelKind::exponential) return dm::exp(x) / e_minus_1;
    float sum = 0.0f;
    for (std::size_t i = kernel.beta.size() - 1; i >= 1; --i)
        sum = sum * x + static_cast<float>(i) * kernel.beta[i];
    return sum;
}

std::string kernel_text(const Kernel& kernel) {
    if (kernel.kind == KernelKind::power) return "x^" + number_text(kernel.alpha);
    if (kernel.kind == KernelKind::sine) return "sin(x pi/2)";
    if (kernel.kind == KernelKind::exponential) return "(e^x - 1)/(e - 1)";
    std::string text = "poly(";
    for (std::size_t i = 0; i < kernel.beta.size(); ++i)
        text += (i ? ", " : "") + number_text(kernel.beta[i]);
    return text + ")";
}

}  // namespace fovref
