// Whether this build runs slowly: unoptimised (-O0) or sanitized (AddressSanitizer). The heaviest
// cases run smaller there (million, a scene of a million triangles, left to the optimised build,
// or fewer samples); the release build runs them whole. clang 14 does not define
// __SANITIZE_ADDRESS__ (g++ does): it answers __has_feature(address_sanitizer).
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define FOVREF_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FOVREF_TEST_SANITIZED 1
#endif
#endif

namespace fovref::test {

#if defined(__OPTIMIZE__) && !defined(FOVREF_TEST_SANITIZED)
constexpr bool slow_build = false;
#else
constexpr bool slow_build = true;
#endif

}  // namespace fovref::test
