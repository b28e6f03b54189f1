#include "tools/cli_common.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>

#include "ref/core/error.h"
#include "ref/modes/modes.h"
#include "ref/scene/scene_file.h"

namespace fovref {

void say(bool quiet, const std::string& line) {
    if (!quiet) std::cout << line << "\n";
}

GoldenCase command_case(const CaseOptions& o, const std::string& name) {
    GoldenCase run;
    run.name = name;
    run.scene = o.scene;
    run.mode = o.mode;
    run.width = o.width;
    run.height = o.height;
    run.frames = 1;
    run.time_start = o.time_start;
    run.time_step = o.time_step;
    for (const std::string& p : o.params) run.params.set_from_assignment(p);
    if (!o.gaze.empty()) {
        if (run.params.given("gaze"))
            throw Error(name + ": --gaze and --param gaze=... both given; give one");
        run.params.set("gaze", o.gaze);
    }
    return run;
}

void add_gaze_option(CLI::App& c, CaseOptions& o) {
    c.add_option("--gaze", o.gaze,
                 "gaze point X,Y in screen pixels for the foveated modes (any finite point, off "
                 "screen too; default the screen centre) (= --param gaze=X,Y)");
}

std::optional<Scene> command_scene(const CaseOptions& o, const std::string& command) {
    if (!find_mode(o.mode).needs_scene) return std::nullopt;
    if (o.scene.empty()) throw Error(command + ": mode '" + o.mode + "' needs --scene");
    return load_scene(o.scene);
}

double median_of(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace fovref
