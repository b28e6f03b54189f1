// Bad input never crashes: every corrupt, truncated or forged file, and every failed write,
// throws fovref::Error whose message names the file (SPEC §1, COMMON error policy).
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>

#include "image_test_util.h"
#include "ref/image/image_io.h"

using namespace fovref;

namespace {

/// Reads `path` with `read` and checks that fovref::Error is thrown naming the file and
/// containing `expected`.
template <class Read>
void check_read_error(Read read, const std::string& path, const std::string& expected) {
    const std::string message = test::error_message([&] { read(path); });
    CAPTURE(path);
    CAPTURE(message);
    CHECK(test::contains(message, std::filesystem::path(path).filename().string()));
    CHECK(test::contains(message, expected));
}

}  // namespace

TEST_CASE("errors: missing, empty and unreadable files") {
    test::TempDir dir("err-files");
    for (const char* name : {"missing.pfm", "missing.png", "missing.exr"})
        check_read_error(read_image, dir.file(name), "cannot open");
    for (const char* name : {"empty.pfm", "empty.png", "empty.exr"}) {
        test::write_bytes(dir.file(name), "");
        check_read_error(read_image, dir.file(name), "empty file");
    }
    std::filesystem::create_directory(dir.file("folder.pfm"));
    check_read_error(read_image, dir.file("folder.pfm"), "is a directory");
    check_read_error(read_image, dir.file("picture.tiff"), ".tiff");
}

TEST_CASE("errors: PFM headers") {
    test::TempDir dir("err-pfm");
    const std::string path = dir.file("bad.pfm");
    const std::string four_floats(16, '\0');
    const struct {
        std::string bytes;
        const char* expected;
    } cases[] = {
        {"P6\n2 2\n255\n" + four_floats, "bad magic"},
        {"PFX\n1 1\n-1\n" + four_floats, "bad magic"},
        {"\x89PNG\r\n\x1a\n", "bad magic"},
        {"PF", "bad magic"},
        {"Pf\nabc 2\n-1\n" + four_floats, "width \"abc\" is not an integer"},
        {"Pf\n2 2x\n-1\n" + four_floats, "height \"2x\" is not an integer"},
        {"Pf\n-2 2\n-1\n" + four_floats, "width -2 must be positive"},
        {"Pf\n2 0\n-1\n" + four_floats, "height 0 must be positive"},
        {"Pf\n99999999999 1\n-1\n" + four_floats, "width 99999999999 is too large"},
        {"Pf\n2 2\n0\n" + four_floats, "scale \"0\" is not a finite non-zero number"},
        {"Pf\n2 2\nnan\n" + four_floats, "scale"},
        {"Pf\n2 2\n-1x\n" + four_floats, "scale"},
        {"Pf\n2 2\n" + std::string(40, '1') + "\n", "field too long"},
        {"Pf\n2 2\n", "ends before the scale"},
        {"Pf\n2", "ends before the height"},
        {"Pf\n2 2\n-1", "no raster"},
        {"Pf\n2 2\n-1\n" + std::string(15, '\0'),
         "truncated: header says 2x2x1 floats (16 bytes), file has 15 bytes after the header"},
        {"Pf\n2 2\n-1\n" + std::string(17, '\0'),
         "trailing bytes: header says 2x2x1 floats (16 bytes), file has 17 bytes"},
        {"PF\n64 32\n-1\n" + std::string(1000, '\0'),
         "truncated: header says 64x32x3 floats (24576 bytes), file has 1000 bytes after the "
         "header"},
    };
    for (const auto& c : cases) {
        test::write_bytes(path, c.bytes);
        check_read_error(read_pfm, path, c.expected);
    }
}

TEST_CASE("errors: a forged huge PFM header fails fast without allocating") {
    // 100000 x 100000 x 3 floats would be 120 GB; the size check happens before any allocation,
    // so the read fails at once with fovref::Error (not bad_alloc) and well under a second.
    test::TempDir dir("err-forged");
    const std::string path = dir.file("forged.pfm");
    test::write_bytes(path, "PF\n100000 100000\n-1\n" + std::string(64, '\x7f'));
    const auto start = std::chrono::steady_clock::now();
    check_read_error(read_pfm, path,
                     "truncated: header says 100000x100000x3 floats (120000000000 bytes), file "
                     "has 64 bytes after the header");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK(seconds < 1.0);  // generous: the read takes microseconds
    test::write_bytes(path, "PF\n2147483647 2147483647\n-1\n" + std::string(64, '\x7f'));
    check_read_error(read_pfm, path, "truncated");
}

