#include "tools/cli/common/output_dir.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include "ref/core/error.h"

namespace fs = std::filesystem;

namespace fovref {

namespace {

// The absolute, lexically normal form of a path (nothing need exist).
fs::path normal(const std::string& path) {
    fs::path p = fs::absolute(path).lexically_normal();
    if (!p.has_filename() && p.has_parent_path()) p = p.parent_path();  // "out/" -> "out"
    return p;
}

// True when `inner` is `outer` or lies below it.
bool inside(const fs::path& inner, const fs::path& outer) {
    const fs::path relative = inner.lexically_relative(outer);
    return !relative.empty() && *relative.begin() != "..";
}

}  // namespace

void check_output_directory(const std::string& option, const std::string& path) {
    if (path.empty()) throw Error(option + ": an empty path");
    std::error_code ec;
    fs::path p = normal(path);
    if (fs::exists(p, ec) && !fs::is_directory(p, ec))
        throw Error(option + " " + path + ": exists and is not a directory");
    // The nearest existing ancestor must be a directory we can write into.
    while (!fs::exists(p, ec) && p.has_parent_path() && p.parent_path() != p) p = p.parent_path();
    if (!fs::is_directory(p, ec))
        throw Error(option + " " + path + ": " + p.string() + " is not a directory");
    if (::access(p.c_str(), W_OK | X_OK) != 0)
        throw Error(option + " " + path + ": cannot write into " + p.string());
}

void check_separate_outputs(const std::vector<std::pair<std::string, std::string>>& outputs) {
    for (std::size_t a = 0; a < outputs.size(); ++a)
        for (std::size_t b = 0; b < outputs.size(); ++b) {
            if (a == b || outputs[a].second.empty() || outputs[b].second.empty()) continue;
            const fs::path pa = normal(outputs[a].second), pb = normal(outputs[b].second);
            if (a < b && pa == pb)
                throw Error(outputs[a].first + " and " + outputs[b].first +
                            " name the same "
                            "directory (" +
                            outputs[a].second + "): give two directories");
            if (pa != pb && inside(pa, pb))
                throw Error(outputs[a].first + " " + outputs[a].second + " lies inside " +
                            outputs[b].first + " " + outputs[b].second +
                            ": give directories side by side");
        }
}

OutputDirectory::OutputDirectory(std::string option, std::string path)
    : option_(std::move(option)), path_(std::move(path)) {
    check_output_directory(option_, path_);
    // The staging directory goes into the nearest existing ancestor, so that a failure creates
    // no folder on the way to the target.
    const fs::path target = normal(path_);
    fs::path existing = target.parent_path();
    std::error_code ec;
    while (!fs::exists(existing, ec) && existing.has_parent_path() &&
           existing.parent_path() != existing)
        existing = existing.parent_path();
    staging_ = (existing / ("." + target.filename().string() + ".writing-" +
                            std::to_string(static_cast<long long>(::getpid()))))
                   .string();
}

OutputDirectory::~OutputDirectory() {
    std::error_code ec;
    if (!committed_) fs::remove_all(staging_, ec);
}

std::string OutputDirectory::file(const std::string& name) {
    const fs::path p = fs::path(staging_) / name;
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    if (ec)
        throw Error(option_ + " " + path_ + ": cannot create " + p.parent_path().string() + ": " +
                    ec.message());
    if (std::find(files_.begin(), files_.end(), name) == files_.end()) files_.push_back(name);
    return p.string();
}

void OutputDirectory::commit() {
    std::error_code ec;
    const fs::path target(path_);
    for (const std::string& name : files_) {
        const fs::path to = target / name;
        fs::create_directories(to.parent_path(), ec);
        if (ec) break;
        fs::rename(fs::path(staging_) / name, to, ec);
        if (ec) break;
    }
    if (ec) throw Error(option_ + " " + path_ + ": cannot move the results in: " + ec.message());
    committed_ = true;
    fs::remove_all(staging_, ec);
}

}  // namespace fovref
