#include "tools/cli/commands/sweep.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "ref/core/error.h"
#include "ref/core/json_locator.h"
#include "ref/golden/bundle.h"
#include "ref/image/image.h"
#include "ref/image/image_io.h"
#include "ref/modes/modes.h"
#include "ref/scene/scene_file.h"
#include "tools/cli/commands/evaluate.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/number_text.h"

extern char** environ;

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace fovref {

namespace {

// ---- The sweep file ---------------------------------------------------------------------------

// Reads a sweep file and reports what is wrong with it as "file:line: /pointer: message".
class SweepFile {
public:
    explicit SweepFile(const std::string& path)
        : path_(path),
          text_(read_file(path)),
          doc_(parse_json_document<json>(text_, path)),
          locator_(text_, path) {
        if (!doc_.is_object()) fail("", "a sweep file is a JSON object (docs/sweeps.md)");
        static const char* known[] = {"scenes", "configurations", "resolutions", "gazes",
                                      "frames", "every",          "reference",   "flip",
                                      "rings",  "time_start",     "time_step",   "repeats"};
        for (const auto& item : doc_.items()) {
            bool is_known = false;
            for (const char* k : known) is_known = is_known || item.key() == k;
            if (!is_known)
                fail("/" + item.key(),
                     "unknown key (known: scenes, configurations, resolutions, gazes, frames, "
                     "every, reference, flip, rings, time_start, time_step, repeats)");
        }
    }

    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
        const int line = locator_.find(pointer).value_line;
        throw Error(path_ + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " +
                    (pointer.empty() ? "" : pointer + ": ") + message);
    }

    const json& doc() const { return doc_; }

    /// A non-empty array of strings at /key, or `fallback` when the key is absent.
    std::vector<std::string> strings(const std::string& key,
                                     const std::vector<std::string>& fallback) const {
        if (!doc_.contains(key)) {
            if (fallback.empty()) fail("", "'" + key + "' is required");
            return fallback;
        }
        const json& v = doc_[key];
        if (!v.is_array() || v.empty()) fail("/" + key, "expected a non-empty array of strings");
        std::vector<std::string> out;
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (!v[i].is_string()) fail(json_pointer_element("/" + key, i), "expected a string");
            out.push_back(v[i].get<std::string>());
        }
        return out;
    }

    int integer(const std::string& key, int fallback, int lo, int hi) const {
        if (!doc_.contains(key)) return fallback;
        const json& v = doc_[key];
        if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
            fail("/" + key,
                 "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return static_cast<int>(v.get<long long>());
    }

    double number(const std::string& key, double fallback) const {
        if (!doc_.contains(key)) return fallback;
        if (!doc_[key].is_number()) fail("/" + key, "expected a number");
        return doc_[key].get<double>();
    }

    bool boolean(const std::string& key, bool fallback) const {
        if (!doc_.contains(key)) return fallback;
        if (!doc_[key].is_boolean()) fail("/" + key, "expected true or false");
        return doc_[key].get<bool>();
    }

private:
    std::string path_, text_;
    json doc_;
    JsonLocator locator_;
};

/// A parameter value of the sweep file as evaluate's --mode text takes it.
std::string param_text(const SweepFile& file, const std::string& pointer, const json& v) {
    std::string text;
    if (v.is_string())
        text = v.get<std::string>();
    else if (v.is_boolean())
        text = v.get<bool>() ? "true" : "false";
    else if (v.is_number())
        text = v.dump();
    else
        file.fail(pointer, "a parameter value is a string, number or boolean");
    if (text.empty() || text.find_first_of(":,= ") != std::string::npos)
        file.fail(pointer, "a parameter value may not be empty or hold ':', ',', '=' or spaces");
    return text;
}

void parse_resolution(const SweepFile& file, const std::string& pointer, const std::string& text,
                      int& width, int& height) {
    char x = 0;
    char rest = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' ||
        width < 11 || height < 11 || width > 16384 || height > 16384)
        file.fail(pointer, "a resolution is WxH with 11 <= W, H <= 16384, got '" + text + "'");
}

std::string short_hash(const std::string& text) {
    return sha256_hex(text.data(), text.size()).substr(0, 12);
}

