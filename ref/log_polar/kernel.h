// The kernel function K of kernel log-polar foveation (Meng 2018 eq. 2.9, Lund §3.3.2; SPEC §5.1):
// a monotone map of [0, 1] onto itself with K(0) = 0 and K(1) = 1 that redistributes the log-polar
// buffer's columns along the radius. The forward map (screen -> buffer) applies K, the inverse
// (buffer -> screen) applies K^-1, so K(x) = x^alpha with alpha > 1 moves samples away from the
// gaze point (Lund eq. 3.7-3.8; Meng's eq. 2.10 and Algorithms 1-2 swap the two and are not
// followed). docs/foveation.md, "Kernel".
//
// Four kinds:
//   power       K(x) = x^alpha, alpha >= 1 (alpha = 1: the classic log-polar map, K = identity)
//   polynomial  K(x) = sum_{i=1..n} beta_i x^i (Meng eq. 2.9), with beta_0 = 0, sum beta = 1 and
//               K'(x) >= 0 on [0, 1], all checked when the kernel is made (kernel_from_betas).
//   sine        K(x) = sin(x pi/2) (named in Meng §2.1 beside eq. 2.9; concave: it moves
//               columns towards the gaze)
//   exponential K(x) = (e^x - 1) / (e - 1) (likewise named there; convex, mildly)
//
// Arithmetic: binary32. x^alpha and t^(1/alpha) use the deterministic pow (ref/core/dmath.h);
// the polynomial is evaluated by Horner's rule from the highest coefficient down; its inverse is a
// bisection (kernel_inverse). The sine and exponential kernels use dm::sin, asin, cos, exp, log
// in closed form (kernel_forward, kernel_inverse), with pi/2 = 1.5707964f, 2/pi = 0.63661975f,
// e - 1 = 1.7182817f (binary32 constants), and their results clamped to [0, 1].
#pragma once

#include <string>
#include <vector>

namespace fovref {

enum class KernelKind { power, polynomial, sine, exponential };

struct Kernel {
    KernelKind kind = KernelKind::power;
    float alpha = 1.0f;       ///< power kernel's exponent (>= 1)
    std::vector<float> beta;  ///< polynomial kernel's beta_0..beta_n (beta_0 = 0)
    bool operator==(const Kernel&) const = default;

    bool identity() const { return kind == KernelKind::power && alpha == 1.0f; }
};

/// K(x) = x^alpha. Throws fovref::Error naming `what` unless 1 <= alpha <= 64 and finite.
Kernel power_kernel(float alpha, const std::string& what = "alpha");

/// K(x) = sum beta_i x^i from beta_0..beta_n. Throws fovref::Error naming `what` when a value is
/// not finite, beta_0 != 0, n < 1 or n > 16, |sum beta - 1| > 1e-5, or K' < 0 somewhere on
/// [0, 1] (K' evaluated in binary64 at the 65537 points k/65536, k = 0..65536; a polynomial of
/// degree <= 16 with K' >= 0 at all of them and a dip below 0 between two of them would need
/// coefficients far beyond any useful kernel).
Kernel polynomial_kernel(const std::vector<float>& beta, const std::string& what = "beta");

/// K(x) = sin(x pi/2) (`sine`) or (e^x - 1) / (e - 1) (`exponential`): Meng's other two kernels.
Kernel named_kernel(KernelKind kind);

/// K(x) for x in [0, 1] (values outside are clamped first). Power: x^alpha (x itself for
/// alpha = 1, so the classic map has no pow in it); polynomial: Horner from beta_n down; sine:
/// sin(x * (pi/2)); exponential: (exp(x) - 1) / (e - 1); both clamped to [0, 1].
float kernel_forward(const Kernel& kernel, float x);

/// K^-1(t) for t in [0, 1] (clamped first). Power: t^(1/alpha) with 1/alpha rounded to float
/// (t itself for alpha = 1). Polynomial: bisection on [lo, hi] = [0, 1] in float, at most 64 steps:
/// mid = (lo + hi) / 2; stop when mid equals lo or hi; K(mid) < t -> lo = mid, else hi = mid; the
/// result is the last mid (SPEC §5.1). Sine: asin(t) * (2/pi); exponential: log(1 + t (e - 1));
/// both clamped to [0, 1].
float kernel_inverse(const Kernel& kernel, float t);

/// K'(x) for x in [0, 1] (clamped first): alpha x^(alpha - 1) (1 for alpha = 1), or
/// sum i beta_i x^(i-1) by Horner's rule from the highest coefficient down, or (pi/2) cos(x pi/2),
/// or exp(x) / (e - 1). Used by the mip
/// resolve's level (ref/log_polar/mip_resolve.h).
float kernel_derivative(const Kernel& kernel, float x);

/// "x^3", "poly(0, 0.5, 0.5)": for notes and reports.
std::string kernel_text(const Kernel& kernel);

}  // namespace fovref
