// The stage framework. A frame is computed by a list of stages, each a plain function from named
// input buffers to named output buffers (one GPU pass each). Before a frame runs, the pipeline is
// planned backwards from the requested outputs: a stage runs only if something consumes one of
// its outputs, and every stage that does not run is recorded as skipped with the reason. Stages
// may also skip work that the scene does not need (no lights: no shadow rays) and say so.
#pragma once

#include <functional>
#include <memory>
#include <optional>
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

/// A stage's own state: its configuration (parameters parsed once when the mode is built, the
/// per-frame values it needs from its mode, such as the frame's gaze) and what it carries from
/// frame to frame (TAA's history). Each stage declares its own struct derived from this and
/// reads it as FrameContext::state<T>(); the stages of one pass family may share one object
/// (BMFR's eight phases share its history), and stages share caches by holding the same object
/// (the BVH, pass 2's forward table). A mode composes these; it has no state of its own.
struct StageState {
    virtual ~StageState() = default;
};

/// One buffer a stage reads or writes, as the stage declares it (Falcor's reflect()): `slot` is
/// the stage's own name for it, the one its function asks for (`context.input("color")`), and
/// `buffer` the frame's buffer the mode wires it to ("resolved", "lp_color", ...). A plain name
/// is both.
struct Port {
    std::string slot;
    std::string buffer;
    Port(const char* name) : slot(name), buffer(name) {}  // NOLINT: a plain name is a port
    Port(std::string name) : slot(name), buffer(std::move(name)) {}  // NOLINT
    Port(std::string slot_name, std::string buffer_name)
        : slot(std::move(slot_name)), buffer(std::move(buffer_name)) {}
};

struct StageDef;

/// What a stage sees: the scene, the settings, this frame's cameras, its own declaration and
/// state, and the frame's buffers, which it reads and writes through its declared ports.
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
    const StageDef* stage = nullptr;  ///< the stage running (set by Pipeline::run_frame)

    /// The buffer wired to input `slot` of the running stage, produced by an earlier stage of
    /// this frame. The first read of each buffer in a frame replaces its NaN and infinite values
    /// by 0 and adds their number to the frame's counter `nonfinite_stage_inputs` (SPEC §0: a
    /// stage never propagates NaN/Inf; none occurs from finite inputs, so the counter appears
    /// only when something upstream went wrong). Throws when the stage declared no such slot.
    const Image& input(const std::string& slot) const;
    /// True when the running stage declares input `slot` (an input the wiring may leave out,
    /// e.g. the gaze buffer of a mode without one).
    bool has_input(const std::string& slot) const;
    /// Adds `image` as the buffer wired to output `slot` of the running stage.
    Buffer& output(const std::string& slot, BufferKind kind, std::vector<std::string> channel_names,
                   Image image) const;
    /// The frame buffer wired to input or output `slot` of the running stage (for messages and
    /// for the previous frame's buffers of a resumed render).
    const std::string& buffer_of(const std::string& slot) const;
    /// The names input() has checked in this frame (reset by Pipeline::run_frame).
    mutable std::vector<std::string> checked_inputs;
    /// The buffers this frame's plan needs (requested, or read by a stage that runs); set by
    /// Pipeline::run_frame; outside it `all_wanted` is true and nothing is skipped.
    std::vector<std::string> wanted;
    bool all_wanted = true;  ///< every buffer is wanted (`--dump all`, or outside run_frame)
    /// True when the buffer wired to output `slot` of the running stage is wanted. A stage may
    /// leave out an output nobody wants when it costs work of its own (pass 2's decision
    /// buffers); the buffers a stage must always produce are the wanted ones.
    bool wants(const std::string& slot) const;
    /// True when frame buffer `name` is wanted (wants() of the port wired to it).
    bool wants_buffer(const std::string& name) const;
    /// For long stages: report progress through the current stage (e.g. after each row).
    void report(double fraction_of_stage) const {
        if (stage_progress) stage_progress(fraction_of_stage);
    }
    /// The running stage's state as its own type; throws when it has none of that type.
    template <class T>
    T& state() const;
    /// Storage for output `slot` of the running stage, width x height x channels, for a pass
    /// that writes every value of it: the storage of the same buffer of an earlier frame when
    /// hand_back kept one of that shape (its values are that frame's, which the pass must not
    /// read), else a new image of zeros. It saves the zero fill of a new image each frame (22 MB
    /// for clamp-buffer's taa_bounds). Asking marks the buffer for hand_back.
    Image recycled(const std::string& slot, int width, int height, int channels);
    /// Output `slot` of the running stage as the previous frame left it, values and all, for a
    /// stage whose next frame reads what it wrote (TAA's output is its history): the frame's
    /// buffer itself, not a copy, as hand_back kept it, moved into `history`; when there is none
    /// (the first frame, or a caller that took the buffer away) `history` is left as it is
    /// (empty, or a resumed render's copy). Throws fovref::Error naming `what` ("TAA") and the
    /// buffer when `expected` (the stage has a history) and `history` is still empty. Asking
    /// marks the buffer for hand_back. A frame's callback may read such a buffer and may copy
    /// it, but must neither alter it nor move it out of the frame (render() keeps copies of its
    /// frames). Where a later stage's input() replaces non-finite values of such a buffer, the
    /// buffer as it was before is what comes back (`unsanitized`): the stage gets what it wrote.
    void carried(const std::string& slot, Image& history, bool expected, const std::string& what);
    /// Keeps, for the next frame's recycled() and carried(), the buffers of `done` that they
    /// have asked for and its caller left in it (the rest goes with the frame). render_each
    /// calls it once the frame's callback has returned, when nothing can read the frame's
    /// buffers any more.
    void hand_back(FrameResult& done);
    /// What hand_back kept of output `slot`'s buffer (taken out of `spare`), or an empty image;
    /// the buffer is marked for hand_back.
    Image take_spare(const std::string& slot);
    std::vector<std::string> recyclable;       ///< the buffers recycled() and carried() asked for
    std::vector<std::string> carried_buffers;  ///< the buffers carried() asked for
    /// Copies of carried buffers taken by input() before it replaced their non-finite values
    /// (the frame's; handed back instead of the replaced buffers).
    mutable std::vector<Buffer> unsanitized;
    std::vector<Buffer> spare;  ///< what hand_back kept
    /// Buffer `name` of frame F - 1 for a stage that carries state (`what`: "TAA", "BMFR") into
    /// the first frame F > 0 rendered, from RenderSettings::state_buffers (`fovref render
    /// --resume DIR`). Throws fovref::Error naming --resume when it is missing or not
    /// W x H x channels (`size`: a buffer's size other than the screen's, e.g. a Visual-Polar
    /// buffer).
    const Image& resumed(const std::string& name, int channels, const std::string& what,
                         std::optional<glm::ivec2> size = std::nullopt) const;
};

