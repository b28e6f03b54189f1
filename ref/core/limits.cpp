#include "ref/core/limits.h"

#include <charconv>
#include <cstdlib>
#include <cstring>

#include "ref/core/error.h"

namespace fovref {

namespace {

void from_environment(const char* variable, std::uint64_t& value) {
    const char* text = std::getenv(variable);
    if (!text) return;
    std::uint64_t parsed = 0;
    const char* end = text + std::strlen(text);
    const auto r = std::from_chars(text, end, parsed);
    if (r.ec != std::errc() || r.ptr != end || parsed == 0)
        throw Error(std::string("environment variable ") + variable + "='" + text +
                    "': expected a positive integer (docs/limits.md)");
    value = parsed;
}

InputLimits read_limits() {
    InputLimits limits;
    from_environment("FOVREF_MAX_FILE_BYTES", limits.max_file_bytes);
    from_environment("FOVREF_MAX_IMAGE_PIXELS", limits.max_image_pixels);
    from_environment("FOVREF_MAX_SCENE_PIXELS", limits.max_scene_texture_pixels);
    from_environment("FOVREF_MAX_RAYS", limits.max_rays);
    from_environment("FOVREF_MAX_SCENE_TRIANGLES", limits.max_scene_triangles);
    return limits;
}

}  // namespace

const InputLimits& input_limits() {
    static const InputLimits limits = read_limits();
    return limits;
}

void check_limit(const std::string& what, std::uint64_t count, std::uint64_t limit,
                 const char* unit, const char* variable) {
    if (count <= limit) return;
    throw Error(what + ": " + std::to_string(count) + " " + unit + " exceed the limit of " +
                std::to_string(limit) + " (raise it with " + variable + "; docs/limits.md)");
}

}  // namespace fovref
