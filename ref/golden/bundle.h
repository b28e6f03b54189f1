// Golden cases and bundles (SPEC §11).
//
// A golden case is (scene, mode, parameters, resolution, frames). Its bundle is a directory with
// manifest.json (the case, the fovref version, compiler and flags, every buffer of every frame with
// its shape, channel names and the SHA-256 of its canonical float data, and per-frame statistics)
// and the buffers themselves: PFM for 1- and 3-channel buffers, EXR (32-bit float) otherwise, plus
// PNG previews. docs/golden.md describes the layout for GPU developers.
#pragma once

#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "ref/stage/pipeline.h"

namespace fovref {

struct GoldenCase {
    std::string name;
    std::string description;
    std::string scene;  ///< procedural name or path relative to the repository; "" = no scene
    std::string mode;
    int width = 0;
    int height = 0;
    int frames = 1;
    float time_start = 0.0f;
    float time_step = 1.0f / 30;
    Params params;
    bool operator==(const GoldenCase&) const = default;
};

/// Reads golden/cases.json. Throws fovref::Error naming the file and the offending case/key.
std::vector<GoldenCase> load_golden_cases(const std::string& path);
const GoldenCase& find_golden_case(const std::vector<GoldenCase>& cases, const std::string& name);

struct BundleOptions {
    bool previews_for_all = false;  ///< PNG for every buffer (export, --dump), else final only
    bool include_timings = false;   ///< stage wall times in the manifest (never in goldens)
    /// Buffers with more pixels are recorded by hash only (no file): keeps the repository small.
    std::size_t max_stored_pixels = std::numeric_limits<std::size_t>::max();
};

/// Loads scenes for cases once each: a procedural name, or a path relative to `base_dir`.
class SceneCache {
public:
    explicit SceneCache(std::string base_dir) : base_dir_(std::move(base_dir)) {}
    /// Null for a case without a scene.
    const Scene* get(const std::string& scene);

private:
    std::string base_dir_;
    std::map<std::string, Scene> scenes_;
};

/// Renders a case with the given width/height (the case's own when 0).
std::vector<FrameResult> render_golden_case(const GoldenCase& golden_case, const Scene* scene,
                                            const std::vector<std::string>& requested,
                                            const std::function<void(double)>& progress = {});

/// Writes a bundle into `directory`, replacing it only once everything is written (a failure
/// leaves the previous contents untouched).
void write_bundle(const std::string& directory, const GoldenCase& golden_case,
                  const std::vector<FrameResult>& frames, const BundleOptions& options);

struct ManifestBuffer {
    int frame = 0;
    std::string name;
    std::string kind;
    int width = 0, height = 0, channels = 0;
    std::vector<std::string> channel_names;
    std::string sha256;
    std::string file;  ///< "" when recorded by hash only
};

struct Manifest {
    GoldenCase golden_case;
    std::string fovref_version, compiler, flags;
    std::vector<ManifestBuffer> buffers;   ///< in frame then pipeline order
    std::vector<Counters> frame_counters;  ///< one per frame
};

Manifest read_manifest(const std::string& directory);

/// One difference between a recomputation and a stored bundle.
struct GoldenDifference {
    int frame = 0;
    std::string buffer;
    std::string what;  ///< human-readable: which pixel differs and both values, or why
};

/// Compares freshly rendered frames with the bundle in `directory`, buffer by buffer in pipeline
/// order, bit-exactly. For a differing buffer with a stored file, names the first differing
/// pixel (row-major, then channel) with both values.
std::vector<GoldenDifference> compare_with_bundle(const std::string& directory,
                                                  const std::vector<FrameResult>& frames);

/// The first element (row-major, then channel) whose bits differ; -1 when bit-equal.
std::ptrdiff_t first_difference(const Image& expected, const Image& actual);

/// "pixel (x, y) channel c: expected 0.25 (0x3e800000), got 0.2500001 (0x3e800001)".
std::string describe_difference(const Image& expected, const Image& actual, std::ptrdiff_t index,
                                const std::vector<std::string>& channel_names);

std::string fovref_version();
std::string fovref_compiler();
std::string fovref_build_flags();

}  // namespace fovref