/// The configurations of one entry of /configurations: its fixed params and every point of
/// its grid (keys in sorted order, the last varying fastest).
std::vector<std::map<std::string, std::string>> expand_configuration(const SweepFile& file,
                                                                     std::size_t index,
                                                                     std::string& mode) {
    const std::string at = json_pointer_element("/configurations", index);
    const json& c = file.doc()["configurations"][index];
    if (!c.is_object()) file.fail(at, "a configuration is an object {\"mode\": ..., ...}");
    for (const auto& [key, value] : c.items())
        if (key != "mode" && key != "params" && key != "grid")
            file.fail(at + "/" + key, "unknown key (known: mode, params, grid)");
    if (!c.contains("mode") || !c["mode"].is_string())
        file.fail(at, "'mode' (a string) is required");
    mode = c["mode"].get<std::string>();
    const ModeInfo* info = nullptr;
    try {
        info = &find_mode(mode);
    } catch (const Error& e) {
        file.fail(at + "/mode", e.what());
    }
    const auto check_key = [&](const std::string& pointer, const std::string& key) {
        for (const ParamSpec& spec : info->params)
            if (spec.name == key) return;
        file.fail(pointer,
                  "mode '" + mode + "' has no parameter '" + key + "' (fovref modes lists them)");
    };
    std::map<std::string, std::string> fixed;
    if (c.contains("params")) {
        if (!c["params"].is_object()) file.fail(at + "/params", "expected an object");
        for (const auto& [key, value] : c["params"].items()) {
            check_key(at + "/params/" + key, key);
            fixed[key] = param_text(file, at + "/params/" + key, value);
        }
    }
    std::vector<std::map<std::string, std::string>> points{fixed};
    if (c.contains("grid")) {
        if (!c["grid"].is_object()) file.fail(at + "/grid", "expected an object of arrays");
        for (const auto& [key, values] : c["grid"].items()) {
            const std::string p = at + "/grid/" + key;
            check_key(p, key);
            if (fixed.count(key)) file.fail(p, "'" + key + "' is in both params and grid");
            if (!values.is_array() || values.empty())
                file.fail(p, "expected a non-empty array of values");
            std::vector<std::map<std::string, std::string>> next;
            for (const auto& point : points)
                for (std::size_t i = 0; i < values.size(); ++i) {
                    auto q = point;
                    q[key] = param_text(file, json_pointer_element(p, i), values[i]);
                    next.push_back(q);
                }
            points = next;
        }
    }
    return points;
}

// ---- The plan ---------------------------------------------------------------------------------

fs::path plan_file(const std::string& out) { return fs::path(out) / "plan.json"; }

json read_plan(const std::string& out) {
    const fs::path path = plan_file(out);
    if (!fs::exists(path))
        throw Error(path.string() + ": no such file (run `fovref sweep plan FILE " + out +
                    "` first)");
    return parse_json_document<json>(read_file(path.string()), path.string());
}

/// evaluate's options for a job of the plan.
EvaluateOptions job_options(const std::string& out, const json& job) {
    EvaluateOptions o;
    o.scene = job["scene"].get<std::string>();
    o.width = job["width"].get<int>();
    o.height = job["height"].get<int>();
    o.frames = job["frames"].get<int>();
    o.every = job["every"].get<int>();
    o.time_start = job["time_start"].get<float>();
    o.time_step = job["time_step"].get<float>();
    o.reference_mode = job["reference"].get<std::string>();
    o.reference_dir =
        (fs::path(out) / "references" / job["reference_id"].get<std::string>()).string();
    o.quiet = true;
    if (job["kind"] == "evaluate") {
        std::string mode = job["mode"].get<std::string>();
        for (const auto& [key, value] : job["params"].items())
            mode += ":" + key + "=" + value.get<std::string>();
        o.modes = {mode};
        if (job["gaze"] != "centre") o.gaze = job["gaze"].get<std::string>();
        o.rings = job["rings"].get<int>();
        o.flip = job["flip"].get<bool>();
        o.repeats = job["repeats"].get<int>();
        o.out_dir = (fs::path(out) / "results" / job["id"].get<std::string>()).string();
    }
    return o;
}

