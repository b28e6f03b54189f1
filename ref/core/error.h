// Errors with context. Every failure that a user can cause (a bad file, a bad parameter) is
// thrown as fovref::Error with a message that names the file and line or the parameter; the CLI
// catches it once, prints the message on one line and exits 2.
#pragma once

#include <stdexcept>
#include <string>
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

/// Checks stay on in every build and print both sides (STYLE.md).
#define FOVREF_CHECK(cond, message)                                                       \
    do {                                                                                  \
        if (!(cond))                                                                      \
            throw ::fovref::Error(std::string("internal check failed: ") + #cond + " (" + \
                                  std::string(message) + ") at " + __FILE__ + ":" +       \
                                  std::to_string(__LINE__));                              \
    } while (0)

}  // namespace fovref
