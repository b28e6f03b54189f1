#include "ref/stage/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <immintrin.h>

#include "ref/core/error.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

/// any_nonfinite with AVX2, 32 values a step in four independent chains: a 52 MB G-buffer in
/// 4.3 ms instead of SSE2's 5.8 (the Intel machine of docs/speed.md), each buffer just written
/// by its stage. Returns how far it went; the caller does the rest.
__attribute__((target("avx2"))) std::size_t nonfinite_avx2(const float* values, std::size_t n,
                                                           bool& any) {
    const __m256i exponent = _mm256_set1_epi32(0x7f800000);
    __m256i found[4] = {_mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256(),
                        _mm256_setzero_si256()};
    std::size_t i = 0;
    for (; i + 32 <= n; i += 32)
        for (int k = 0; k < 4; ++k) {
            const __m256i v =
                _mm256_loadu_si256(reinterpret_cast<const __m256i*>(values + i + 8 * k));
            found[k] = _mm256_or_si256(found[k],
                                       _mm256_cmpeq_epi32(_mm256_and_si256(v, exponent), exponent));
        }
    const __m256i all =
        _mm256_or_si256(_mm256_or_si256(found[0], found[1]), _mm256_or_si256(found[2], found[3]));
    any = !_mm256_testz_si256(all, all);
    return i;
}

/// Whether any value is NaN or infinite (all exponent bits set): a memory-speed scan (AVX2 where
/// the CPU has it, else four values per SSE2 instruction), since every stage input is checked
/// once per frame.
bool any_nonfinite(const float* values, std::size_t n) {
    std::size_t i = 0;
    if (cpu_has_avx2()) {
        bool any = false;
        i = nonfinite_avx2(values, n, any);
        if (any) return true;
    }
    const __m128i exponent = _mm_set1_epi32(0x7f800000);
    __m128i found = _mm_setzero_si128();
    for (; i + 4 <= n; i += 4) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(values + i));
        found = _mm_or_si128(found, _mm_cmpeq_epi32(_mm_and_si128(v, exponent), exponent));
    }
    bool any = _mm_movemask_epi8(found) != 0;
    for (; i < n; ++i) any = any || !std::isfinite(values[i]);
    return any;
}

}  // namespace

namespace {

// The port of `stage` named `slot`, or null.
const Port* find_port(const std::vector<Port>& ports, const std::string& slot) {
    for (const Port& port : ports)
        if (port.slot == slot) return &port;
    return nullptr;
}

// The frame's buffer wired to input `slot` of the running stage.
const std::string& input_buffer(const FrameContext& ctx, const std::string& slot) {
    FOVREF_CHECK(ctx.stage != nullptr, "stage input '" + slot + "' read outside a stage");
    const Port* port = find_port(ctx.stage->inputs, slot);
    FOVREF_CHECK(port != nullptr,
                 "stage '" + ctx.stage->name + "' reads '" + slot + "', which it does not declare");
    return port->buffer;
}

}  // namespace

const Image& FrameContext::input(const std::string& slot) const {
    const std::string& name = input_buffer(*this, slot);
    Buffer* buffer = nullptr;
    for (Buffer& b : result->buffers)
        if (b.name == name) {
            buffer = &b;
            break;
        }
    FOVREF_CHECK(buffer != nullptr, "stage input '" + name + "' was not produced");
    if (std::find(checked_inputs.begin(), checked_inputs.end(), name) == checked_inputs.end()) {
        checked_inputs.push_back(name);
        std::vector<float>& data = buffer->image.data;
        if (any_nonfinite(data.data(), data.size())) {
            // A carried buffer comes back to its stage as the stage wrote it
            if (std::find(carried_buffers.begin(), carried_buffers.end(), name) !=
                carried_buffers.end())
                unsanitized.push_back(*buffer);
            std::int64_t replaced = 0;
            for (float& v : data)
                if (!std::isfinite(v)) {
                    v = 0.0f;
                    ++replaced;
                }
            result->counters.add("nonfinite_stage_inputs", replaced);
        }
    }
    return buffer->image;
}

bool FrameContext::has_input(const std::string& slot) const {
    return stage != nullptr && find_port(stage->inputs, slot) != nullptr;
}

