#include "tools/cli/commands/modes.h"

#include <algorithm>
#include <cstdio>

#include "ref/modes/modes.h"
#include "tools/cli/common/cli_common.h"

namespace fovref {

int run_modes() {
    int name_width = 4;  // the names' column: as wide as the longest
    for (const ModeInfo& mode : render_modes())
        name_width = std::max(name_width, static_cast<int>(mode.name.size()));
    for (const ModeInfo& mode : render_modes()) {
        std::printf("%-*s %s%s\n", name_width, mode.name.c_str(), mode.description.c_str(),
                    mode.needs_scene ? "" : " (no scene needed)");
        for (const ParamSpec& p : mode.params)
            std::printf("    --param %s=<%s>  %s\n", p.name.c_str(), p.default_value.c_str(),
                        p.doc.c_str());
    }
    return exit_ok;
}

}  // namespace fovref