/// A stage's body: a plain named function (so `break fovref::<stage>` works in a debugger and
/// stepping in from Pipeline::run_frame lands in it directly). It reads its inputs through the
/// context, calls the pass, and adds the pass's outputs and counters to the frame.
using StageFunction = void (*)(FrameContext& context);

/// One stage: its name, the buffers it reads and writes (its ports, wired by the mode), its
/// function and its state.
struct StageDef {
    std::string name;
    std::vector<Port> inputs;
    std::vector<Port> outputs;
    StageFunction run = nullptr;
    std::shared_ptr<StageState> state;  ///< may be null (a stage without configuration)

    StageDef(std::string stage_name, std::vector<Port> input_ports, std::vector<Port> output_ports,
             StageFunction function, std::shared_ptr<StageState> stage_state = nullptr)
        : name(std::move(stage_name)),
          inputs(std::move(input_ports)),
          outputs(std::move(output_ports)),
          run(function),
          state(std::move(stage_state)) {}
};

template <class T>
T& FrameContext::state() const {
    T* typed = stage ? dynamic_cast<T*>(stage->state.get()) : nullptr;
    FOVREF_CHECK(typed != nullptr,
                 "stage '" + (stage ? stage->name : std::string("?")) + "' run without its state");
    return *typed;
}

struct Pipeline {
    std::vector<StageDef> stages;            ///< in execution order
    std::vector<std::string> final_outputs;  ///< what a plain render writes

    /// Appends a stage (the wiring reads as a list of stages).
    Pipeline& add(StageDef stage) {
        stages.push_back(std::move(stage));
        return *this;
    }
    /// Every buffer name the stages produce, in pipeline order.
    std::vector<std::string> all_outputs() const;
    /// Throws when an output is produced twice or an input is not produced by an earlier stage.
    void validate(const std::string& mode) const;
    /// Names of the stages needed for `requested` (empty = final outputs, {"all"} = all).
    /// Throws fovref::Error naming an unknown buffer.
    std::vector<bool> plan(const std::vector<std::string>& requested) const;
    /// The buffers needed for `requested`: those requested and every input of a needed stage
    /// (in planning order, with repeats); {"all"} when everything is.
    std::vector<std::string> wanted_buffers(const std::vector<std::string>& requested) const;
    /// Runs the planned stages for one frame.
    FrameResult run_frame(FrameContext& context, const std::vector<std::string>& requested) const;
};

struct ProbeContext;  // ref/stage/probe.h
struct ProbeReport;

/// What a pass's per-pixel function receives as its coordinates, for `fovref probe --debugger`.
enum class PixelArgs {
    screen,     ///< x, y: the screen pixel
    texel,      ///< x, y: a texel of PixelFunction::family that the pixel reads (pass 2's taps)
    eye_pixel,  ///< x, y: the pixel within its eye's half of a side-by-side stereo screen
    block,      ///< cell_x, cell_y: the BMFR block (grid cell) holding the pixel or texel
};

