// Procedural scenes (SPEC §2), generated in code and deterministically (dm:: math only), so
// tests and benchmarks never depend on downloads.
#pragma once

#include <string>
#include <vector>

#include "ref/scene/scene.h"

namespace fovref {

struct ProceduralSceneInfo {
    std::string name;
    std::string description;
};

/// cornell, sphere-grid, million, checker-room, glossy-floor.
const std::vector<ProceduralSceneInfo>& procedural_scenes();

bool is_procedural_scene(const std::string& name);

/// Build a procedural scene by name; throws fovref::Error listing the valid names otherwise.
Scene make_procedural_scene(const std::string& name);

}  // namespace fovref