TEST_CASE("errors: corrupt PNG files") {
    test::TempDir dir("err-png");
    Image image(32, 16, 3);
    test::SplitMix64 rng(9);
    for (float& v : image.data) v = rng.unit();
    const std::string good = dir.file("good.png");
    write_png(good, image);
    const std::string bytes = read_file(good);

    const std::string path = dir.file("cut.png");
    test::write_bytes(path, bytes.substr(0, bytes.size() / 2));
    check_read_error([](const std::string& p) { read_png(p); }, path,
                     "truncated PNG: chunk \"IDAT\"");

    test::write_bytes(path, "GIF89a" + bytes.substr(6));
    check_read_error([](const std::string& p) { read_png(p); }, path, "bad signature");

    // A forged IHDR (stb_image does not check CRCs): 100000x100000 RGB on a small file.
    std::string forged = bytes;
    const std::string dims = {'\0', '\x01', '\x86', '\xa0', '\0', '\x01', '\x86', '\xa0'};
    forged.replace(16, 8, dims);
    test::write_bytes(path, forged);
    check_read_error([](const std::string& p) { read_png(p); }, path, "100000x100000");
}

TEST_CASE("errors: corrupt EXR files") {
    test::TempDir dir("err-exr");
    Image image(16, 8, 3);
    test::SplitMix64 rng(13);
    for (float& v : image.data) v = rng.unit();
    const std::string good = dir.file("good.exr");
    write_exr(good, image);
    const std::string bytes = read_file(good);

    const std::string path = dir.file("bad.exr");
    for (std::size_t length :
         {std::size_t{3}, std::size_t{10}, std::size_t{100}, bytes.size() / 2, bytes.size() - 1}) {
        CAPTURE(length);
        test::write_bytes(path, bytes.substr(0, length));
        check_read_error(read_exr, path, "bad.exr");
    }
    // Magic number followed by garbage; garbage without the magic number.
    std::string garbage = bytes.substr(0, 4);
    for (int i = 0; i < 500; ++i) garbage += static_cast<char>(rng.next_u32() & 0xff);
    test::write_bytes(path, garbage);
    check_read_error(read_exr, path, "cannot read EXR");
    test::write_bytes(path, garbage.substr(4));
    check_read_error(read_exr, path, "cannot read EXR");
    // Valid header, forged chunk: the single line block's (y, byte count) header claims 2^31-1
    // bytes. The one-entry offset table is found as the 8 bytes that point just past themselves.
    std::size_t table = 0;
    for (std::size_t p = 0; p + 8 <= bytes.size(); ++p) {
        std::uint64_t offset = 0;
        for (int i = 7; i >= 0; --i)
            offset =
                offset << 8 | static_cast<unsigned char>(bytes[p + static_cast<std::size_t>(i)]);
        if (offset == p + 8) table = p;
    }
    REQUIRE(table > 0);
    std::string forged = bytes;
    forged.replace(table + 12, 4, std::string("\xff\xff\xff\x7f", 4));
    test::write_bytes(path, forged);
    check_read_error(read_exr, path, "bad.exr");
    // Garbage pixel bytes may still decode (a chunk whose ZIP data did not shrink is stored raw),
    // so here the contract is only: an image of the right shape, or fovref::Error.
    std::string scrambled = bytes;
    for (std::size_t i = table + 16; i < scrambled.size(); ++i)
        scrambled[i] = static_cast<char>(rng.next_u32() & 0xff);
    test::write_bytes(path, scrambled);
    const std::string message = test::error_message([&] {
        const Image back = read_exr(path);
        if (!back.same_shape(image)) throw Error("wrong shape");
    });
    CHECK((message == "<no exception>" || test::contains(message, "bad.exr")));
}

TEST_CASE("write_file_atomic: failures leave nothing under the target name") {
    test::TempDir dir("err-write");
    // Directory does not exist: cannot even create the temporary file.
    const std::string nowhere = dir.file("no/such/dir/out.pfm");
    check_read_error([](const std::string& p) { write_pfm(p, Image(1, 1, 1)); }, nowhere,
                     "cannot create");
    CHECK_FALSE(std::filesystem::exists(nowhere));

    // The target is a directory: refused before anything is written.
    const std::string target = dir.file("occupied.exr");
    std::filesystem::create_directory(target);
    check_read_error([](const std::string& p) { write_exr(p, Image(2, 2, 3)); }, target,
                     "is a directory");
    CHECK(std::filesystem::is_directory(target));
    int entries = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path)) {
        (void)entry;
        ++entries;
    }
    CHECK(entries == 1);  // only the directory itself; no stray temporary file

    // Overwriting an existing file replaces its contents.
    const std::string file = dir.file("replace.bin");
    write_file_atomic(file, "first version, longer");
    write_file_atomic(file, "second");
    CHECK(read_file(file) == "second");
}
