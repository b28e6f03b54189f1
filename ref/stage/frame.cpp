#include "ref/stage/frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ref/core/error.h"
#include "ref/core/rng.h"

namespace fovref {

const char* buffer_kind_name(BufferKind kind) {
    switch (kind) {
        case BufferKind::color: return "color";
        case BufferKind::depth: return "depth";
        case BufferKind::id: return "id";
        case BufferKind::vector: return "vector";
        case BufferKind::scalar: return "scalar";
    }
    return "scalar";
}

void Counters::add(const std::string& name, std::int64_t value) {
    for (auto& [key, existing] : values)
        if (key == name) {
            existing += value;
            return;
        }
    values.emplace_back(name, value);
}

std::int64_t Counters::get(const std::string& name) const {
    for (const auto& [key, value] : values)
        if (key == name) return value;
    return 0;
}

const Buffer* FrameResult::find(const std::string& name) const {
    for (const Buffer& buffer : buffers)
        if (buffer.name == name) return &buffer;
    return nullptr;
}

Buffer& FrameResult::add(std::string name, BufferKind kind, std::vector<std::string> channel_names,
                         Image image) {
    FOVREF_CHECK(find(name) == nullptr, "buffer '" + name + "' produced twice");
    FOVREF_CHECK_EQ(channel_names.size(), static_cast<std::size_t>(image.channels),
                    "channel names and channels of buffer '" + name + "'");
    buffers.push_back(
        Buffer{std::move(name), kind, std::move(channel_names), std::move(image), ""});
    return buffers.back();
}

namespace {

// Range of the finite values of channel c (of all channels when c < 0).
std::pair<float, float> finite_range(const Image& image, int c, bool positive_only) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < image.pixel_count(); ++i)
        for (int k = 0; k < image.channels; ++k) {
            if (c >= 0 && k != c) continue;
            float v = image.data[i * image.channels + k];
            if (!std::isfinite(v) || (positive_only && !(v > 0.0f))) continue;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    return {lo, hi};
}

float normalise(float v, std::pair<float, float> range) {
    if (!std::isfinite(v) || !(range.second >= range.first)) return 0.0f;
    if (range.second == range.first) return 0.5f;
    return (v - range.first) / (range.second - range.first);
}

}  // namespace

Image preview_image(const Buffer& buffer) {
    const Image& src = buffer.image;
    Image out(src.width, src.height, 3);
    const int channels = std::min(src.channels, 3);
    std::vector<std::pair<float, float>> ranges;
    for (int c = 0; c < channels; ++c)
        ranges.push_back(finite_range(src, buffer.kind == BufferKind::depth ? -1 : c,
                                      buffer.kind == BufferKind::depth));
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const int sc = std::min(c, src.channels - 1);
                const float v = src.at(x, y, sc);
                float shown = 0.0f;
                switch (buffer.kind) {
                    case BufferKind::color: shown = std::isfinite(v) ? v : 0.0f; break;
                    case BufferKind::vector:
                        shown = c < src.channels ? v * 0.5f + 0.5f : 0.0f;
                        break;
                    case BufferKind::depth:
                        shown = v > 0.0f ? 1.0f - 0.9f * normalise(v, ranges[0]) : 0.0f;
                        break;
                    case BufferKind::scalar:
                        shown =
                            c < src.channels || src.channels == 1 ? normalise(v, ranges[sc]) : 0.0f;
                        break;
                    case BufferKind::id: {
                        if (!(v >= 0.0f && v < 16777216.0f)) break;  // ids are exact below 2^24
                        std::uint32_t h = pcg_hash(static_cast<std::uint32_t>(v) * 3u + c);
                        shown = 0.25f + 0.75f * u32_to_unit(h);
                        break;
                    }
                }
                out.at(x, y, c) = shown;
            }
        }
    return out;
}

}  // namespace fovref