/// The `fovref evaluate` command line of a job (what it computes, for a user to rerun by hand).
std::string evaluate_command(const EvaluateOptions& o) {
    std::string c = "fovref evaluate --scene " + o.scene;
    for (const std::string& m : o.modes) c += " --mode " + m;
    c += " --width " + std::to_string(o.width) + " --height " + std::to_string(o.height) +
         " --frames " + std::to_string(o.frames) + " --every " + std::to_string(o.every);
    if (!o.gaze.empty()) c += " --gaze " + o.gaze;
    if (!o.modes.empty()) c += " --rings " + std::to_string(o.rings);
    if (o.flip) c += " --flip";
    if (o.repeats > 1) c += " --repeats " + std::to_string(o.repeats);
    c += " --reference " + o.reference_mode + " --reference-dir " + o.reference_dir;
    if (!o.out_dir.empty()) c += " --out " + o.out_dir;
    return c;
}

/// What a job's result depends on: its configuration, the scene file's bytes, the version.
std::string inputs_sha(const json& job) {
    std::string text = job["config"].dump() + "\n" + fovref_version();
    const std::string scene = job["scene"].get<std::string>();
    if (fs::is_regular_file(scene)) text += "\n" + read_file(scene);
    return sha256_hex(text.data(), text.size());
}

// ---- Running jobs -----------------------------------------------------------------------------

std::string self_executable() {
    std::error_code error;
    const fs::path self = fs::read_symlink("/proc/self/exe", error);
    if (error) throw Error("sweep run: cannot find the fovref executable (/proc/self/exe)");
    return self.string();
}

/// Runs `fovref sweep job OUT K` for every K in `indices`, at most `parallel` at a time; returns
/// the indices that failed.
std::vector<int> run_processes(const std::string& self, const std::string& out,
                               const std::vector<int>& indices, int parallel, const json& plan,
                               int& finished, int total, bool quiet) {
    std::map<pid_t, std::pair<int, std::chrono::steady_clock::time_point>> running;
    std::vector<int> failed;
    std::size_t next = 0;
    while (next < indices.size() || !running.empty()) {
        while (next < indices.size() && static_cast<int>(running.size()) < parallel) {
            const std::string index = std::to_string(indices[next]);
            std::vector<std::string> args = {self, "sweep", "job", out, index, "-q"};
            std::vector<char*> argv;
            for (std::string& a : args) argv.push_back(a.data());
            argv.push_back(nullptr);
            pid_t pid = 0;
            if (posix_spawn(&pid, self.c_str(), nullptr, nullptr, argv.data(), environ) != 0)
                throw Error("sweep run: cannot start " + self);
            running[pid] = {indices[next], std::chrono::steady_clock::now()};
            ++next;
        }
        int status = 0;
        const pid_t pid = ::waitpid(-1, &status, 0);
        if (pid < 0) throw Error("sweep run: waitpid failed");
        const auto it = running.find(pid);
        if (it == running.end()) continue;
        const int index = it->second.first;
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - it->second.second)
                .count();
        running.erase(it);
        ++finished;
        const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
        if (!ok) failed.push_back(index);
        if (!quiet || !ok)
            std::printf("[%d/%d] %-6s job %d %s (%.2f s)\n", finished, total, ok ? "ok" : "FAILED",
                        index, plan["jobs"][index]["id"].get<std::string>().c_str(), seconds);
        std::fflush(stdout);
    }
    return failed;
}

double mean_of(const json& frames, const char* key, bool& present) {
    double sum = 0.0;
    int count = 0;
    for (const json& f : frames)
        if (f.contains(key) && f[key].is_number()) {
            sum += f[key].get<double>();
            ++count;
        }
    present = count > 0;
    return count > 0 ? sum / count : 0.0;
}

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string q = "\"";
    for (char ch : text) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return q + "\"";
}

}  // namespace

// ---- Commands ---------------------------------------------------------------------------------

