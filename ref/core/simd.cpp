#include "ref/core/simd.h"

#include <atomic>

namespace fovref {

namespace {

std::atomic<bool> allowed{true};

}  // namespace

bool simd_allowed() { return allowed.load(std::memory_order_relaxed); }

void set_simd_allowed(bool value) { allowed.store(value, std::memory_order_relaxed); }

bool cpu_has_avx() {
    static const bool has = __builtin_cpu_supports("avx") != 0;
    return has;
}

bool cpu_has_avx2() {
    static const bool has = __builtin_cpu_supports("avx2") != 0;
    return has;
}

}  // namespace fovref
