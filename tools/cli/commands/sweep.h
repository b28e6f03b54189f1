// `fovref sweep` (issue 17): run time against error over a grid of configurations.
//   plan FILE OUT      expand a sweep file (docs/sweeps.md) into jobs: OUT/plan.json, jobs.txt
//   job OUT K          run job K of the plan (idempotent: skipped when its result is there for
//                      the same inputs); what `run`, GNU parallel, Slurm and Kubernetes call
//   run OUT [--jobs N] every job as a separate single-threaded process, references first
//   merge OUT          the results into OUT/results.csv and OUT/results.json
//   export OUT --format parallel|slurm|k8s   job lists and scripts for an existing engine
//   report OUT --html DIR   Pareto fronts, ring-error curves, the table of configurations
//                           (tools/cli/report/sweep_report.cpp)
// Every job is one `fovref evaluate` run; the reference frames of a scene, screen and camera path
// are a job of their own, computed once and shared (evaluate --reference-dir).
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace fovref {

struct SweepOptions {
    std::string file;               ///< plan: the sweep file
    std::string out;                ///< the sweep directory
    int job = -1;                   ///< job: its index in the plan
    int jobs = 1;                   ///< run: processes at a time
    std::string format;             ///< export: parallel, slurm or k8s
    std::string fovref = "fovref";  ///< export: the fovref command on the machines that run jobs
    std::string image = "fovref:latest";  ///< export k8s: the container image
    std::string html;                     ///< report: the output directory
    std::string metric = "psnr";          ///< report: psnr, ssim, flip or temporal
    bool quiet = false;
};

/// The options of each subcommand of `sweep` (tools/cli/options/command_options.cpp; the
/// subcommands are made by tools/cli/fovref.cpp).
void add_sweep_plan_options(CLI::App& command, SweepOptions& options);
void add_sweep_job_options(CLI::App& command, SweepOptions& options);
void add_sweep_run_options(CLI::App& command, SweepOptions& options);
void add_sweep_merge_options(CLI::App& command, SweepOptions& options);
void add_sweep_export_options(CLI::App& command, SweepOptions& options);
void add_sweep_report_options(CLI::App& command, SweepOptions& options);

int run_sweep_plan(const SweepOptions& options);
int run_sweep_job(const SweepOptions& options);
int run_sweep_run(const SweepOptions& options);
int run_sweep_merge(const SweepOptions& options);
int run_sweep_export(const SweepOptions& options);
int run_sweep_report(const SweepOptions& options);

}  // namespace fovref