namespace {

// A sweep file's grid, read and checked before any job is planned: a bad mode, scene or gaze
// fails the plan, not every job.
struct SweepGrid {
    std::vector<std::string> scenes, resolutions, gazes;
    int frames = 4, every = 1, rings = 20, repeats = 3;
    bool flip = false;
    double time_start = 0.0, time_step = 1.0 / 30.0;
    std::string reference = "ground-truth";
};

SweepGrid read_grid(const SweepFile& file) {
    const json& doc = file.doc();
    SweepGrid g;
    g.scenes = file.strings("scenes", {});
    g.resolutions = file.strings("resolutions", {"320x180"});
    g.gazes = file.strings("gazes", {"centre"});
    g.frames = file.integer("frames", 4, 1, 100000);
    g.every = file.integer("every", 1, 1, 100000);
    g.rings = file.integer("rings", 20, 1, 1000);
    g.repeats = file.integer("repeats", 3, 1, 1000);
    g.flip = file.boolean("flip", false);
    g.time_start = file.number("time_start", 0.0);
    g.time_step = file.number("time_step", 1.0 / 30.0);
    if (doc.contains("reference")) {
        if (!doc["reference"].is_string()) file.fail("/reference", "expected a mode name");
        g.reference = doc["reference"].get<std::string>();
    }
    try {
        find_mode(g.reference);
    } catch (const Error& e) {
        file.fail("/reference", e.what());
    }
    for (std::size_t i = 0; i < g.scenes.size(); ++i) try {
            load_scene(g.scenes[i]);  // a name or a file: it must load now, not in every job
        } catch (const Error& e) {
            file.fail(json_pointer_element("/scenes", i), e.what());
        }
    for (std::size_t i = 0; i < g.gazes.size(); ++i) {
        float x = 0, y = 0;
        char rest = 0;
        if (g.gazes[i] != "centre" &&
            std::sscanf(g.gazes[i].c_str(), "%f,%f%c", &x, &y, &rest) != 2)
            file.fail(json_pointer_element("/gazes", i),
                      "a gaze is \"centre\" or \"X,Y\" in pixels, got '" + g.gazes[i] + "'");
    }
    if (!doc.contains("configurations") || !doc["configurations"].is_array() ||
        doc["configurations"].empty())
        file.fail("", "'configurations' (a non-empty array) is required");
    return g;
}

// The evaluation jobs of one reference: every configuration's parameter sets at every gaze.
void add_evaluations(const SweepFile& file, const SweepGrid& g, const json& rconfig,
                     const std::string& rid, json& evaluations) {
    for (std::size_t c = 0; c < file.doc()["configurations"].size(); ++c) {
        std::string mode;
        for (const auto& params : expand_configuration(file, c, mode))
            for (const std::string& gaze : g.gazes) {
                json config = rconfig;
                config["mode"] = mode;
                config["params"] = params;
                config["gaze"] = gaze;
                config["rings"] = g.rings;
                config["flip"] = g.flip;
                config["repeats"] = g.repeats;
                json job = config;
                job["kind"] = "evaluate";
                job["id"] = mode + "-" + short_hash(config.dump());
                job["reference_id"] = rid;
                job["config"] = config;
                evaluations.push_back(job);
            }
    }
}

// The jobs of the grid: one reference per scene and screen (shared by its evaluations), then the
// evaluations.
void plan_jobs(const SweepFile& file, const SweepGrid& g, json& references, json& evaluations) {
    std::map<std::string, bool> reference_ids;
    for (std::size_t r = 0; r < g.resolutions.size(); ++r) {
        int width = 0, height = 0;
        parse_resolution(file, json_pointer_element("/resolutions", r), g.resolutions[r], width,
                         height);
        for (const std::string& scene : g.scenes) {
            json rconfig = {{"scene", scene},
                            {"reference", g.reference},
                            {"width", width},
                            {"height", height},
                            {"frames", g.frames},
                            {"every", g.every},
                            {"time_start", g.time_start},
                            {"time_step", g.time_step}};
            const std::string rid = "ref-" + short_hash(rconfig.dump());
            if (!reference_ids[rid]) {
                reference_ids[rid] = true;
                json job = rconfig;
                job["kind"] = "reference";
                job["id"] = rid;
                job["reference_id"] = rid;
                job["config"] = rconfig;
                references.push_back(job);
            }
            add_evaluations(file, g, rconfig, rid, evaluations);
        }
    }
}

}  // namespace

