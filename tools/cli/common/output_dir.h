// Output directories of fovref's commands (--out, --dump, --html, OUT_DIR): checked before any
// work, written through a staging directory, and moved into place only when the command has
// finished, so a failure at any point leaves nothing behind (docs/limits.md, Outputs).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace fovref {

/// Throws fovref::Error naming `option` when `path` cannot be an output directory: empty, an
/// existing file (not a directory), or below an existing file or a directory this process cannot
/// write into. Creates nothing.
void check_output_directory(const std::string& option, const std::string& path);

/// Throws fovref::Error when two of the (option, path) outputs are the same directory or one
/// lies inside another (`render --out X --dump X/d`). Empty paths are skipped.
void check_separate_outputs(const std::vector<std::pair<std::string, std::string>>& outputs);

/// The files a command writes into one output directory: checked on construction
/// (check_output_directory), written into a staging directory beside it (`file`), moved into the
/// directory (created if need be) by commit(). Without commit() the staging directory is
/// removed and the target is untouched.
class OutputDirectory {
public:
    OutputDirectory(std::string option, std::string path);
    OutputDirectory(const OutputDirectory&) = delete;
    OutputDirectory& operator=(const OutputDirectory&) = delete;
    ~OutputDirectory();

    /// The path to write file `name` (a relative path) to now; its folders are created.
    std::string file(const std::string& name);
    /// Moves every written file into the target, replacing files of the same name.
    void commit();
    const std::string& path() const { return path_; }

private:
    std::string option_, path_, staging_;
    std::vector<std::string> files_;
    bool committed_ = false;
};

}  // namespace fovref