/// A pass's per-pixel function, for `fovref probe --debugger`: a debugger can stop in it at one
/// pixel because it takes the pixel (or the texel, or block) as parameters named `x` and `y`
/// (`cell_x`, `cell_y` for a block).
struct PixelFunction {
    std::string stage;     ///< the stage whose pass calls it
    std::string function;  ///< qualified name, e.g. "fovref::shade_basic_pixel"
    std::string note;      ///< e.g. "once per triangle covering the pixel"
    PixelArgs args = PixelArgs::screen;
    /// texel: the buffer family of its texels ("lp_", "gaze_", "vp_"). screen: when set, the
    /// function matters only for a pixel that reads texels of this family (the composite's gaze
    /// pass traces screen pixels that only the gaze buffer holds).
    std::string family;
    /// block: the grid cell that covers a point of the frame (a screen pixel, or a texel of
    /// `family`).
    using BlockOf =
        std::function<glm::ivec2(const RenderSettings& settings, int frame, glm::ivec2 point)>;
    BlockOf block_of;
    /// Reached only where a triangle covers the point (the rasterizer's functions): a point
    /// whose G-buffer primitive is -1 (DebugTarget::background) gets no breakpoint.
    bool needs_geometry = false;

    PixelFunction(std::string stage_name, std::string function_name, std::string note_text,
                  PixelArgs arguments = PixelArgs::screen, std::string texel_family = "",
                  BlockOf block = {})
        : stage(std::move(stage_name)),
          function(std::move(function_name)),
          note(std::move(note_text)),
          args(arguments),
          family(std::move(texel_family)),
          block_of(std::move(block)) {}
};

/// Where the pipeline is: written by Pipeline::run_frame before each stage (and by a stage that
/// runs its pass once per eye), read by nothing in fovref - only by the conditions of the
/// breakpoints `fovref probe --debugger` prints, because a per-pixel function receives its
/// pixel but not its frame or stage. The one global of the library, kept for the debugger.
struct DebuggerPosition {
    int frame = -1;  ///< the frame being rendered
    int stage = -1;  ///< the index of the running stage in Pipeline::stages
    int eye = -1;    ///< a stereo stage's eye (0 left, 1 right) while it runs that eye's pass
};
extern DebuggerPosition debugger_position;

/// How the pixels of a buffer relate to the screen (a mode describes its buffers that are not
/// screen images): what `fovref diff` offers as the probe of a differing pixel and how reports
/// summarise a buffer.
enum class BufferSpace {
    screen,         ///< W x H: pixel (x, y) is screen pixel (x, y) (`probe --pixel X,Y`)
    texel,          ///< a foveation buffer: pixel (x, y) is texel (x, y) (`probe --texel X,Y`)
    stereo_texel,   ///< both eyes' buffers side by side, `buffer_width` columns each: pixel (x, y)
                    ///< is texel (x - e w, y) of eye e (`probe --texel I,J,EYE`)
    screen_window,  ///< a window of the screen whose pixel (0, 0) is screen pixel
                    ///< (gaze_window_x0, gaze_window_y0) (the frame's counters)
    samples,        ///< a list of samples (N x 1), not an image of the screen
};

/// The buffers whose names start with `prefix` are in `space`.
struct BufferFamily {
    std::string prefix;
    BufferSpace space = BufferSpace::screen;
};

/// A texel pass 2 reads for a screen pixel: its buffer family (the prefix of a BufferFamily, e.g.
/// "lp_") and the texel.
struct TexelRead {
    std::string family;
    glm::ivec2 texel{0};
    bool operator==(const TexelRead&) const = default;
};

struct ModeInfo {
    std::string name;
    std::string description;
    bool needs_scene = true;
    std::vector<ParamSpec> params;
    /// Builds the pipeline for a scene (null when !needs_scene) and validated settings; its
    /// stages' states may carry data from frame to frame (TAA history, ...).
    std::function<Pipeline(const Scene* scene, const RenderSettings& settings)> build;
    /// Explains one pixel of a rendered frame for `fovref probe` (ref/stage/probe.h); may be
    /// null (the probe then lists the buffers' values only).
    void (*explain)(const ProbeContext& context, ProbeReport& report) = nullptr;
    /// True when `explain` can also explain a texel of the mode's buffer (`probe --texel`).
    bool explains_texels = false;
    /// The per-pixel functions of the passes the parameters select, in pipeline order; may be
    /// null (no breakpoints to offer).
    std::function<std::vector<PixelFunction>(const Params& params)> pixel_functions;
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
    /// The mode's buffers that are not screen images (every other buffer is W x H screen space),
    /// e.g. {"lp_", texel}, {"gaze_", screen_window}.
    std::vector<BufferFamily> buffer_families;
    /// How screen pixel (x, y) of frame `frame` maps to the buffer texels pass 2 reads for it
    /// (traced or not; a mip resolve's level 0); empty for a mode whose screen pixels read only
    /// screen images.
    std::function<std::vector<TexelRead>(const Scene& scene, const RenderSettings& settings,
                                         int frame, int x, int y)>
        pixel_texels;
};

/// The space of buffer `name` of `mode` (the first family whose prefix it starts with; screen
/// when none).
BufferSpace buffer_space(const ModeInfo& mode, const std::string& name);

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
