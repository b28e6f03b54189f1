// `fovref golden list|verify|update|export`: the golden cases (golden/cases.json), recomputed
// and compared bit-exactly with their bundles, rewritten, or exported as full bundles at any
// size for a GPU implementation. docs/golden.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

/// The options of `fovref golden` itself, shared by its subcommands.
struct GoldenOptions {
    std::string dir;  ///< golden directory ("": ./golden if it has cases.json, else the source's)
    bool quiet = false;
};

/// `golden verify` and `golden update`: which cases.
struct GoldenCasesOptions {
    std::vector<std::string> cases;  ///< empty: every case
};

struct GoldenExportOptions {
    std::string case_name;             ///< golden case name
    std::string directory;             ///< output directory
    std::optional<int> width, height;  ///< override the case's size
    std::optional<int> frames;         ///< override the case's frame count
    std::vector<std::string> params;   ///< override or add mode parameters, key=value
    bool with_scene = false;           ///< also the scene files into DIR/scene
    bool raw_copies = false;           ///< also .f32 copies of the EXR buffers
    bool timings = false;              ///< stage wall times in the manifest
};

/// Registers --dir on the `golden` command.
void add_golden_options(CLI::App& command, GoldenOptions& options);
/// Registers --case on `golden verify` or `golden update`.
void add_golden_cases_options(CLI::App& command, GoldenCasesOptions& options);
/// Registers the options of `golden export`.
void add_golden_export_options(CLI::App& command, GoldenExportOptions& options);

/// Throw fovref::Error for usage and input errors (the CLI exits 2). run_golden_verify returns
/// 1 when a case differs from its bundle, the others 0.
int run_golden_list(const GoldenOptions& options);
int run_golden_verify(const GoldenOptions& options, const GoldenCasesOptions& cases);
int run_golden_update(const GoldenOptions& options, const GoldenCasesOptions& cases);
int run_golden_export(const GoldenOptions& options, const GoldenExportOptions& export_options);

}  // namespace fovref
