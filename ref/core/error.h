// Errors with context. Every failure that a user can cause (a bad file, a bad parameter) is
// thrown as fovref::Error with a message that names the file and line or the parameter; the CLI
// catches it once, prints the message on one line and exits 2.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace fovref {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// "file:line: message" (line omitted when 0).
inline Error file_error(const std::string& file, int line, const std::string& message) {
    if (line > 0) return Error(file + ":" + std::to_string(line) + ": " + message);
    return Error(file + ": " + message);
}

/// "a, b, c": for messages that list the valid choices.
inline std::string join_names(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
    return text;
}

/// A value in a failed check's message: integers exactly, floats round-trip exact ("%.9g",
/// "%.17g"), strings quoted.
template <class T>
std::string check_value_text(const T& value) {
    if constexpr (std::is_same_v<T, bool>) {
        return value ? "true" : "false";
    } else if constexpr (std::is_integral_v<T> || std::is_enum_v<T>) {
        if constexpr (std::is_enum_v<T>)
            return std::to_string(static_cast<long long>(value));
        else if constexpr (std::is_signed_v<T>)
            return std::to_string(static_cast<long long>(value));
        else
            return std::to_string(static_cast<unsigned long long>(value));
    } else if constexpr (std::is_floating_point_v<T>) {
        char text[40];
        std::snprintf(text, sizeof text, sizeof(T) <= 4 ? "%.9g" : "%.17g",
                      static_cast<double>(value));
        return text;
    } else if constexpr (std::is_convertible_v<const T&, std::string>) {
        return "'" + std::string(value) + "'";
    } else {
        static_assert(sizeof(T) == 0, "FOVREF_CHECK_EQ: no text for this type");
    }
}

/// Checks stay on in every build (a failed one is a bug in fovref, reported with its place).
#define FOVREF_CHECK(cond, message)                                                       \
    do {                                                                                  \
        if (!(cond))                                                                      \
            throw ::fovref::Error(std::string("internal check failed: ") + #cond + " (" + \
                                  std::string(message) + ") at " + __FILE__ + ":" +       \
                                  std::to_string(__LINE__));                              \
    } while (0)

/// FOVREF_CHECK(a == b) that prints both values: "internal check failed: texels == expected
/// (852 != 853; the texel count) at file:line".
#define FOVREF_CHECK_EQ(a, b, message)                                                          \
    do {                                                                                        \
        const auto& fovref_check_a_ = (a);                                                      \
        const auto& fovref_check_b_ = (b);                                                      \
        if (!(fovref_check_a_ == fovref_check_b_))                                              \
            throw ::fovref::Error(std::string("internal check failed: ") + #a + " == " + #b +   \
                                  " (" + ::fovref::check_value_text(fovref_check_a_) +          \
                                  " != " + ::fovref::check_value_text(fovref_check_b_) + "; " + \
                                  std::string(message) + ") at " + __FILE__ + ":" +             \
                                  std::to_string(__LINE__));                                    \
    } while (0)

}  // namespace fovref
