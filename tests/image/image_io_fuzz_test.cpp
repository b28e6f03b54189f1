// Deterministic mutation fuzzing of the three readers: byte flips and truncations of valid PFM,
// PNG and EXR files. Each read must either succeed or throw fovref::Error, never crash or throw
// anything else (this also runs under ASan/UBSan in CI). Fixed seed, a few hundred mutations.
#include <doctest/doctest.h>

#include <string>

#include "image_test_util.h"
#include "ref/image/image_io.h"

using namespace fovref;

TEST_CASE("fuzz: mutated image files are read or rejected with fovref::Error") {
    test::TempDir dir("fuzz");
    test::SplitMix64 rng(20240601);
    Image rgb(12, 9, 3), rgba(12, 9, 4), grey(12, 9, 1);
    for (Image* image : {&rgb, &rgba, &grey})
        for (float& v : image->data) v = rng.unit();

    const struct {
        const char* name;
        const Image& image;
    } sources[] = {{"a.pfm", rgb},  {"b.pfm", grey}, {"c.png", rgba},
                   {"d.png", grey}, {"e.exr", rgba}, {"f.exr", grey}};
    constexpr int mutations_per_source = 60;  // 360 reads in all
    int accepted = 0, rejected = 0, other = 0;
    for (const auto& source : sources) {
        const std::string path = dir.file(source.name);
        write_image(path, source.image);
        const std::string original = read_file(path);
        for (int m = 0; m < mutations_per_source; ++m) {
            std::string bytes = original;
            const std::size_t kind = rng.below(4);
            // 0: flip 1-4 bytes anywhere; 1: flip bytes in the first 64 (headers);
            // 2: truncate; 3: truncate and flip.
            if (kind != 2) {
                const std::size_t flips = 1 + rng.below(4);
                for (std::size_t f = 0; f < flips; ++f) {
                    const std::size_t span =
                        kind == 1 ? std::min<std::size_t>(64, bytes.size()) : bytes.size();
                    const std::size_t at = rng.below(span);
                    bytes[at] =
                        static_cast<char>(bytes[at] ^ static_cast<char>(1 + rng.below(255)));
                }
            }
            if (kind >= 2) bytes.resize(rng.below(bytes.size()));
            test::write_bytes(path, bytes);
            try {
                const Image image = read_image(path);
                // Whatever was accepted is a consistent image.
                CHECK(image.data.size() ==
                      image.pixel_count() * static_cast<std::size_t>(image.channels));
                ++accepted;
            } catch (const Error& e) {
                CHECK(test::contains(e.what(), source.name));
                ++rejected;
            } catch (...) {
                ++other;
                FAIL_CHECK("mutation " << m << " of " << source.name
                                       << " threw something other than fovref::Error");
            }
        }
    }
    MESSAGE("fuzz: " << accepted << " accepted, " << rejected << " rejected");
    CHECK(other == 0);
    CHECK(rejected > 0);
}
