// vk_passes: fovref's passes as a Vulkan compute port (issue 30's client). Each pass reads a
// golden bundle's own input buffers, runs its compute shaders and writes its output under the
// bundle's names, so that `fovref diff` checks that pass alone (an error cannot cascade):
//
//   fovref golden export textured-room-ckfov-gaze-lerp gold --raw-copies
//   vk_passes lerp gold out            # out/f000_final.pfm ..., out/port.json
//   fovref diff gold out --profile vulkan
//
// The passes are in passes/*.cpp (`vk_passes --help` lists them), their shaders in
// shaders/*.comp. Options: --lavapipe (the CPU device even when a GPU is there; default: a GPU
// first), --bug (the shaders built with -DINJECT_BUG: each pass's typical porting bug, for the
// diff to catch). It depends on nothing of fovref's; the dump's port.json records the
// device, driver, float controls, the injected bug and the pass's device time. Exit 0 on
// success, 2 on any error.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/clients/vulkan/pass.h"

using namespace fovref_client;

namespace {

int usage(const std::vector<Pass>& passes) {
    std::fprintf(stderr,
                 "usage: vk_passes [--lavapipe] [--bug] PASS BUNDLE OUT_DIR\n"
                 "  runs one of fovref's passes as Vulkan compute shaders on a golden bundle's\n"
                 "  own inputs (export it with `fovref golden export CASE DIR --raw-copies`)\n"
                 "  and writes its output for `fovref diff DIR OUT_DIR --profile vulkan`\n"
                 "  --lavapipe  run on Mesa's CPU device even when a GPU is there\n"
                 "  --bug       the shaders with the pass's injected porting bug\n"
                 "  --repeat=N  run the pass N times and record the fastest run's times\n"
                 "passes:\n");
    for (const Pass& p : passes)
        std::fprintf(stderr, "  %-18s %s\n  %-18s (bug: %s)\n", p.name.c_str(), p.summary.c_str(),
                     "", p.injected_bug.c_str());
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<Pass> passes = registered_passes();
    DevicePreference preference = DevicePreference::any;
    bool bug = false;
    int repeat = 1;
    std::vector<std::string> positional;
    for (int k = 1; k < argc; ++k) {
        const std::string a = argv[k];
        if (a == "--device=lavapipe" || a == "--lavapipe")
            preference = DevicePreference::lavapipe;
        else if (a == "--bug")
            bug = true;
        else if (a.rfind("--repeat=", 0) == 0)
            repeat = std::max(1, std::atoi(a.c_str() + 9));
        else if (a == "-h" || a == "--help")
            return usage(passes), 0;
        else
            positional.push_back(a);
    }
    const Pass* pass = nullptr;
    for (const Pass& p : passes)
        if (!positional.empty() && p.name == positional[0]) pass = &p;
    if (positional.size() != 3 || !pass) {
        if (!positional.empty() && !pass)
            std::fprintf(stderr, "vk_passes: unknown pass '%s'\n", positional[0].c_str());
        return usage(passes);
    }
    const std::string bundle = positional[1], out = positional[2];
    try {
        const json manifest = json::parse(read_text(bundle + "/manifest.json"));
        VulkanCompute vk(preference);
        std::error_code ec;
        std::filesystem::create_directories(out, ec);
        if (ec) throw std::runtime_error(out + ": cannot create directory: " + ec.message());
        // --repeat=N: the pass N times, the fastest run's times (the first run also pays for
        // the driver's shader compilation, which lavapipe does at the first dispatch)
        PassContext ctx{vk, manifest, bundle, out, bug};
        int frames = 0;
        double wall_ms = 0.0, device_ms = 0.0;
        for (int k = 0; k < repeat; ++k) {
            ctx.device_ms = 0.0;
            ctx.dispatches = 0;
            const auto start = std::chrono::steady_clock::now();
            frames = pass->run(ctx);
            const double ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                    .count();
            wall_ms = k == 0 ? ms : std::min(wall_ms, ms);
            device_ms = k == 0 ? ctx.device_ms : std::min(device_ms, ctx.device_ms);
        }
        json record{{"pass", pass->name},
                    {"case", manifest.at("case").value("name", "")},
                    {"device", vk.device_description()},
                    {"float_controls", vk.float_controls()},
                    {"injected_bug", bug ? pass->injected_bug : ""},
                    {"frames", frames},
                    {"dispatches", ctx.dispatches},
                    {"device_ms", device_ms},
                    {"wall_ms", wall_ms},
                    {"runs", repeat}};
        for (const auto& [key, value] : ctx.notes.items()) record[key] = value;
        std::ofstream(out + "/port.json") << record.dump(1) << "\n";
        std::fprintf(stderr, "vk_passes: %s, %d frame(s), %d dispatch(es), %.2f ms on %s\n",
                     pass->name.c_str(), frames, ctx.dispatches, device_ms,
                     vk.device_description().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vk_passes: %s: %s\n", pass->name.c_str(), e.what());
        return 2;
    }
    return 0;
}
