// libFuzzer target: a scene texture (PNG, PFM or EXR by the first byte), named by map_Kd in a
// fixed OBJ + MTL and loaded with the scene: decoding, the RGB conversion, the NaN check and the
// scene's texture limit. tests/fuzz/fuzz_util.h.
#include "ref/scene/scene_file.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* extensions[] = {".png", ".pfm", ".exr"};
    const std::string ext = extensions[data[0] % 3];
    fovref::fuzz::write("tex" + ext, data + 1, size - 1);
    fovref::fuzz::write("tex.mtl", "newmtl t\nKd 1 1 1\nmap_Kd tex" + ext + "\n");
    fovref::fuzz::write("tex.obj",
                        "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                        "usemtl t\nf 1/1 2/2 3/3\n");
    const std::string scene = fovref::fuzz::write(
        "tex_scene.json",
        "{\"version\": 1, \"meshes\": [{\"obj\": \"tex.obj\"}], \"camera\": {\"position\": [0, 0, "
        "5], \"look_at\": [0, 0, 0], \"vfov_deg\": 45}}");
    fovref::fuzz::expect_error_or_success([&] { fovref::load_scene_file(scene); });
    return 0;
}
