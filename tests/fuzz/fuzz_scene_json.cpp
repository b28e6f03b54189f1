// libFuzzer target: scene.json (load_scene_file), next to a small valid OBJ, MTL and texture that
// the document may name (tri.obj, tri.mtl with material "red", tex.pfm). tests/fuzz/fuzz_util.h.
#include "ref/scene/scene_file.h"
#include "tests/fuzz/fuzz_util.h"

namespace {

void write_fixtures() {
    static const bool done = [] {
        fovref::fuzz::write("tri.obj",
                            "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                            "vn 0 0 1\nusemtl red\nf 1/1/1 2/2/1 3/3/1\n");
        fovref::fuzz::write("tri.mtl", "newmtl red\nKd 0.8 0.1 0.1\nmap_Kd tex.pfm\n");
        const float pixels[12] = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f,
                                  0.7f, 0.8f, 0.9f, 1.0f, 0.0f, 0.5f};
        std::string pfm = "PF\n2 2\n-1\n";
        pfm.append(reinterpret_cast<const char*>(pixels), sizeof pixels);
        fovref::fuzz::write("tex.pfm", pfm);
        return true;
    }();
    (void)done;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    write_fixtures();
    const std::string path = fovref::fuzz::write("scene.json", data, size);
    fovref::fuzz::expect_error_or_success([&] { fovref::load_scene_file(path); });
    return 0;
}
