#include "ref/stage/params.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>

#include "ref/core/error.h"

namespace fovref {

namespace {

// A bound in a message: "%.9g" (64, not 64.000000; 3.40282347e+38).
std::string bound_text(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
    return text;
}

}  // namespace

void Params::set_from_assignment(const std::string& assignment) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0)
        throw Error("parameter '" + assignment + "': expected key=value");
    values_[assignment.substr(0, eq)] = assignment.substr(eq + 1);
}

Params Params::from_assignments(const std::vector<std::string>& assignments) {
    Params params;
    for (const std::string& assignment : assignments) {
        Params one;
        one.set_from_assignment(assignment);
        const auto& [key, value] = *one.values_.begin();
        if (params.given(key))
            throw Error("parameter '" + key + "' is given twice (" + key + "=" +
                        params.values_[key] + ", " + key + "=" + value + "): give it once");
        params.values_[key] = value;
    }
    return params;
}

void Params::check_known(const std::vector<ParamSpec>& specs, const std::string& mode) const {
    for (const auto& [key, value] : values_) {
        bool known = false;
        for (const ParamSpec& spec : specs) known = known || spec.name == key;
        if (!known) {
            std::string names;
            for (const ParamSpec& spec : specs) names += (names.empty() ? "" : ", ") + spec.name;
            throw Error("parameter '" + key + "' is not a parameter of mode '" + mode + "'" +
                        (names.empty() ? " (it takes none)" : " (it takes: " + names + ")"));
        }
    }
}

std::string Params::get_string(const std::vector<ParamSpec>& specs, const std::string& key) const {
    auto it = values_.find(key);
    if (it != values_.end()) return it->second;
    for (const ParamSpec& spec : specs)
        if (spec.name == key) return spec.default_value;
    throw Error("internal: parameter '" + key + "' has no specification");
}

float Params::get_float(const std::vector<ParamSpec>& specs, const std::string& key, float min,
                        float max) const {
    const std::string text = get_string(specs, key);
    float value = 0.0f;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec == std::errc::result_out_of_range ||
        (ec == std::errc() && end == text.data() + text.size() && std::isinf(value)))
        throw Error("parameter '" + key + "': " + text + " is outside [" + bound_text(min) + ", " +
                    bound_text(max) + "] (beyond the float range)");
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        throw Error("parameter '" + key + "': '" + text + "' is not a finite number");
    if (value < min || value > max)
        throw Error("parameter '" + key + "': " + text + " is outside [" + bound_text(min) + ", " +
                    bound_text(max) + "]");
    return value;
}

int Params::get_int(const std::vector<ParamSpec>& specs, const std::string& key, int min,
                    int max) const {
    const std::string text = get_string(specs, key);
    int value = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size())
        throw Error("parameter '" + key + "': '" + text + "' is not an integer");
    if (value < min || value > max)
        throw Error("parameter '" + key + "': " + text + " is outside [" + std::to_string(min) +
                    ", " + std::to_string(max) + "]");
    return value;
}

std::vector<float> Params::get_float_list(const std::vector<ParamSpec>& specs,
                                          const std::string& key) const {
    const std::string text = get_string(specs, key);
    std::vector<float> values;
    if (text.find_first_not_of(' ') == std::string::npos) return values;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        std::size_t first = text.find_first_not_of(' ', start);
        std::size_t last = text.find_last_not_of(' ', comma == 0 ? 0 : comma - 1);
        if (first == std::string::npos || first >= comma) first = last = comma;
        const std::string item = first < comma ? text.substr(first, last + 1 - first) : "";
        float value = 0.0f;
        auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
        if (item.empty() || ec != std::errc() || end != item.data() + item.size() ||
            !std::isfinite(value))
            throw Error("parameter '" + key + "': '" + item + "' in '" + text +
                        "' is not a finite number (expected a comma-separated list)");
        values.push_back(value);
        if (comma == text.size()) break;
        start = comma + 1;
    }
    return values;
}

std::size_t Params::get_choice(const std::vector<ParamSpec>& specs, const std::string& key,
                               const std::vector<std::string>& choices) const {
    const std::string text = get_string(specs, key);
    std::string expected;
    for (std::size_t i = 0; i < choices.size(); ++i) {
        if (choices[i] == text) return i;
        expected += (i == 0 ? "'" : i + 1 == choices.size() ? " or '" : ", '") + choices[i] + "'";
    }
    throw Error("parameter '" + key + "': expected " + expected + ", got '" + text + "'");
}

bool Params::get_bool(const std::vector<ParamSpec>& specs, const std::string& key) const {
    const std::string text = get_string(specs, key);
    if (text == "1" || text == "true" || text == "on") return true;
    if (text == "0" || text == "false" || text == "off") return false;
    throw Error("parameter '" + key + "': '" + text + "' is not a boolean (true/false)");
}

}  // namespace fovref
