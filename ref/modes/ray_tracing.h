// The ray tracers as render modes (Lund §3.1-3.2, Koskela §2.4; SPEC §3, §4, §8, §12), wired from
// the stages of ref/raster, ref/trace, ref/temporal and ref/bmfr:
//
// clang-format off
//   basic:         primary_visibility (rasterize, or raycast at the TAA jitter)
//                    -> shade_direct (shade: Lambert + one shadow ray per light) -> final
//                    [taa != off: -> shaded -> taa (ref/temporal/stages.h) -> final]
//   ground-truth:  primary_visibility (raycast; for --dump and goldens only)
//                  supersample (16 Halton rays per pixel, shaded, box-filtered) -> final
//   pathtrace:     primary_visibility (rasterize)
//                    -> pathtrace (1-spp paths: NEE + secondary rays, SPEC §8)   -> final
//                    [denoise=bmfr: -> radiance, emission -> the BMFR stages (ref/bmfr/stages.h)]
//   pathtrace-reference: pathtrace_reference (N jittered samples of the same paths)
//                    -> final, standard_error, the running sums (resumable)
// clang-format on
//
// Every buffer is a screen image (W x H). The BVH is built only when something traces a ray (ray
// primaries, shadow rays, paths), once per render; its build appears in the counters of the
// frame that needed it.
#pragma once

#include "ref/stage/pipeline.h"

namespace fovref {

ModeInfo basic_mode();
ModeInfo ground_truth_mode();
ModeInfo pathtrace_mode();
ModeInfo pathtrace_reference_mode();

}  // namespace fovref
