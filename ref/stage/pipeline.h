// The stage framework. A frame is computed by a list of stages, each a plain function from named
// input buffers to named output buffers (one GPU pass each). Before a frame runs, the pipeline is
// planned backwards from the requested outputs: a stage runs only if something consumes one of
// its outputs, and every stage that does not run is recorded as skipped with the reason. Stages
// may also skip work that the scene does not need (no lights: no shadow rays) and say so.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "ref/scene/scene.h"
#include "ref/stage/frame.h"
#include "ref/stage/params.h"

namespace fovref {

struct RenderSettings {
    int width = 320;
    int height = 180;
    int frame_count = 1;
    /// Index of the first frame rendered (frame numbers seed rand(); the camera-path time of
    /// frame f is time_start + f time_step). Lets a stateless mode render one frame of a sequence.
    int first_frame = 0;
    float time_start = 0.0f;      ///< camera-path time of frame 0
    float time_step = 1.0f / 30;  ///< camera-path time between frames
    Params params;                ///< mode parameters (validated against the mode's list)
    /// Buffers wanted: empty = the mode's final outputs; {"all"} = every buffer of every stage.
    std::vector<std::string> requested;
    /// Called with the fraction done (0..1) after each stage (and by long stages as they go);
    /// may be empty.
    std::function<void(double)> progress;
    /// The buffers of frame first_frame - 1 (a dump), for a mode that carries state from frame to
    /// frame (TAA) and resumes at first_frame > 0; empty: none given.
    std::vector<Buffer> state_buffers;
    /// A test hook, empty in normal use: called after each stage that ran, with the stage's name
    /// and the frame's buffers so far, which it may alter (the stress suite injects NaN and Inf
    /// into a stage's outputs to check that the stages consuming them stay finite).
    std::function<void(const std::string& stage, FrameResult& result)> after_stage;
};

/// A mode's state for one render, shared by its stages: typed parameters parsed once, caches
/// built on first use (the BVH), state carried from frame to frame (TAA history). Each mode
/// derives its own; a stage reads it through FrameContext::mode_state<T>().
struct ModeState {
    virtual ~ModeState() = default;
};

/// What a stage sees: the scene, the settings, this frame's cameras and the frame's buffers.
struct FrameContext {
    const Scene* scene = nullptr;  ///< null for modes that need no scene
    const RenderSettings* settings = nullptr;
    int frame = 0;
    float time = 0.0f;
    Camera camera;
    /// The camera of frame - 1 (the camera path at its time); equal to camera on frame 0.
    Camera previous_camera;
    bool has_previous = false;  ///< frame > 0
    FrameResult* result = nullptr;
    std::string note;  ///< set by a stage to explain what it did or skipped
    /// Set by the pipeline: reports the fraction of the current stage done (0..1).
    std::function<void(double)> stage_progress;
    ModeState* state = nullptr;  ///< the pipeline's state (null for a mode without state)

    /// A buffer an earlier stage of this frame produced. The first read of each buffer in a
    /// frame replaces its NaN and infinite values by 0 and adds their number to the frame's
    /// counter `nonfinite_stage_inputs` (SPEC §0: a stage never propagates NaN/Inf; none occurs
    /// from finite inputs, so the counter appears only when something upstream went wrong).
    const Image& input(const std::string& name) const;
    /// The names input() has checked in this frame (reset by Pipeline::run_frame).
    mutable std::vector<std::string> checked_inputs;
    /// For long stages: report progress through the current stage (e.g. after each row).
    void report(double fraction_of_stage) const {
        if (stage_progress) stage_progress(fraction_of_stage);
    }
    /// The mode's state as its own type; throws when the pipeline carries none of that type.
    template <class T>
    T& mode_state() const {
        T* typed = dynamic_cast<T*>(state);
        FOVREF_CHECK(typed != nullptr, "stage run without its mode's state");
        return *typed;
    }
};

/// A stage's body: a plain named function (so `break fovref::<stage>` works in a debugger and
/// stepping in from Pipeline::run_frame lands in it directly). It reads its inputs through the
/// context, calls the pass, and adds the pass's outputs and counters to the frame.
using StageFunction = void (*)(FrameContext& context);

struct StageDef {
    std::string name;
    std::vector<std::string> inputs;
    std::vector<std::string> outputs;
    StageFunction run = nullptr;
};

struct Pipeline {
    std::vector<StageDef> stages;            ///< in execution order
    std::vector<std::string> final_outputs;  ///< what a plain render writes
    std::shared_ptr<ModeState> state;        ///< handed to every stage; may be null