Buffer& FrameContext::output(const std::string& slot, BufferKind kind,
                             std::vector<std::string> channel_names, Image image) const {
    FOVREF_CHECK(stage != nullptr, "stage output '" + slot + "' written outside a stage");
    const Port* port = find_port(stage->outputs, slot);
    FOVREF_CHECK(port != nullptr,
                 "stage '" + stage->name + "' writes '" + slot + "', which it does not declare");
    return result->add(port->buffer, kind, std::move(channel_names), std::move(image));
}

bool FrameContext::wants(const std::string& slot) const { return wants_buffer(buffer_of(slot)); }

bool FrameContext::wants_buffer(const std::string& name) const {
    return all_wanted || std::find(wanted.begin(), wanted.end(), name) != wanted.end();
}

const std::string& FrameContext::buffer_of(const std::string& slot) const {
    FOVREF_CHECK(stage != nullptr, "port '" + slot + "' asked for outside a stage");
    if (const Port* port = find_port(stage->outputs, slot)) return port->buffer;
    return input_buffer(*this, slot);
}

Image FrameContext::take_spare(const std::string& slot) {
    FOVREF_CHECK(stage != nullptr && find_port(stage->outputs, slot) != nullptr,
                 "storage asked for '" + slot + "', which the running stage does not write");
    const std::string& name = buffer_of(slot);
    if (std::find(recyclable.begin(), recyclable.end(), name) == recyclable.end())
        recyclable.push_back(name);
    Image image;
    for (Buffer& b : spare)
        if (b.name == name) image = std::move(b.image);
    return image;
}

void FrameContext::carried(const std::string& slot, Image& history, bool expected,
                           const std::string& what) {
    if (Image image = take_spare(slot); !image.empty()) history = std::move(image);
    const std::string& name = buffer_of(slot);
    if (std::find(carried_buffers.begin(), carried_buffers.end(), name) == carried_buffers.end())
        carried_buffers.push_back(name);
    FOVREF_CHECK(!expected || !history.empty(),
                 what + "'s history, the previous frame's buffer '" + name +
                     "', was not handed back: a frame's callback moved it away");
}

Image FrameContext::recycled(const std::string& slot, int width, int height, int channels) {
    Image image = take_spare(slot);
    keep_or_make(image, width, height, channels);
    return image;
}

void FrameContext::hand_back(FrameResult& done) {
    spare.clear();
    for (Buffer& b : done.buffers) {
        if (b.image.empty() ||
            std::find(recyclable.begin(), recyclable.end(), b.name) == recyclable.end())
            continue;
        // a carried buffer whose non-finite values a stage's read replaced: as it was written
        const auto original = std::find_if(unsanitized.begin(), unsanitized.end(),
                                           [&](const Buffer& u) { return u.name == b.name; });
        spare.push_back(original != unsanitized.end() ? std::move(*original) : std::move(b));
    }
    unsanitized.clear();
}

const Image& FrameContext::resumed(const std::string& name, int channels, const std::string& what,
                                   std::optional<glm::ivec2> size) const {
    const int width = size ? size->x : settings->width;
    const int height = size ? size->y : settings->height;
    for (const Buffer& b : settings->state_buffers) {
        if (b.name != name) continue;
        const Image& image = b.image;
        if (image.width != width || image.height != height || image.channels != channels)
            throw Error("--resume: buffer '" + name + "' is " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + "x" + std::to_string(image.channels) +
                        ", the frame needs " + std::to_string(width) + "x" +
                        std::to_string(height) + "x" + std::to_string(channels));
        return image;
    }
    throw Error("frame " + std::to_string(frame) + ": " + what + " carries state from frame " +
                std::to_string(frame - 1) + ", and buffer '" + name +
                "' of that frame was not given: render from frame 0, or resume from a --dump of "
                "frame " +
                std::to_string(frame - 1) + " (`fovref render --resume DIR`)");
}

std::vector<std::string> Pipeline::all_outputs() const {
    std::vector<std::string> names;
    for (const StageDef& stage : stages)
        for (const Port& output : stage.outputs) names.push_back(output.buffer);
    return names;
}