int run_sweep_plan(const SweepOptions& o) {
    const SweepFile file(o.file);
    const SweepGrid grid = read_grid(file);
    json references = json::array(), evaluations = json::array();
    plan_jobs(file, grid, references, evaluations);
    json jobs = json::array();
    for (json& j : references) jobs.push_back(std::move(j));
    for (json& j : evaluations) jobs.push_back(std::move(j));
    std::map<std::string, int> seen;
    for (json& job : jobs) {
        if (seen[job["id"].get<std::string>()]++)
            throw Error(o.file + ": two configurations give the same job (" +
                        job["id"].get<std::string>() + "): a grid repeats a value?");
        job["command"] = evaluate_command(job_options(o.out, job));
    }
    fs::create_directories(o.out);
    json plan = {{"sweep_file", fs::absolute(o.file).string()},
                 {"fovref_version", fovref_version()},
                 {"references", references.size()},
                 {"jobs", jobs}};
    write_file_atomic(plan_file(o.out).string(), plan.dump(1) + "\n");
    std::printf("sweep plan: %zu reference job(s) and %zu evaluation job(s) in %s\n",
                references.size(), evaluations.size(), plan_file(o.out).string().c_str());
    std::printf(
        "run them: fovref sweep run %s --jobs N (or: fovref sweep export %s --format "
        "parallel|slurm|k8s)\n",
        o.out.c_str(), o.out.c_str());
    return 0;
}

