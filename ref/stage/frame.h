// What one frame of a render produces (SPEC §11, issue "stage framework"): named buffers in
// pipeline order, a record of every stage (ran or skipped, and why), and integer statistics.
// Every buffer can be dumped by name; the golden bundles and `--dump` write exactly these.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <optional>

#include "ref/image/image.h"
#include "ref/scene/camera.h"

namespace fovref {

/// How a buffer's values are meant, which decides its PNG preview (the PFM/EXR data is always the
/// raw floats).
enum class BufferKind {
    color,   ///< linear RGB radiance: clamped and sRGB-encoded
    depth,   ///< distances: normalised to [min, max] of the finite positive values, near = bright
    id,      ///< integer ids stored as float (exact below 2^24), -1 = none: a hashed colour per id
    vector,  ///< unit vectors / offsets in [-1, 1]: v * 0.5 + 0.5
    scalar,  ///< anything else: normalised to [min, max] per channel
};

const char* buffer_kind_name(BufferKind kind);

struct Buffer {
    std::string name;
    BufferKind kind = BufferKind::scalar;
    std::vector<std::string> channel_names;  ///< e.g. {"r","g","b"}; size == image.channels
    Image image;
    std::string stage;  ///< the stage that produced it (set by Pipeline::run_frame)
};

/// The record of one stage in one frame.
struct StageRun {
    std::string name;
    bool ran = false;
    std::string note;    ///< why it was skipped, or what it did
    double seconds = 0;  ///< wall time (never part of a golden)
};

/// Ordered integer statistics (rays traced, texels skipped, NaNs replaced, ...).
struct Counters {
    std::vector<std::pair<std::string, std::int64_t>> values;
    void add(const std::string& name, std::int64_t value);  ///< adds to an existing entry
    std::int64_t get(const std::string& name) const;        ///< 0 when absent
    bool operator==(const Counters&) const = default;
};

struct FrameResult {
    int frame = 0;
    float time = 0.0f;  ///< camera-path time of this frame
    /// Viewing distance in pixels of the scene's display model for this frame's camera (SPEC
    /// §1), what eccentricities (error ranges) are measured with; 0 without a scene.
    float display_distance_px = 0.0f;
    /// This frame's camera (absent without a scene): the bundle's manifest records it, so a GPU
    /// implementation renders exactly the same view.
    std::optional<Camera> camera;
    std::vector<Buffer> buffers;
    std::vector<StageRun> stages;
    Counters counters;

    const Buffer* find(const std::string& name) const;
    Buffer& add(std::string name, BufferKind kind, std::vector<std::string> channel_names,
                Image image);
};

/// An RGB image in [0,1] for a person to look at (BufferKind decides the mapping).
Image preview_image(const Buffer& buffer);

}  // namespace fovref