void Pipeline::validate(const std::string& mode) const {
    std::vector<std::string> produced;
    for (const StageDef& stage : stages) {
        for (const Port& input : stage.inputs)
            FOVREF_CHECK(
                std::find(produced.begin(), produced.end(), input.buffer) != produced.end(),
                "mode '" + mode + "': stage '" + stage.name + "' reads '" + input.buffer +
                    "' before any stage produces it");
        for (const Port& output : stage.outputs) {
            FOVREF_CHECK(
                std::find(produced.begin(), produced.end(), output.buffer) == produced.end(),
                "mode '" + mode + "': buffer '" + output.buffer + "' is produced twice");
            produced.push_back(output.buffer);
        }
    }
    for (const std::string& output : final_outputs)
        FOVREF_CHECK(std::find(produced.begin(), produced.end(), output) != produced.end(),
                     "mode '" + mode + "': final output '" + output + "' is never produced");
}

namespace {

/// The planning walk: needed[k] for each stage, and the buffers wanted (requested and read).
std::vector<bool> plan_walk(const Pipeline& pipeline, const std::vector<std::string>& requested,
                            std::vector<std::string>& wanted) {
    wanted = requested.empty() ? pipeline.final_outputs : requested;
    const bool everything = std::find(wanted.begin(), wanted.end(), "all") != wanted.end();
    const std::vector<std::string> known = pipeline.all_outputs();
    for (const std::string& name : wanted)
        if (name != "all" && std::find(known.begin(), known.end(), name) == known.end()) {
            std::string list;
            for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
            throw Error("buffer '" + name + "' is not produced by this mode (it produces: " + list +
                        ")");
        }
    // Walk backwards: a stage is needed when one of its outputs is wanted; its inputs then are.
    const std::vector<StageDef>& stages = pipeline.stages;
    std::vector<bool> needed(stages.size(), everything);
    if (everything) {
        wanted = {"all"};
        return needed;
    }
    for (std::size_t k = stages.size(); k-- > 0;) {
        const StageDef& stage = stages[k];
        for (const Port& output : stage.outputs)
            if (std::find(wanted.begin(), wanted.end(), output.buffer) != wanted.end())
                needed[k] = true;
        if (needed[k])
            for (const Port& input : stage.inputs) wanted.push_back(input.buffer);
    }
    return needed;
}

}  // namespace

std::vector<bool> Pipeline::plan(const std::vector<std::string>& requested) const {
    std::vector<std::string> wanted;
    return plan_walk(*this, requested, wanted);
}

std::vector<std::string> Pipeline::wanted_buffers(const std::vector<std::string>& requested) const {
    std::vector<std::string> wanted;
    plan_walk(*this, requested, wanted);
    return wanted;
}

DebuggerPosition debugger_position;

FrameResult Pipeline::run_frame(FrameContext& context,
                                const std::vector<std::string>& requested) const {
    FrameResult result;
    result.frame = context.frame;
    result.time = context.time;
    context.result = &result;
    context.checked_inputs.clear();
    context.unsanitized.clear();  // (a frame not handed back)
    std::vector<std::string> wanted;
    const std::vector<bool> needed = plan_walk(*this, requested, wanted);
    context.all_wanted = wanted.size() == 1 && wanted[0] == "all";
    context.wanted = std::move(wanted);
    const auto stage_count = static_cast<double>(stages.size());
    const std::function<void(double)> frame_progress = context.stage_progress;
    for (std::size_t k = 0; k < stages.size(); ++k) {
        StageRun run{stages[k].name, needed[k], "", 0.0};
        if (!needed[k]) {
            run.note = "skipped: no requested output consumes it";
        } else {
            context.note.clear();
            if (frame_progress)
                context.stage_progress = [&frame_progress, k, stage_count](double f) {
                    frame_progress((static_cast<double>(k) + f) / stage_count);
                };
            const auto start = std::chrono::steady_clock::now();
            context.stage = &stages[k];
            debugger_position = {context.frame, static_cast<int>(k), -1};
            stages[k].run(context);
            context.stage = nullptr;
            run.seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            run.note = context.note;
            for (const Port& output : stages[k].outputs)
                FOVREF_CHECK(
                    result.find(output.buffer) != nullptr || !context.wants_buffer(output.buffer),
                    "stage '" + stages[k].name + "' did not produce '" + output.buffer + "'");
            for (Buffer& buffer : result.buffers)
                if (buffer.stage.empty()) buffer.stage = stages[k].name;
            if (context.settings && context.settings->after_stage)
                context.settings->after_stage(stages[k].name, result);
        }
        result.stages.push_back(run);
        if (frame_progress) frame_progress(static_cast<double>(k + 1) / stage_count);
    }
    context.stage_progress = frame_progress;
    context.result = nullptr;
    context.wanted.clear();
    context.all_wanted = true;  // outside run_frame, nothing is skipped
    return result;
}

