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
#include <memory>
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
    /// "all": every frame's buffers stored as files; "last-frame": only the last frame's, the
    /// earlier frames' recorded by their SHA-256 alone: keeps long sequences small in the
    /// repository (`golden export` writes every file, to compare pixels).
    std::string files = "all";
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
    /// Also a raw copy of every stored buffer whose channel count PFM cannot hold (not 1 or 3):
    /// f000_name.f32, binary32 little-endian, channels interleaved, top row first, recorded as
    /// "raw_file" (for clients without an EXR reader, such as the Vulkan client).
    bool raw_copies = false;
    /// Every parameter of the case's mode with the value the render used (the case's, else the
    /// mode's default), written as the manifest's "effective_params" when not empty (`golden
    /// export`): a port reads its settings from the bundle instead of the mode's defaults.
    std::map<std::string, std::string> effective_params;
};

/// Loads scenes for cases once each: a procedural name, an absolute path, or a path relative to
/// `base_dir` (the repository root for golden/cases.json; never the current directory).
class SceneCache {
public:
    explicit SceneCache(std::string base_dir) : base_dir_(std::move(base_dir)) {}
    /// Null for a case without a scene.
    const Scene* get(const std::string& scene);

private:
    std::string base_dir_;
    std::map<std::string, Scene> scenes_;
};

/// The render settings of a case.
RenderSettings case_settings(const GoldenCase& golden_case,
                             const std::vector<std::string>& requested,
                             const std::function<void(double)>& progress = {});

/// Writes a bundle frame by frame into a staging directory beside the target and swaps it in on
/// commit(), so a failure (or an exception before commit) leaves the target as it was and no
/// staging directory behind. The target must be absent, an empty directory, or a fovref bundle
/// (a directory whose manifest.json says "format": "fovref-bundle-1"): anything else is refused,
/// never overwritten.
class BundleWriter {
public:
    BundleWriter(const std::string& directory, GoldenCase golden_case, BundleOptions options);
    ~BundleWriter();
    BundleWriter(const BundleWriter&) = delete;
    BundleWriter& operator=(const BundleWriter&) = delete;

    /// Adds a frame's buffers (only those named in `only`, when given) and its counters and
    /// stage runs. The frame is left as it is: its buffers go back to the stages that recycle or
    /// carry them (FrameContext::hand_back).
    void add_frame(const FrameResult& frame, const std::vector<std::string>* only = nullptr);
    /// Exports `scene` (OBJ + MTL + textures + scene.json, export_scene) into the bundle's
    /// `relative_directory`, recorded in the manifest as "scene_export": the geometry a GPU
    /// implementation loads to render the case (triangle k of the OBJ is primitive id k, MTL
    /// material k is material id k).
    void add_scene(const Scene& scene, const std::string& relative_directory);
    void commit();

private:
    struct State;
    std::unique_ptr<State> state_;
};

/// Writes a whole bundle at once (BundleWriter with every frame).
void write_bundle(const std::string& directory, const GoldenCase& golden_case,
                  const std::vector<FrameResult>& frames, const BundleOptions& options);

/// Rows per block for the per-block hashes of a hash-only buffer: at most 256 blocks.
int hash_block_rows(int height);

struct ManifestBuffer {
    int frame = 0;
    std::string name;
    std::string kind;
    std::string stage;  ///< the stage that produced it ("" in bundles older than this field)
    int width = 0, height = 0, channels = 0;
    std::vector<std::string> channel_names;
    std::string sha256;
    std::string file;  ///< "" when recorded by hash only
    /// Hash-only buffers: SHA-256 of each block of block_rows rows, to locate a difference.
    int block_rows = 0;
    std::vector<std::string> block_sha256;
};

struct Manifest {
    GoldenCase golden_case;
    std::string fovref_version, compiler, flags;
    std::vector<ManifestBuffer> buffers;     ///< in frame then pipeline order
    std::vector<Counters> frame_counters;    ///< one per frame
    std::vector<float> display_distance_px;  ///< one per frame; 0 when the case has no scene
};

Manifest read_manifest(const std::string& directory);

/// One difference between a recomputation and a stored bundle.
struct GoldenDifference {
    int frame = 0;
    std::string buffer;
    std::string what;  ///< human-readable: which pixel differs and both values, or why
};

/// Compares freshly rendered frames with the bundle in `directory` (whose manifest is given),
/// buffer by buffer in pipeline order, bit-exactly, and the per-frame counters. For a differing
/// buffer with a stored file, names the first differing pixel (row-major, then channel) with both
/// values; for a hash-only buffer, the first differing block of rows.
std::vector<GoldenDifference> compare_with_bundle(const std::string& directory,
                                                  const Manifest& manifest,
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