    /// Every buffer name the stages produce, in pipeline order.
    std::vector<std::string> all_outputs() const;
    /// Throws when an output is produced twice or an input is not produced by an earlier stage.
    void validate(const std::string& mode) const;
    /// Names of the stages needed for `requested` (empty = final outputs, {"all"} = all).
    /// Throws fovref::Error naming an unknown buffer.
    std::vector<bool> plan(const std::vector<std::string>& requested) const;
    /// Runs the planned stages for one frame.
    FrameResult run_frame(FrameContext& context, const std::vector<std::string>& requested) const;
};

struct ProbeContext;  // ref/stage/probe.h
struct ProbeReport;

/// A pass's per-pixel function, for `fovref probe --debugger`: a debugger can stop in it at one
/// pixel because it takes the pixel as parameters named `x` and `y`.
struct PixelFunction {
    std::string stage;     ///< the stage whose pass calls it
    std::string function;  ///< qualified name, e.g. "fovref::shade_basic_pixel"
    std::string note;      ///< e.g. "once per triangle covering the pixel"
};

struct ModeInfo {
    std::string name;
    std::string description;
    bool needs_scene = true;
    std::vector<ParamSpec> params;
    /// Builds the pipeline for a scene (null when !needs_scene) and validated settings; its
    /// state (Pipeline::state) may carry data from frame to frame (TAA history, ...).
    Pipeline (*build)(const Scene* scene, const RenderSettings& settings) = nullptr;
    /// Explains one pixel of a rendered frame for `fovref probe` (ref/stage/probe.h); may be
    /// null (the probe then lists the buffers' values only).
    void (*explain)(const ProbeContext& context, ProbeReport& report) = nullptr;
    /// True when `explain` can also explain a texel of the mode's buffer (`probe --texel`).
    bool explains_texels = false;
    /// The per-pixel functions of the passes the parameters select, in pipeline order; may be
    /// null (no breakpoints to offer).
    std::vector<PixelFunction> (*pixel_functions)(const Params& params) = nullptr;
    /// True when a frame depends on no earlier frame, so frame f can be rendered alone
    /// (RenderSettings::first_frame) with the same bits.
    bool stateless = true;
    /// When set: whether these parameters make frame f depend on frame f - 1 (then it renders
    /// alone only with --resume), for a mode whose default carries state (visual-polar's BMFR,
    /// acuity's progressive mean); null: TAA or BMFR turned on by a parameter decides.
    bool (*parameters_carry_state)(const Params& params) = nullptr;
    /// True when `--resume DIR` continues the same frame from DIR's buffers of that frame (the
    /// accumulated reference) instead of carrying frame F - 1's state into frame F.
    bool resume_same_frame = false;
};

/// Renders frames 0..frame_count-1 of `mode`, handing each frame to `on_frame` as soon as it is
/// done (so long runs need not keep every frame in memory). Validates the settings, parameters
/// and requested buffers before any work. Returns the mode's final outputs.
std::vector<std::string> render_each(const Scene* scene, const ModeInfo& mode,
                                     const RenderSettings& settings,
                                     const std::function<void(FrameResult&)>& on_frame);

/// render_each, keeping every frame.
std::vector<FrameResult> render(const Scene* scene, const ModeInfo& mode,
                                const RenderSettings& settings);

/// Checks width/height/frame counts and times; throws fovref::Error naming the setting.
void validate_settings(const RenderSettings& settings);

}  // namespace fovref
