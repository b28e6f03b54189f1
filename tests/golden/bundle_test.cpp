#include <doctest/doctest.h>

#include <unistd.h>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "ref/core/error.h"
#include "ref/core/json_locator.h"
#include "ref/golden/bundle.h"
#include "ref/image/image_io.h"
#include "ref/modes/modes.h"

using namespace fovref;
namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("fovref-golden-test-" + std::to_string(getpid()));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
};

GoldenCase rng_case() {
    GoldenCase c;
    c.name = "rng-small";
    c.mode = "rng";
    c.width = 7;
    c.height = 5;
    c.frames = 2;
    return c;
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST_CASE("bundle: write, read back and compare bit-exactly, a one-ulp change is located") {
    TempDir tmp;
    const GoldenCase c = rng_case();
    std::vector<FrameResult> frames = render_golden_case(c, nullptr, {"all"});
    const std::string dir = (tmp.path / "bundle").string();
    write_bundle(dir, c, frames, BundleOptions{});

    Manifest m = read_manifest(dir);
    CHECK(m.golden_case == c);
    REQUIRE(m.buffers.size() == 2);
    CHECK(m.buffers[1].frame == 1);
    CHECK(m.buffers[0].sha256 == canonical_sha256(frames[0].buffers[0].image));
    CHECK(m.buffers[0].file == "f000_rng.pfm");
    CHECK(bit_equal(read_image(dir + "/f000_rng.pfm"), frames[0].buffers[0].image));
    CHECK(compare_with_bundle(dir, read_manifest(dir), frames).empty());

    // One ulp at pixel (3, 2), channel 1 of frame 1.
    std::vector<FrameResult> perturbed = frames;
    float& v = perturbed[1].buffers[0].image.at(3, 2, 1);
    v = std::nextafter(v, 2.0f);
    auto differences = compare_with_bundle(dir, read_manifest(dir), perturbed);
    REQUIRE(differences.size() == 1);
    CHECK(differences[0].frame == 1);
    CHECK(differences[0].buffer == "rng");
    CHECK(differences[0].what.find("pixel (3, 2) channel d1") != std::string::npos);

    // Rewriting replaces the bundle whole; nothing is left beside it.
    write_bundle(dir, c, perturbed, BundleOptions{});
    CHECK(compare_with_bundle(dir, read_manifest(dir), perturbed).empty());
    CHECK_FALSE(fs::exists(dir + ".writing"));
    CHECK_FALSE(fs::exists(dir + ".previous"));
}

TEST_CASE("bundle: hash-only buffers, missing and extra buffers, changed shapes") {
    TempDir tmp;
    GoldenCase c = rng_case();
    c.frames = 1;
    std::vector<FrameResult> frames = render_golden_case(c, nullptr, {"all"});
    const std::string dir = (tmp.path / "b").string();
    BundleOptions options;
    options.max_stored_pixels = 10;  // 7x5 = 35 pixels: hash only
    write_bundle(dir, c, frames, options);
    CHECK(read_manifest(dir).buffers[0].file.empty());
    CHECK_FALSE(fs::exists(dir + "/f000_rng.pfm"));

    std::vector<FrameResult> changed = frames;
    changed[0].buffers[0].image.data[0] += 1.0f;
    auto d = compare_with_bundle(dir, read_manifest(dir), changed);
    REQUIRE(d.size() == 1);
    CHECK(d[0].what.find("hash only") != std::string::npos);
    CHECK(d[0].what.find("rows 0..0") != std::string::npos);  // 5 rows: one row per block

    std::vector<FrameResult> reshaped = frames;
    reshaped[0].buffers[0].image = Image(5, 7, 3);
    d = compare_with_bundle(dir, read_manifest(dir), reshaped);
    REQUIRE(d.size() == 1);
    CHECK(d[0].what.find("shape 5x7x3") != std::string::npos);

    std::vector<FrameResult> renamed = frames;
    renamed[0].buffers[0].name = "other";
    d = compare_with_bundle(dir, read_manifest(dir), renamed);
    CHECK(d.size() == 2);  // rng missing, other extra
}

TEST_CASE("bundle: a failed write leaves the previous bundle untouched and nothing beside it") {
    TempDir tmp;
    const GoldenCase c = rng_case();
    std::vector<FrameResult> frames = render_golden_case(c, nullptr, {"all"});
    const std::string dir = (tmp.path / "bundle").string();
    write_bundle(dir, c, frames, BundleOptions{});
    const Manifest before = read_manifest(dir);

    // An empty buffer cannot be written: the write fails after frame 0 was written.
    std::vector<FrameResult> broken = frames;
    broken[1].buffers[0].image = Image();
    CHECK_THROWS_AS(write_bundle(dir, c, broken, BundleOptions{}), Error);
    CHECK(read_manifest(dir).buffers[1].sha256 == before.buffers[1].sha256);
    CHECK(bit_equal(read_image(dir + "/f001_rng.pfm"), frames[1].buffers[0].image));
    CHECK_FALSE(fs::exists(dir + ".writing"));
    CHECK_FALSE(fs::exists(dir + ".previous"));

    // A writer dropped before commit leaves nothing either.
    { BundleWriter abandoned((tmp.path / "never").string(), c, BundleOptions{}); }
    CHECK_FALSE(fs::exists(tmp.path / "never"));
    CHECK_FALSE(fs::exists(tmp.path / "never.writing"));

    // A path under a regular file cannot be created.
    write_text(tmp.path / "file", "x");
    CHECK_THROWS_AS(
        write_bundle((tmp.path / "file" / "bundle").string(), c, frames, BundleOptions{}), Error);
}

TEST_CASE("bundle: only absent, empty or bundle directories are replaced") {
    TempDir tmp;
    const GoldenCase c = rng_case();
    std::vector<FrameResult> frames = render_golden_case(c, nullptr, {"all"});

    // A directory holding someone's files is refused and left alone.
    fs::create_directories(tmp.path / "mydocs");
    write_text(tmp.path / "mydocs" / "thesis.txt", "precious");
    CHECK_THROWS_WITH_AS(write_bundle((tmp.path / "mydocs").string(), c, frames, BundleOptions{}),
                         doctest::Contains("not a fovref bundle"), Error);
    CHECK(fs::exists(tmp.path / "mydocs" / "thesis.txt"));
    // So is a regular file.
    write_text(tmp.path / "notes.txt", "keep");
    CHECK_THROWS_WITH_AS(
        write_bundle((tmp.path / "notes.txt").string(), c, frames, BundleOptions{}),
        doctest::Contains("not a directory"), Error);
    CHECK(fs::is_regular_file(tmp.path / "notes.txt"));
    // '.', '..' and a root are never bundle directories.
    CHECK_THROWS_AS(write_bundle(".", c, frames, BundleOptions{}), Error);
    CHECK_THROWS_AS(write_bundle("/", c, frames, BundleOptions{}), Error);
    // An empty directory is fine, and so is a trailing slash (staging goes beside, not inside).
    fs::create_directories(tmp.path / "empty");
    write_bundle((tmp.path / "empty").string() + "/", c, frames, BundleOptions{});
    CHECK(fs::exists(tmp.path / "empty" / "manifest.json"));
    CHECK_FALSE(fs::exists(tmp.path / "empty" / ".writing"));
    // An existing bundle is replaced.
    write_bundle((tmp.path / "empty").string(), c, frames, BundleOptions{});
    CHECK(read_manifest((tmp.path / "empty").string()).buffers.size() == 2);
}

TEST_CASE("bundle: hash-only buffers locate the first differing block of rows") {
    TempDir tmp;
    GoldenCase c = rng_case();
    c.width = 3;
    c.height = 600;  // 600 rows -> blocks of 3 rows (at most 256 blocks)
    c.frames = 1;
    std::vector<FrameResult> frames = render_golden_case(c, nullptr, {"all"});
    const std::string dir = (tmp.path / "b").string();
    BundleOptions options;
    options.max_stored_pixels = 100;
    write_bundle(dir, c, frames, options);
    const Manifest m = read_manifest(dir);
    CHECK(m.buffers[0].block_rows == hash_block_rows(600));
    CHECK(hash_block_rows(600) == 3);
    CHECK(m.buffers[0].block_sha256.size() == 200);
    std::vector<FrameResult> changed = frames;
    changed[0].buffers[0].image.at(1, 400, 2) += 0.5f;
    auto d = compare_with_bundle(dir, m, changed);
    REQUIRE(d.size() == 1);
    CHECK(d[0].what.find("first differing rows 399..401") != std::string::npos);
}

TEST_CASE("first_difference and describe_difference") {
    Image a(3, 2, 2, 0.25f), b = a;
    CHECK(first_difference(a, b) == -1);
    b.at(1, 1, 1) = -0.0f;
    a.at(1, 1, 1) = 0.0f;
    CHECK(first_difference(a, b) ==
          static_cast<std::ptrdiff_t>(a.index(1, 1, 1)));  // -0 != +0 in bits
    b.at(2, 0, 0) = std::bit_cast<float>(0x3e800001u);
    const std::ptrdiff_t i = first_difference(a, b);
    CHECK(i == static_cast<std::ptrdiff_t>(a.index(2, 0, 0)));
    const std::string text = describe_difference(a, b, i, {"u", "v"});
    CHECK(text ==
          "first difference at pixel (2, 0) channel u: expected 0.25 (0x3e800000), got "
          "0.25000003 (0x3e800001)");
}

TEST_CASE("golden cases file: good and bad definitions") {
    TempDir tmp;
    const fs::path file = tmp.path / "cases.json";
    write_text(file, R"({"cases": [
      {"name": "a", "mode": "rng", "width": 8, "height": 4, "frames": 2, "params": {"k": 1.5}},
      {"name": "b", "scene": "cornell", "mode": "splat", "width": 16, "height": 9}
    ]})");
    auto cases = load_golden_cases(file.string());
    REQUIRE(cases.size() == 2);
    CHECK(cases[0].frames == 2);
    CHECK(cases[0].params.values().at("k") == "1.5");
    CHECK(cases[1].scene == "cornell");
    CHECK(find_golden_case(cases, "b").width == 16);
    CHECK_THROWS_WITH_AS(find_golden_case(cases, "zzz"), doctest::Contains("cases: a, b"), Error);

    write_text(file,
               R"({"cases": [{"name": "a", "mode": "rng", "width": 8, "height": 4, "color": 1}]})");
    CHECK_THROWS_WITH_AS(load_golden_cases(file.string()), doctest::Contains("unknown key 'color'"),
                         Error);
    write_text(file, R"({"cases": [{"name": "a", "mode": "rng", "width": 8, "height": 4},
                                   {"name": "a", "mode": "rng", "width": 8, "height": 4}]})");
    CHECK_THROWS_WITH_AS(load_golden_cases(file.string()), doctest::Contains("defined twice"),
                         Error);
    write_text(file, R"({"cases": [{"name": "a/b", "mode": "rng", "width": 8, "height": 4}]})");
    CHECK_THROWS_AS(load_golden_cases(file.string()), Error);
    write_text(file, R"({"cases": [ {"name": )");
    CHECK_THROWS_WITH_AS(load_golden_cases(file.string()), doctest::Contains("cases.json"), Error);
    CHECK_THROWS_WITH_AS(load_golden_cases((tmp.path / "missing.json").string()),
                         doctest::Contains("missing.json"), Error);
}

