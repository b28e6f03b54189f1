// What the command modules of `fovref` (tools/cli/commands/*.h, tools/cli/bench/*.h) share: the
// exit codes, the line printer that -q silences, and the render case that `render` and `probe`
// describe with their options.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "ref/golden/bundle.h"
#include "ref/scene/scene.h"
#include "ref/scene/scene_file.h"
#include "ref/stage/pipeline.h"

namespace CLI {
class App;
class Option;
class Option;
}  // namespace CLI

namespace fovref {

/// Exit codes of fovref: 0 ok, 1 a check failed (golden verify, diff, probe), 2 usage or input
/// error.
constexpr int exit_ok = 0, exit_check_failed = 1, exit_usage = 2;

/// Prints `line` and a newline on stdout unless `quiet` (-q).
void say(bool quiet, const std::string& line);

/// The median (the mean of the two middle values for an even count; 0 for none).
double median_of(std::vector<double> values);

/// fovref's data directory (golden/, scenes/, tools/*.py): <the executable's directory>/
/// ../share/fovref when that holds golden/cases.json (an installed fovref, docs/install.md), else
/// the source tree the binary was built from.
std::string data_directory();

/// How this run of fovref reads scenes: --strict-obj and --camera of the command that runs.
SceneLoadOptions& cli_scene_options();

/// Registers --strict-obj and (unless `with_camera` is false: `rays` has a --camera flag of its
/// own) --camera FILE on a command that takes a scene; they set cli_scene_options().
void add_scene_load_options(CLI::App& command, bool with_camera = true);

/// load_scene with cli_scene_options(): what every command uses for its --scene. A relative path
/// that names nothing in the working directory is looked up in data_directory() (so
/// `--scene scenes/textured-room` works from anywhere). With `report`,
/// a scene with load warnings, unsupported features or defaults gets one summary line on
/// stderr and its first three warnings (`scene info` lists them all).
Scene load_cli_scene(const std::string& name_or_path, bool report = true);

/// The help of --scene for a command that renders one scene.
inline constexpr const char* scene_option_help =
    "procedural scene, scene file/directory, or model file (.obj, .gltf, .glb)";

/// The scene options of a command that renders one scene: --scene (`help`), --strict-obj and
/// --camera (add_scene_load_options). Returns --scene (to mark it required or show its default).
CLI::Option* add_scene_options(CLI::App& command, std::string& scene,
                               const std::string& help = scene_option_help);
/// The scene options of a command that takes several scenes (a repeatable --scene; default:
/// every procedural scene).
CLI::Option* add_scenes_options(CLI::App& command, std::vector<std::string>& scenes);

/// The screen options --width and --height ("screen width" + `of`), their defaults shown; with
/// `min_side` > 0 checked to [min_side, 16384] (without, the render's own settings check names
/// the bad value).
void add_screen_options(CLI::App& command, int& width, int& height, const std::string& of = "",
                        int min_side = 0);

/// The error-range options: --rings (1 .. 1000 rings of eccentricity) and --max-range (the
/// fraction of the largest eccentricity they cover), their defaults shown.
void add_ring_options(CLI::App& command, int& rings, float& max_range);

/// The options `fovref render` and `fovref probe` share: the case they render.
struct CaseOptions {
    std::string scene;                ///< procedural scene name or scene file ("": none)
    std::string mode = "splat";       ///< render mode (`fovref modes`)
    int width = 320, height = 180;    ///< screen size in pixels
    float time_start = 0.0f;          ///< camera-path time of frame 0
    float time_step = 1.0f / 30;      ///< camera-path time between frames
    std::vector<std::string> params;  ///< mode parameters, key=value
    std::string gaze;                 ///< --gaze X,Y: the foveated modes' gaze=X,Y ("": unset)
};

/// --gaze "X,Y" in pixels; "" = the screen centre. Throws fovref::Error when malformed.
glm::vec2 parse_gaze(const std::string& text, int width, int height);

/// Registers --gaze X,Y on a command whose options derive from CaseOptions.
void add_gaze_option(CLI::App& command, CaseOptions& options);

/// The case the options describe, named `name`, with one frame.
GoldenCase command_case(const CaseOptions& options, const std::string& name);

/// What a command that renders a case resolves once from its options and hands down: the case
/// (scene, mode name, size, times, parameters), its mode and its scene (none for a mode that
/// needs none). No layer below looks the mode or the scene up again.
struct ResolvedCase {
    GoldenCase run;
    const ModeInfo* mode = nullptr;
    std::optional<Scene> scene;
    const Scene* scene_or_null() const { return scene ? &*scene : nullptr; }
};

/// The mode (fovref::Error listing the modes for an unknown one), the scene
/// and the case (as command_case, named `command`), in that order. The scene: none for a mode
/// that needs none; fovref::Error ("COMMAND: mode 'M' needs --scene") when it needs one and
/// --scene is missing.
ResolvedCase resolve_case(const CaseOptions& options, const std::string& command);

}  // namespace fovref