void validate_settings(const RenderSettings& settings) {
    constexpr int max_side = 16384;
    if (settings.width < 1 || settings.width > max_side)
        throw Error("--width " + std::to_string(settings.width) + ": must be in [1, 16384]");
    if (settings.height < 1 || settings.height > max_side)
        throw Error("--height " + std::to_string(settings.height) + ": must be in [1, 16384]");
    if (settings.first_frame < 0 || settings.first_frame > 100000)
        throw Error("first frame " + std::to_string(settings.first_frame) +
                    ": must be in [0, 100000]");
    if (settings.frame_count < 1 || settings.frame_count > 100000)
        throw Error("--frames " + std::to_string(settings.frame_count) +
                    ": must be in [1, 100000]");
    if (!std::isfinite(settings.time_start) || !std::isfinite(settings.time_step) ||
        settings.time_step < 0.0f)
        throw Error("--time-start/--time-step must be finite and the step non-negative");
}

std::vector<std::string> render_each(const Scene* scene, const ModeInfo& mode,
                                     const RenderSettings& settings,
                                     const std::function<void(FrameResult&)>& on_frame) {
    validate_settings(settings);
    settings.params.check_known(mode.params, mode.name);
    if (mode.needs_scene && scene == nullptr) throw Error("mode '" + mode.name + "' needs a scene");
    const Pipeline pipeline = mode.build(scene, settings);
    pipeline.validate(mode.name);
    pipeline.plan(settings.requested);  // reject unknown buffer names before any work

    FrameContext context;
    context.scene = scene;
    context.settings = &settings;
    const auto frames = static_cast<double>(settings.frame_count);
    for (int k = 0; k < settings.frame_count; ++k) {
        const int f = settings.first_frame + k;
        context.frame = f;
        context.time = settings.time_start + static_cast<float>(f) * settings.time_step;
        const Camera camera = scene ? camera_at(*scene, context.time) : Camera{};
        // Frame f's previous camera is frame f - 1's, also when f is the first frame rendered, so
        // that frame f alone has the same motion vectors as in the sequence.
        context.previous_camera =
            k > 0            ? context.camera
            : f > 0 && scene ? camera_at(*scene, settings.time_start +
                                                     static_cast<float>(f - 1) * settings.time_step)
                             : camera;
        context.has_previous = f > 0;
        context.camera = camera;
        if (settings.progress)
            context.stage_progress = [&settings, k, frames](double within) {
                settings.progress((static_cast<double>(k) + within) / frames);
            };
        FrameResult result = pipeline.run_frame(context, settings.requested);
        if (scene) {
            result.display_distance_px = display_distance_px(scene->display, settings.width,
                                                             settings.height, camera.vfov_deg);
            result.camera = camera;
        }
        on_frame(result);
        context.hand_back(result);
    }
    return pipeline.final_outputs;
}

std::vector<FrameResult> render(const Scene* scene, const ModeInfo& mode,
                                const RenderSettings& settings) {
    std::vector<FrameResult> frames;
    // Copies: a stage may read its own buffers of a frame in the next one (carried()).
    render_each(scene, mode, settings, [&frames](FrameResult& f) { frames.push_back(f); });
    return frames;
}

BufferSpace buffer_space(const ModeInfo& mode, const std::string& name) {
    for (const BufferFamily& family : mode.buffer_families)
        if (name.rfind(family.prefix, 0) == 0) return family.space;
    return BufferSpace::screen;
}

}  // namespace fovref
