// The SIMD paths' CPU features, and one switch for them all. Every SIMD path in the library
// (AVX, AVX2, F16C) gives its scalar reference's bits and runs only where the CPU has the feature
// and `simd_allowed()`; the scalar reference is the readable code a debugger steps through.
// `fovref render --scalar` turns the SIMD paths off for the whole process, and `probe
// --debugger` puts it in the command line it prints, so that a breakpoint in a per-pixel
// function (which a SIMD path does not call for the pixels it covers) stops at every pixel.
#pragma once

namespace fovref {

/// Whether the SIMD paths may run (true unless set_simd_allowed(false)).
bool simd_allowed();
/// Turns the SIMD paths on or off for the whole process (the results are the same bits).
void set_simd_allowed(bool allowed);

/// Whether this CPU has AVX (eight float lanes), and AVX2.
bool cpu_has_avx();
bool cpu_has_avx2();

}  // namespace fovref
