#include "ref/stage/debugger.h"

#include <algorithm>

#include "ref/core/error.h"

namespace fovref {

namespace {

std::string number(int v) { return std::to_string(v); }

// The points, distinct, in first-seen order.
std::vector<glm::ivec2> distinct(const std::vector<glm::ivec2>& points) {
    std::vector<glm::ivec2> out;
    for (const glm::ivec2& p : points)
        if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
    return out;
}

// The bounding rectangle of distinct points, and whether they fill it (pass 2's 2 x 2 taps).
struct Bounds {
    glm::ivec2 lo, hi;
    bool filled;
};
Bounds bounds_of(const std::vector<glm::ivec2>& points) {
    Bounds b{points.front(), points.front(), false};
    for (const glm::ivec2& p : points) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    b.filled =
        static_cast<std::size_t>((b.hi.x - b.lo.x + 1) * (b.hi.y - b.lo.y + 1)) == points.size();
    return b;
}

// "x == 3 && y == 4" for one point; a range test when the points fill their bounding rectangle;
// else one test per point joined by ||.
std::string points_condition(const std::vector<glm::ivec2>& points, const std::string& xn,
                             const std::string& yn) {
    const Bounds b = bounds_of(points);
    const auto axis = [](const std::string& name, int lo, int hi) {
        return lo == hi ? name + " == " + number(lo)
                        : name + " >= " + number(lo) + " && " + name + " <= " + number(hi);
    };
    if (b.filled) return axis(xn, b.lo.x, b.hi.x) + " && " + axis(yn, b.lo.y, b.hi.y);
    std::string out = "(";
    for (std::size_t k = 0; k < points.size(); ++k)
        out += (k ? " || " : "") + std::string("(") + xn + " == " + number(points[k].x) + " && " +
               yn + " == " + number(points[k].y) + ")";
    return out + ")";
}

// "(75..76, 215..216)" for points that fill their bounding rectangle, else "(3, 4) (9, 2)".
std::string points_text(const std::vector<glm::ivec2>& points) {
    const Bounds b = bounds_of(points);
    const auto range = [](int lo, int hi) {
        return lo == hi ? number(lo) : number(lo) + ".." + number(hi);
    };
    if (b.filled) return "(" + range(b.lo.x, b.hi.x) + ", " + range(b.lo.y, b.hi.y) + ")";
    std::string out;
    for (const glm::ivec2& p : points)
        out += (out.empty() ? "" : " ") + std::string("(") + number(p.x) + ", " + number(p.y) + ")";
    return out;
}

std::vector<glm::ivec2> texels_of(const DebugTarget& target, const std::string& family) {
    std::vector<glm::ivec2> out;
    for (const TexelRead& read : target.texels)
        if (read.family == family) out.push_back(read.texel);
    return distinct(out);
}

// The points a function receives for the target, with the condition's extra terms (the eye) and
// the words for what they are; empty points: `skipped` says why.
struct Points {
    std::vector<glm::ivec2> points;
    std::string names[2] = {"x", "y"};
    int eye = -1;
    std::string extra, what, skipped;
};

Points function_points(const PixelFunction& f, const RenderSettings& settings,
                       const DebugTarget& target) {
    Points out;
    const auto texels = [&](const std::string& family) {
        std::vector<glm::ivec2> t = texels_of(target, family);
        if (t.empty())
            out.skipped = target.pixel ? "this pixel reads no " + family + " texel"
                                       : "the probed texel is not a " + family + " texel";
        return t;
    };
    switch (f.args) {
        case PixelArgs::screen:
            if (!target.pixel) {
                out.skipped = "a screen pass: a texel probe stops in the buffer's passes only";
            } else if (f.family.empty() || !texels(f.family).empty()) {
                out.points = {*target.pixel};
                out.what = "the pixel";
            }
            break;
        case PixelArgs::eye_pixel:
            if (!target.pixel) {
                out.skipped = "a screen pass: a texel probe stops in the buffer's passes only";
            } else {
                FOVREF_CHECK(target.eye_width > 0, "a stereo target without its eye width");
                const int eye = target.pixel->x / target.eye_width;
                out.points = {{target.pixel->x - eye * target.eye_width, target.pixel->y}};
                out.eye = eye;
                out.extra = " && fovref::debugger_position.eye == " + number(eye);
                out.what = "the pixel within eye " + number(eye);
            }
            break;
        case PixelArgs::texel:
            out.points = texels(f.family);
            out.what = f.family + " texel" + (out.points.size() > 1 ? "s" : "");
            break;
        case PixelArgs::block: {
            FOVREF_CHECK(static_cast<bool>(f.block_of),
                         f.function + ": a block function without its grid");
            std::vector<glm::ivec2> points;
            if (!f.family.empty())
                points = texels(f.family);
            else if (target.pixel)
                points = {*target.pixel};
            else
                out.skipped = "the probed texel is not in this pass's image";
            for (const glm::ivec2& p : points)
                out.points.push_back(f.block_of(settings, target.frame, p));
            out.points = distinct(out.points);
            out.names[0] = "cell_x";
            out.names[1] = "cell_y";
            out.what = out.points.size() > 1 ? "the blocks" : "the block";
            break;
        }
    }
    if (f.needs_geometry && !out.points.empty()) {
        // The rasterizer's functions run only where a triangle covers the point
        std::vector<glm::ivec2> covered;
        for (const glm::ivec2& p : out.points)
            if (std::find(target.background.begin(), target.background.end(), p) ==
                target.background.end())
                covered.push_back(p);
        if (covered.empty())
            out.skipped = "no triangle covers " + points_text(out.points) +
                          " (background): the rasterizer never reaches it";
        out.points = covered;
    }
    return out;
}

}  // namespace

std::vector<Breakpoint> debugger_breakpoints(const std::vector<PixelFunction>& functions,
                                             const Pipeline& pipeline,
                                             const RenderSettings& settings,
                                             const DebugTarget& target) {
    std::vector<Breakpoint> out;
    for (const PixelFunction& f : functions) {
        Breakpoint b{f, -1, "", {}, "x", "y", -1, "", ""};
        for (std::size_t k = 0; k < pipeline.stages.size(); ++k)
            if (pipeline.stages[k].name == f.stage) b.stage = static_cast<int>(k);
        if (b.stage < 0)
            throw Error("--debugger: " + f.function + " belongs to stage '" + f.stage +
                        "', which this pipeline does not have");
        const Points p = function_points(f, settings, target);
        if (p.points.empty()) {
            b.skipped = p.skipped;
        } else {
            b.condition = points_condition(p.points, p.names[0], p.names[1]) + p.extra +
                          " && fovref::debugger_position.frame == " + number(target.frame) +
                          " && fovref::debugger_position.stage == " + number(b.stage);
            b.points = p.points;
            b.x_name = p.names[0];
            b.y_name = p.names[1];
            b.eye = p.eye;
            b.coordinates = p.names[0] + ", " + p.names[1] + " = " + points_text(p.points) + " (" +
                            p.what + ")";
        }
        out.push_back(std::move(b));
    }
    return out;
}

std::string shell_quote(const std::string& text) {
    const bool plain = !text.empty() && text.find_first_not_of(
                                            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789_-+=/.,:@%") == std::string::npos;
    if (plain) return text;
    std::string out = "'";
    for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string debugger_command(const std::string& debugger, const std::string& program,
                             const std::vector<std::string>& arguments,
                             const std::vector<Breakpoint>& breakpoints) {
    if (std::none_of(breakpoints.begin(), breakpoints.end(),
                     [](const Breakpoint& b) { return !b.condition.empty(); }))
        throw Error("--debugger: no per-pixel function of this mode computes this pixel");
    std::string command;
    if (debugger == "gdb") {
        command = "gdb -q";
        for (const Breakpoint& b : breakpoints)
            if (!b.condition.empty())
                command +=
                    " -ex " + shell_quote("break " + b.function.function + " if " + b.condition);
        command += " -ex run --args " + shell_quote(program);
    } else if (debugger == "lldb") {
        command = "lldb";
        for (const Breakpoint& b : breakpoints)
            if (!b.condition.empty())
                command += " -o " + shell_quote("breakpoint set -n " + b.function.function +
                                                " -c \"" + b.condition + "\"");
        command += " -o run -- " + shell_quote(program);
    } else {
        throw Error("--debugger '" + debugger + "': expected gdb or lldb");
    }
    for (const std::string& a : arguments) command += " " + shell_quote(a);
    return command;
}

}  // namespace fovref
