// libFuzzer target: OBJ + MTL, read three ways: load_scene_file of a fixed scene.json naming
// mesh.obj, and mesh.obj as a bare model file (load_model_file: default camera and light) with the
// quirks of docs/obj-quirks.md accepted and with --strict-obj. The input is the OBJ text, then
// optionally the line "#--mtl--" and the text of mesh.mtl (which the OBJ may name with
// "mtllib mesh.mtl"); tex.pfm exists for map_Kd. tests/fuzz/fuzz_util.h.
#include "ref/scene/scene_file.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool fixtures = [] {
        fovref::fuzz::write("scene.json",
                            "{\"version\": 1, \"meshes\": [{\"obj\": \"mesh.obj\"}], \"camera\": "
                            "{\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"vfov_deg\": 45}}");
        const float pixels[3] = {0.5f, 0.25f, 1.0f};
        std::string pfm = "PF\n1 1\n-1\n";
        pfm.append(reinterpret_cast<const char*>(pixels), sizeof pixels);
        fovref::fuzz::write("tex.pfm", pfm);
        return true;
    }();
    (void)fixtures;
    const std::string input(reinterpret_cast<const char*>(data), size);
    const std::string separator = "#--mtl--\n";
    const std::size_t split = input.find(separator);
    fovref::fuzz::write("mesh.obj", input.substr(0, split));
    fovref::fuzz::write("mesh.mtl", split == std::string::npos
                                        ? std::string()
                                        : input.substr(split + separator.size()));
    fovref::fuzz::expect_error_or_success(
        [&] { fovref::load_scene_file((fovref::fuzz::scratch() / "scene.json").string()); });
    const std::string obj = (fovref::fuzz::scratch() / "mesh.obj").string();
    fovref::fuzz::expect_error_or_success([&] { fovref::load_model_file(obj); });
    fovref::SceneLoadOptions strict;
    strict.strict_obj = true;
    fovref::fuzz::expect_error_or_success([&] { fovref::load_model_file(obj, strict); });
    return 0;
}