int run_sweep_job(const SweepOptions& o) {
    const json plan = read_plan(o.out);
    if (o.job < 0 || o.job >= static_cast<int>(plan["jobs"].size()))
        throw Error("sweep job: index " + std::to_string(o.job) + " is not in the plan (0 .. " +
                    std::to_string(static_cast<int>(plan["jobs"].size()) - 1) + ")");
    const json& job = plan["jobs"][o.job];
    EvaluateOptions options = job_options(o.out, job);
    if (job["kind"] == "reference") {
        store_evaluation_reference(options);
        if (!o.quiet)
            std::printf("sweep job %d: reference %s\n", o.job, options.reference_dir.c_str());
        return 0;
    }
    const std::string sha = inputs_sha(job);
    const fs::path target(options.out_dir);
    const fs::path marker = target / "job.json";
    if (fs::exists(marker)) {
        const json done = parse_json_document<json>(read_file(marker.string()), marker.string());
        if (done.value("inputs_sha256", "") == sha) {
            if (!o.quiet)
                std::printf("sweep job %d: %s is done (skipped)\n", o.job, target.string().c_str());
            return 0;
        }
    }
    const fs::path temporary =
        target.string() + ".tmp-" + std::to_string(static_cast<long long>(::getpid()));
    fs::remove_all(temporary);
    options.out_dir = temporary.string();
    const auto start = std::chrono::steady_clock::now();
    try {
        run_evaluate(options);
    } catch (...) {  // nothing half-written stays behind
        std::error_code ignored;
        fs::remove_all(temporary, ignored);
        throw;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    json done = {{"id", job["id"]},           {"index", o.job},
                 {"inputs_sha256", sha},      {"config", job["config"]},
                 {"command", job["command"]}, {"wall_seconds", seconds}};
    write_file_atomic((temporary / "job.json").string(), done.dump(1) + "\n");
    fs::remove_all(target);
    fs::rename(temporary, target);
    if (!o.quiet)
        std::printf("sweep job %d: wrote %s (%.2f s)\n", o.job, target.string().c_str(), seconds);
    return 0;
}

int run_sweep_run(const SweepOptions& o) {
    const json plan = read_plan(o.out);
    const int total = static_cast<int>(plan["jobs"].size());
    const int references = plan["references"].get<int>();
    std::vector<int> first, second;
    for (int k = 0; k < total; ++k) (k < references ? first : second).push_back(k);
    const std::string self = self_executable();
    int finished = 0;
    std::vector<int> failed =
        run_processes(self, o.out, first, o.jobs, plan, finished, total, o.quiet);
    if (!failed.empty()) {
        std::printf(
            "sweep run: %zu reference job(s) failed; rerun one alone to see why: fovref "
            "sweep job %s %d\n",
            failed.size(), o.out.c_str(), failed.front());
        return 1;
    }
    failed = run_processes(self, o.out, second, o.jobs, plan, finished, total, o.quiet);
    if (!failed.empty()) {
        std::printf(
            "sweep run: %zu of %zu job(s) failed; rerun one alone to see why: fovref "
            "sweep job %s %d\n",
            failed.size(), second.size(), o.out.c_str(), failed.front());
        return 1;
    }
    std::printf("sweep run: %d job(s) done; collect them with: fovref sweep merge %s\n", total,
                o.out.c_str());
    return 0;
}

namespace {

// The job's columns of results.csv, up to the status.
std::string job_csv_columns(const json& job) {
    std::string params;
    for (const auto& [key, value] : job["params"].items())
        params += (params.empty() ? "" : " ") + key + "=" + value.get<std::string>();
    return csv_field(job["id"].get<std::string>()) + "," +
           csv_field(job["scene"].get<std::string>()) + "," +
           csv_field(job["mode"].get<std::string>()) + "," + csv_field(params) + "," +
           std::to_string(job["width"].get<int>()) + "," +
           std::to_string(job["height"].get<int>()) + "," +
           csv_field(job["gaze"].get<std::string>()) + "," +
           std::to_string(job["frames"].get<int>()) + "," +
           std::to_string(job["every"].get<int>()) + ",";
}

// Whether the job's result is there and made for the job's inputs.
bool job_done(const fs::path& dir, const json& job) {
    const fs::path marker = dir / "job.json";
    if (!fs::exists(marker)) return false;
    const json d = parse_json_document<json>(read_file(marker.string()), marker.string());
    return d.value("inputs_sha256", "") == inputs_sha(job);
}

// Per stage the median over the evaluated frames (each already the median of the repeats), and
// per counter the mean per evaluated frame; `stage_text` lists the stages for the CSV.
void add_stage_times_and_counters(const json& frames, json& row, std::string& stage_text) {
    std::map<std::string, std::vector<double>> stage_samples;
    std::map<std::string, double> counter_sums;
    for (const json& f : frames) {
        if (f.contains("stage_times"))
            for (const auto& [name, t] : f["stage_times"].items())
                stage_samples[name].push_back(t.get<double>());
        if (f.contains("counters"))
            for (const auto& [name, v] : f["counters"].items())
                counter_sums[name] += v.get<double>();
    }
    json stage_seconds = json::object(), counters = json::object();
    for (const auto& [name, samples] : stage_samples) {
        stage_seconds[name] = median_of(samples);
        stage_text +=
            (stage_text.empty() ? "" : " ") + name + "=" + number_text(median_of(samples), "%.9g");
    }
    for (const auto& [name, sum] : counter_sums)
        counters[name] = sum / static_cast<double>(std::max<std::size_t>(frames.size(), 1));
    row["stage_seconds"] = stage_seconds;
    row["counters_per_frame"] = counters;
}

// The candidate's ring errors as columns of the row.
void add_rings(const json& candidate, json& row) {
    json ring_psnr = json::array(), ring_rmse = json::array(), ring_ssim = json::array(),
         ring_deg = json::array();
    for (const json& ring : candidate["rings"]) {
        ring_psnr.push_back(ring["psnr"]);
        ring_rmse.push_back(ring["rmse"]);
        ring_ssim.push_back(ring["ssim"]);
        ring_deg.push_back(ring["outer_deg"]);
    }
    row["ring_outer_deg"] = ring_deg;
    row["ring_psnr"] = ring_psnr;
    row["ring_rmse"] = ring_rmse;
    row["ring_ssim"] = ring_ssim;
    if (candidate.contains("ring_flip_mean")) row["ring_flip"] = candidate["ring_flip_mean"];
}

// A finished job's row (from its summary.json) and its CSV columns after the status.
std::string add_result(const fs::path& dir, const json& job, json& row) {
    const fs::path summary_file = dir / "summary.json";
    const json summary =
        parse_json_document<json>(read_file(summary_file.string()), summary_file.string());
    const json& candidate = summary["candidates"][0];
    const json& frames = candidate["frames"];
    bool has_flip = false, present = false;
    const double psnr = mean_of(frames, "psnr", present);
    const double ssim = mean_of(frames, "ssim", present);
    const double flip_mean = mean_of(frames, "flip_mean", has_flip);
    const double rays = mean_of(frames, "rays_traced", present);
    const double shaded = mean_of(frames, "pixels_shaded", present);
    std::vector<double> seconds;
    for (const json& f : frames)
        if (f.contains("stage_seconds")) seconds.push_back(f["stage_seconds"].get<double>());
    row["status"] = "done";
    row["psnr"] = psnr;
    row["ssim"] = ssim;
    if (has_flip) row["flip_mean"] = flip_mean;
    // null (not finite) in summary.json stays null here
    row["temporal_error"] =
        candidate.contains("temporal_error") && candidate["temporal_error"].is_number()
            ? json(candidate["temporal_error"].get<double>())
            : json();
    row["seconds_per_frame"] = median_of(seconds);
    row["rays_traced_per_frame"] = rays;
    row["pixels_shaded_per_frame"] = shaded;
    std::string stage_text;
    add_stage_times_and_counters(frames, row, stage_text);
    add_rings(candidate, row);
    row["command"] = job["command"];
    return "done," + number_text(psnr, "%.9g") + "," + number_text(ssim, "%.9g") + "," +
           (has_flip ? number_text(flip_mean, "%.9g") : std::string()) + "," +
           (row["temporal_error"].is_number()
                ? number_text(row["temporal_error"].get<double>(), "%.9g")
                : std::string()) +
           "," + number_text(median_of(seconds), "%.9g") + "," + number_text(rays, "%.9g") + "," +
           number_text(shaded, "%.9g") + "," + csv_field(stage_text) + "\n";
}

}  // namespace

int run_sweep_merge(const SweepOptions& o) {
    const json plan = read_plan(o.out);
    json rows = json::array();
    std::string csv =
        "id,scene,mode,params,width,height,gaze,frames,every,status,psnr,ssim,flip_mean,"
        "temporal_error,seconds_per_frame,rays_traced_per_frame,pixels_shaded_per_frame,"
        "stage_seconds\n";
    int missing = 0;
    for (const json& job : plan["jobs"]) {
        if (job["kind"] != "evaluate") continue;
        const fs::path dir = fs::path(o.out) / "results" / job["id"].get<std::string>();
        json row = {{"id", job["id"]},         {"scene", job["scene"]},   {"mode", job["mode"]},
                    {"params", job["params"]}, {"width", job["width"]},   {"height", job["height"]},
                    {"gaze", job["gaze"]},     {"frames", job["frames"]}, {"every", job["every"]}};
        const std::string line = job_csv_columns(job);
        if (!job_done(dir, job)) {
            ++missing;
            row["status"] = "missing";
            rows.push_back(row);
            csv += line + "missing,,,,,,,,\n";
            continue;
        }
        csv += line + add_result(dir, job, row);
        rows.push_back(row);
    }
    write_file_atomic((fs::path(o.out) / "results.csv").string(), csv);
    write_file_atomic((fs::path(o.out) / "results.json").string(),
                      json{{"fovref_version", fovref_version()}, {"results", rows}}.dump(1) + "\n");
    std::printf("sweep merge: %zu result(s), %d missing; wrote %s/results.csv and results.json\n",
                rows.size(), missing, o.out.c_str());
    return 0;
}

namespace {

// GNU parallel: the references first, then the jobs (files written, in export/).
std::vector<std::string> export_parallel(const SweepOptions& o, const fs::path& dir,
                                         const std::string& out, int total, int references) {
    const auto job_line = [&](int k) {
        return o.fovref + " sweep job " + out + " " + std::to_string(k) + " -q\n";
    };
    std::string refs, jobs;
    for (int k = 0; k < total; ++k) (k < references ? refs : jobs) += job_line(k);
    write_file_atomic((dir / "references.txt").string(), refs);
    write_file_atomic((dir / "jobs.txt").string(), jobs);
    write_file_atomic(
        (dir / "run-parallel.sh").string(),
        "#!/bin/sh\n# GNU parallel: the references first, then the jobs; --joblog records "
        "every job, --resume-failed reruns only what failed.\nset -e\ncd \"$(dirname "
        "\"$0\")\"\nparallel --joblog references.log --resume-failed < references.txt\n"
        "parallel --joblog jobs.log --resume-failed < jobs.txt\n" +
            o.fovref + " sweep merge " + out + "\n");
    return {"references.txt", "jobs.txt", "run-parallel.sh"};
}

// Slurm: an array job for the references, one for the jobs after them.
std::vector<std::string> export_slurm(const SweepOptions& o, const fs::path& dir,
                                      const std::string& out, int total, int references) {
    const auto script = [&](const std::string& name, int first, int count) {
        return "#!/bin/bash\n#SBATCH --job-name=fovref-" + name + "\n#SBATCH --array=0-" +
               std::to_string(count - 1) + "\n#SBATCH --cpus-per-task=1\n#SBATCH --output=" + out +
               "/export/slurm-" + name + "-%a.log\n# one array task per job of the plan; " + out +
               " must be on a shared file system\n" + o.fovref + " sweep job " + out +
               " $((SLURM_ARRAY_TASK_ID + " + std::to_string(first) + ")) -q\n";
    };
    write_file_atomic((dir / "references.sbatch").string(),
                      script("references", 0, std::max(references, 1)));
    write_file_atomic((dir / "jobs.sbatch").string(),
                      script("jobs", references, std::max(total - references, 1)));
    write_file_atomic((dir / "submit-slurm.sh").string(),
                      "#!/bin/sh\n# the jobs start when every reference task succeeded\n"
                      "set -e\ncd \"$(dirname \"$0\")\"\nref=$(sbatch --parsable "
                      "references.sbatch)\nsbatch --dependency=afterok:$ref jobs.sbatch\n");
    return {"references.sbatch", "jobs.sbatch", "submit-slurm.sh"};
}

// Kubernetes: an Indexed Job for the references, one for the jobs.
std::vector<std::string> export_k8s(const SweepOptions& o, const fs::path& dir,
                                    const std::string& out, int total, int references) {
    const auto manifest = [&](const std::string& name, int first, int count) {
        const std::string n = std::to_string(count);
        return "# Kubernetes Indexed Job: completion index i runs job i + " +
               std::to_string(first) + " of " + out +
               "/plan.json.\n# The sweep directory must be on the volume fovref-sweep "
               "(a ReadWriteMany claim), mounted at the same path.\napiVersion: batch/v1\n"
               "kind: Job\nmetadata:\n  name: fovref-sweep-" +
               name + "\nspec:\n  completionMode: Indexed\n  completions: " + n +
               "\n  parallelism: " + n +
               "\n  backoffLimitPerIndex: 2\n  template:\n    spec:\n      restartPolicy: "
               "Never\n      containers:\n        - name: fovref\n          image: " +
               o.image +
               "\n          resources:\n            requests:\n              cpu: \"1\"\n"
               "          command: [\"sh\", \"-c\", \"" +
               o.fovref + " sweep job " + out + " $((JOB_COMPLETION_INDEX + " +
               std::to_string(first) +
               ")) -q\"]\n          volumeMounts:\n            - name: sweep\n"
               "              mountPath: " +
               out +
               "\n      volumes:\n        - name: sweep\n          persistentVolumeClaim:\n"
               "            claimName: fovref-sweep\n";
    };
    write_file_atomic((dir / "k8s-references.yaml").string(),
                      manifest("references", 0, std::max(references, 1)));
    write_file_atomic((dir / "k8s-jobs.yaml").string(),
                      manifest("jobs", references, std::max(total - references, 1)));
    return {"k8s-references.yaml", "k8s-jobs.yaml"};
}

}  // namespace

int run_sweep_export(const SweepOptions& o) {
    const json plan = read_plan(o.out);
    const int total = static_cast<int>(plan["jobs"].size());
    const int references = plan["references"].get<int>();
    const fs::path dir = fs::path(o.out) / "export";
    fs::create_directories(dir);
    const std::string out = fs::absolute(o.out).string();
    const std::vector<std::string> written =
        o.format == "parallel" ? export_parallel(o, dir, out, total, references)
        : o.format == "slurm"  ? export_slurm(o, dir, out, total, references)
                               : export_k8s(o, dir, out, total, references);
    for (const std::string& w : written) {
        const fs::path p = dir / w;
        if (p.extension() == ".sh")
            fs::permissions(p, fs::perms::owner_exec | fs::perms::group_exec,
                            fs::perm_options::add);
        std::printf("wrote %s\n", p.string().c_str());
    }
    std::printf(
        "%d reference job(s) (indices 0 .. %d) run before the %d others; docs/sweeps.md "
        "has the commands\n",
        references, references - 1, total - references);
    return 0;
}

}  // namespace fovref
