// Mode parameters: plain key = value pairs, validated against each mode's declared list, with
// documented defaults. A bad value is an error naming the parameter.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace fovref {

struct ParamSpec {
    std::string name;
    std::string default_value;
    std::string doc;
};

/// `a` followed by `b`: a mode's parameter list made of its parts' lists.
inline std::vector<ParamSpec> concat_specs(std::vector<ParamSpec> a,
                                           const std::vector<ParamSpec>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

class Params {
public:
    Params() = default;
    explicit Params(std::map<std::string, std::string> values) : values_(std::move(values)) {}

    /// Parses "key=value" (replacing an earlier value of the key); throws fovref::Error when
    /// malformed.
    void set_from_assignment(const std::string& assignment);
    /// The parameters of a list of "key=value" given on a command line: throws fovref::Error
    /// for a malformed one or a key given twice (`--param alpha=2 --param alpha=3`).
    static Params from_assignments(const std::vector<std::string>& assignments);
    void set(const std::string& key, const std::string& value) { values_[key] = value; }

    /// Throws fovref::Error naming the first key that is not in `specs`.
    void check_known(const std::vector<ParamSpec>& specs, const std::string& mode) const;

    // Typed getters: the value given, else the spec's default; a malformed or out-of-range value
    // throws fovref::Error("parameter 'name': ...").
    std::string get_string(const std::vector<ParamSpec>& specs, const std::string& key) const;
    float get_float(const std::vector<ParamSpec>& specs, const std::string& key, float min,
                    float max) const;
    int get_int(const std::vector<ParamSpec>& specs, const std::string& key, int min,
                int max) const;
    bool get_bool(const std::vector<ParamSpec>& specs, const std::string& key) const;
    /// The index in `choices` of the value; any other value throws
    /// fovref::Error("parameter 'name': expected 'a', 'b' or 'c', got 'x'").
    std::size_t get_choice(const std::vector<ParamSpec>& specs, const std::string& key,
                           const std::vector<std::string>& choices) const;
    /// A comma-separated list of finite numbers ("0, 0.5,0.5"; spaces allowed around commas);
    /// empty text gives an empty list.
    std::vector<float> get_float_list(const std::vector<ParamSpec>& specs,
                                      const std::string& key) const;
    /// True when the parameter was given (not defaulted).
    bool given(const std::string& key) const { return values_.count(key) != 0; }

    const std::map<std::string, std::string>& values() const { return values_; }
    bool operator==(const Params&) const = default;

private:
    std::map<std::string, std::string> values_;  // ordered: deterministic manifests
};

}  // namespace fovref
