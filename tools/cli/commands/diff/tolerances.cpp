#include <algorithm>
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "tools/cli/commands/diff/internal.h"

namespace fovref {

namespace {

// Throws when `key` (from `origin`) names no buffer of `names`.
void check_key(const std::string& key, const std::string& origin,
               const std::vector<std::string>& names) {
    const bool pattern = key.find('*') != std::string::npos;
    for (const std::string& name : names)
        if (pattern ? tolerance_pattern_matches(key, name) : key == name) return;
    std::string nearest;
    if (pattern) {
        // The golden's families: "gbuffer_* (9 buffers)", a name without '_' as it is
        std::vector<std::pair<std::string, int>> families;
        for (const std::string& name : names) {
            const std::size_t underscore = name.find('_');
            const std::string family =
                underscore == std::string::npos ? name : name.substr(0, underscore + 1) + "*";
            auto it = std::find_if(families.begin(), families.end(),
                                   [&](const auto& f) { return f.first == family; });
            if (it == families.end())
                families.emplace_back(family, 1);
            else
                ++it->second;
        }
        for (const auto& [family, count] : families)
            nearest += (nearest.empty() ? "" : ", ") + family +
                       (count > 1 ? " (" + std::to_string(count) + ")" : "");
        throw Error(origin + ": the pattern '" + key +
                    "' matches no buffer of the golden (it has: " + nearest + ")");
    }
    for (const std::string& n : nearest_names(key, names))
        nearest += (nearest.empty() ? "" : ", ") + n;
    throw Error(origin + ": the golden has no buffer '" + key + "' (nearest: " + nearest +
                "; `fovref diff GOLDEN CANDIDATE` lists them all)");
}

}  // namespace

ToleranceTable diff_tolerances(const DiffOptions& o, const std::vector<std::string>& names) {
    ToleranceTable tolerances = tolerance_profile(o.profile, names);
    std::vector<std::pair<std::string, std::string>> given;  // (key, where it was given)
    if (!o.tolerance_file.empty()) {
        ToleranceTable file;
        read_tolerance_file(o.tolerance_file, file);
        for (const auto& [key, t] : file.buffers) {
            tolerances.buffers[key] = t;
            given.emplace_back(key, "tolerance file " + o.tolerance_file);
        }
    }
    for (const std::string& option : o.tolerances) {
        ToleranceTable one;
        parse_tolerance_option(option, one);
        for (const auto& [key, t] : one.buffers) {
            tolerances.buffers[key] = t;
            given.emplace_back(key, "--tolerance '" + option + "'");
        }
    }
    for (const auto& [key, origin] : given)
        if (key != "*") check_key(key, origin, names);
    return tolerances;
}

}  // namespace fovref