TEST_CASE(
    "hostile JSON: deep nesting is refused before parsing, mistyped keys name file, line, key") {
    // A 100000-deep document used to reach nlohmann's parser (and its recursion) in the bundle
    // code; every JSON reader now refuses nesting beyond 256 first, with the file and line.
    TempDir tmp;
    const std::string deep =
        "{\"a\":\n" + std::string(100000, '[') + std::string(100000, ']') + "}";
    const fs::path bundle = tmp.path / "bundle";
    fs::create_directories(bundle);
    write_text(bundle / "manifest.json", deep);
    CHECK_THROWS_WITH_AS(read_manifest(bundle.string()),
                         doctest::Contains("manifest.json:2: JSON nested deeper than 256"), Error);
    write_text(tmp.path / "cases.json", deep);
    CHECK_THROWS_WITH_AS(load_golden_cases((tmp.path / "cases.json").string()),
                         doctest::Contains("cases.json:2: JSON nested deeper than 256"), Error);
    // A bundle directory with such a manifest is not a bundle: never overwritten.
    const std::vector<FrameResult> frames = render(nullptr, "rng", case_settings(rng_case(), {}));
    CHECK_THROWS_WITH_AS(write_bundle(bundle.string(), rng_case(), frames, {}),
                         doctest::Contains("not a fovref bundle"), Error);
    // Brackets inside strings do not count; 256 levels are fine.
    write_text(tmp.path / "cases.json",
               "{\"cases\": [{\"name\": \"x\", \"description\": \"" + std::string(300, '[') +
                   "\\\"]]\", \"mode\": \"rng\", \"width\": 8, \"height\": 4}]}");
    CHECK(load_golden_cases((tmp.path / "cases.json").string()).size() == 1);
    CHECK_NOTHROW(check_json_nesting(std::string(256, '[') + std::string(256, ']'), "f"));
    CHECK_THROWS_AS(check_json_nesting(std::string(257, '[') + std::string(257, ']'), "f"), Error);

    // Mistyped members: the file, the key's line and its JSON pointer, in words.
    write_bundle(bundle.string() + "2", rng_case(), frames, {});
    const fs::path manifest = fs::path(bundle.string() + "2") / "manifest.json";
    std::ifstream in(manifest);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = text.find("\"name\": \"rng\"");
    REQUIRE(at != std::string::npos);
    text.replace(at, 13, "\"name\": 17");
    write_text(manifest, text);
    int line = 1;
    for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n';
    const std::string expected = "manifest.json:" + std::to_string(line) +
                                 ": malformed manifest: /frames/0/buffers/0/name: "
                                 "expected a string, got number";
    CHECK_THROWS_WITH_AS(read_manifest(bundle.string() + "2"), doctest::Contains(expected.c_str()),
                         Error);
    write_text(
        tmp.path / "cases.json",
        "{\"cases\": [\n{\"name\": \"a\", \"mode\": \"rng\",\n \"width\": \"8\", \"height\": 4}]}");
    CHECK_THROWS_WITH_AS(load_golden_cases((tmp.path / "cases.json").string()),
                         doctest::Contains("cases.json:3: /cases/0: 'width' must be an integer"),
                         Error);
}

TEST_CASE("bundle: a symbolic link to a bundle directory is written through, not replaced") {
    TempDir tmp;
    const fs::path real = tmp.path / "real";
    const fs::path link = tmp.path / "link";
    const std::vector<FrameResult> frames = render(nullptr, "rng", case_settings(rng_case(), {}));
    write_bundle(real.string(), rng_case(), frames, {});
    fs::create_directory_symlink("real", link);
    GoldenCase changed = rng_case();
    changed.description = "through the link";
    write_bundle(link.string(), changed, frames, {});
    CHECK(fs::is_symlink(fs::symlink_status(link)));
    CHECK(read_manifest(real.string()).golden_case.description == "through the link");
    CHECK_FALSE(fs::exists(tmp.path / "link.writing"));
    CHECK_FALSE(fs::exists(tmp.path / "real.writing"));
}
