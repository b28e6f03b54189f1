// `fovref scene info|export|list`: what a scene holds (and what its loader dropped or repaired),
// any scene written as files, and the procedural scenes. docs/scene-format.md describes scene
// files, docs/procedural-scenes.md the procedural ones.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace fovref {

struct SceneInfoOptions {
    std::string scene;  ///< procedural scene name or scene file/directory
    bool json = false;  ///< machine-readable output
};

struct SceneExportOptions {
    std::string scene;      ///< procedural scene name or scene file
    std::string directory;  ///< output directory (created)
    bool quiet = false;
};

/// Registers the options of `scene info` and `scene export` on their subcommands.
void add_scene_info_options(CLI::App& command, SceneInfoOptions& options);
void add_scene_export_options(CLI::App& command, SceneExportOptions& options);

/// Each returns 0; they throw fovref::Error for usage and input errors (the CLI exits 2).
int run_scene_info(const SceneInfoOptions& options);
int run_scene_export(const SceneExportOptions& options);
int run_scene_list();

}  // namespace fovref
