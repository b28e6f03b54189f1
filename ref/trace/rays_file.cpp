#include "ref/trace/rays_file.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/limits.h"
#include "ref/core/rng.h"
#include "ref/core/vec.h"
#include "ref/image/image_io.h"
#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

namespace {

static_assert(std::endian::native == std::endian::little, "ray files are little-endian");

template <typename Record>
std::vector<Record> read_records(const std::string& path, std::size_t record_bytes,
                                 const char* what) {
    const std::string bytes = read_file(path);
    if (bytes.size() % record_bytes != 0)
        throw Error(path + ": truncated " + what + " file: " + std::to_string(bytes.size()) +
                    " bytes is not a multiple of the " + std::to_string(record_bytes) +
                    "-byte record");
    check_limit(path, bytes.size() / record_bytes, input_limits().max_rays, "records",
                "FOVREF_MAX_RAYS");
    std::vector<Record> records(bytes.size() / record_bytes);
    if (!records.empty()) std::memcpy(records.data(), bytes.data(), bytes.size());
    return records;
}

template <typename Record>
void write_records(const std::string& path, const std::vector<Record>& records) {
    std::string bytes(records.size() * sizeof(Record), '\0');
    if (!records.empty()) std::memcpy(bytes.data(), records.data(), bytes.size());
    write_file_atomic(path, bytes);
}

struct RayRecord {
    float values[8];
};
struct HitRecord {
    float t;
    std::int32_t primitive;
    float u, v;
};
static_assert(sizeof(RayRecord) == 32 && sizeof(HitRecord) == 16);

}  // namespace

std::vector<Ray> read_rays(const std::string& path) {
    const std::vector<RayRecord> records = read_records<RayRecord>(path, sizeof(RayRecord), "ray");
    std::vector<Ray> rays(records.size());
    for (std::size_t k = 0; k < records.size(); ++k) {
        const float* v = records[k].values;
        rays[k].origin = {v[0], v[1], v[2]};
        rays[k].direction = {v[3], v[4], v[5]};
        rays[k].t_min = v[6];
        rays[k].t_max = v[7];
        // Every field finite except t_max, which may be +inf; the direction must not be zero.
        static const char* const names[8] = {"origin x",    "origin y",    "origin z",
                                             "direction x", "direction y", "direction z",
                                             "t_min",       "t_max"};
        for (int i = 0; i < 8; ++i)
            if (std::isnan(v[i]) || (std::isinf(v[i]) && !(i == 7 && v[i] > 0.0f)))
                throw Error(path + ": ray " + std::to_string(k) + ": " + names[i] + " is " +
                            std::to_string(v[i]) + " (must be finite; only t_max may be +inf)");
        if (v[3] == 0.0f && v[4] == 0.0f && v[5] == 0.0f)
            throw Error(path + ": ray " + std::to_string(k) + ": the direction is zero");
    }
    return rays;
}

void write_rays(const std::string& path, const std::vector<Ray>& rays) {
    std::vector<RayRecord> records(rays.size());
    for (std::size_t k = 0; k < rays.size(); ++k) {
        const Ray& r = rays[k];
        records[k] = {{r.origin.x, r.origin.y, r.origin.z, r.direction.x, r.direction.y,
                       r.direction.z, r.t_min, r.t_max}};
    }
    write_records(path, records);
}

std::vector<Hit> read_hits(const std::string& path) {
    const std::vector<HitRecord> records = read_records<HitRecord>(path, sizeof(HitRecord), "hit");
    std::vector<Hit> hits(records.size());
    for (std::size_t k = 0; k < records.size(); ++k)
        hits[k] = Hit{records[k].t, records[k].primitive, records[k].u, records[k].v};
    return hits;
}

void write_hits(const std::string& path, const std::vector<Hit>& hits) {
    std::vector<HitRecord> records(hits.size());
    for (std::size_t k = 0; k < hits.size(); ++k)
        records[k] = hits[k].hit() ? HitRecord{hits[k].t, hits[k].primitive, hits[k].u, hits[k].v}
                                   : HitRecord{-1.0f, -1, 0.0f, 0.0f};
    write_records(path, records);
}

void write_occlusion(const std::string& path, const std::vector<std::uint32_t>& occluded) {
    write_records(path, occluded);
}

std::vector<std::uint32_t> read_occlusion(const std::string& path) {
    return read_records<std::uint32_t>(path, sizeof(std::uint32_t), "occlusion");
}

std::vector<Ray> camera_rays_list(const Camera& camera, int width, int height) {
    std::vector<Ray> rays;
    rays.reserve(static_cast<std::size_t>(width) * height);
    const float tan_half = tan_half_vfov(camera);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::vec2 centre = pixel_centre(x, y);
            rays.push_back(primary_ray(camera, tan_half, width, height, centre.x, centre.y));
        }
    return rays;
}

std::vector<Ray> random_rays(const Scene& scene, std::uint32_t count, std::uint32_t seed) {
    const Bounds bounds = scene_bounds(scene);
    std::vector<Ray> rays(count);
    for (std::uint32_t k = 0; k < count; ++k) {
        Ray& ray = rays[k];
        for (int c = 0; c < 3; ++c)
            ray.origin[c] = bounds.min[c] + (bounds.max[c] - bounds.min[c]) *
                                                rand_unit(seed, k, static_cast<std::uint32_t>(c));
        // Uniform direction: z = 1 - 2 r, phi = 2 pi r'.
        const float z = 1.0f - 2.0f * rand_unit(seed, k, 3);
        const float phi = 2.0f * dm::pi * rand_unit(seed, k, 4);
        const float radius = std::sqrt(std::max(0.0f, 1.0f - z * z));
        ray.direction = {radius * dm::cos(phi), radius * dm::sin(phi), z};
    }
    return rays;
}

}  // namespace fovref
