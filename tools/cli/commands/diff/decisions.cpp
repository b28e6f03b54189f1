// Threshold decisions in `fovref diff` (docs/diff.md, "Threshold decisions"): the oracle's margin
// of each decision, and the failing pixels that a near-threshold flip explains.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ref/metrics/compare.h"
#include "tools/cli/commands/diff/internal.h"

namespace fovref {

namespace {

// Item `name` among items [first, end) (null when absent).
DiffItem* find_item(DiffReport& report, std::size_t first, std::size_t end,
                    const std::string& name) {
    for (std::size_t i = first; i < end; ++i)
        if (report.items[i].name == name) return &report.items[i];
    return nullptr;
}

// The golden image of `item`, loaded now when the candidate lacked the buffer (null when the
// golden keeps only a hash).
const Image* golden_of(const DiffOptions& o, DiffItem& item) {
    if (item.hash_only || item.golden_file.empty()) return nullptr;
    if (item.golden.data.empty())
        item.golden = load_image(o, item.golden_file, item.kind, 0, 0, 0, nullptr);
    return &item.golden;
}

}  // namespace

const Image* decision_margin(const DiffOptions& o, const ItemInputs& inputs, DiffReport& report,
                             std::size_t first, std::size_t end, const DiffItem& item,
                             const Tolerance& tolerance, Image& storage, std::string& why) {
    const std::string derived_from = decision_margin_input(tolerance.margin);
    const std::string source = derived_from.empty() ? tolerance.margin : derived_from;
    DiffItem* found = find_item(report, first, end, source);
    const Image* image = found ? golden_of(o, *found) : nullptr;
    if (!image || image->width != item.golden.width || image->height != item.golden.height) {
        why = "its decision margin (" + tolerance.margin + ") needs the golden's " + source +
              " of the same size, which this frame lacks: compared as ids";
        return nullptr;
    }
    if (derived_from.empty()) return image;
    if (image->channels < 2 || inputs.screen_width <= 0) {
        why = "its decision margin (" + tolerance.margin +
              ") needs screen points and a case: " + "compared as ids";
        return nullptr;
    }
    storage = derived_decision_margin(tolerance.margin, *image, inputs.screen_width,
                                      inputs.screen_height);
    return &storage;
}

namespace {

// The near-threshold flips of one decision buffer, as the attribution sees them.
struct NearFlips {
    int frame = 0;
    std::string name;
    int width = 0, height = 0;
    std::vector<glm::ivec2> pixels;
    std::vector<glm::vec2> screen_points;  ///< the flipped texels' golden screen points (if any)
};

// Every decision buffer's near-threshold flips, with the screen points of buffer-space ones
// (from the frame's golden buffer the margin derives from, when it is a derivation).
std::vector<NearFlips> near_flips(DiffReport& report) {
    std::vector<NearFlips> all;
    for (DiffItem& item : report.items) {
        if (!item.is_id || !item.compared || item.ids.near_pixels.empty()) continue;
        NearFlips f{item.frame,           item.name, item.ids.width, item.ids.height,
                    item.ids.near_pixels, {}};
        const std::string points = decision_margin_input(item.ids.margin_source);
        for (const DiffItem& other : report.items)
            if (!points.empty() && other.frame == item.frame && other.name == points &&
                !other.golden.data.empty() && other.golden.channels >= 2)
                for (const glm::ivec2& p : f.pixels)
                    f.screen_points.emplace_back(other.golden.at(p.x, p.y, 0),
                                                 other.golden.at(p.x, p.y, 1));
        all.push_back(std::move(f));
    }
    return all;
}

// Whether failing pixel (x, y) of `item` is explained by one of `flips`.
bool explained(const DiffItem& item, const ItemInputs& inputs, const NearFlips& flips, int x,
               int y) {
    if (flips.frame > item.frame) return false;
    if (flips.width == item.result.width && flips.height == item.result.height)
        for (const glm::ivec2& p : flips.pixels)
            if (std::abs(p.x - x) <= 1 && std::abs(p.y - y) <= 1) return true;
    if (item.result.width == inputs.screen_width && item.result.height == inputs.screen_height) {
        const glm::vec2 centre(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
        for (const glm::vec2& s : flips.screen_points)
            if (std::fabs(s.x - centre.x) <= 2.0f && std::fabs(s.y - centre.y) <= 2.0f) return true;
    }
    return false;
}

}  // namespace

void attribute_to_decisions(const ItemInputs& inputs, DiffReport& report) {
    const std::vector<NearFlips> flips = near_flips(report);
    if (flips.empty()) return;
    for (DiffItem& item : report.items) {
        BufferComparison& r = item.result;
        if (item.is_id || !item.compared || item.hash_only || r.failing_pixels == 0) continue;
        std::int64_t attributed = 0;
        std::optional<PixelDifference> first;
        for (std::size_t p = 0; p < r.failing_map.size(); ++p) {
            if (!r.failing_map[p]) continue;
            const int x = static_cast<int>(p % static_cast<std::size_t>(r.width));
            const int y = static_cast<int>(p / static_cast<std::size_t>(r.width));
            const NearFlips* by = nullptr;
            for (const NearFlips& f : flips)
                if (!by && explained(item, inputs, f, x, y)) by = &f;
            if (!by) {
                if (!first) {
                    first = PixelDifference{x, y, r.abs_error.at(x, y), {}, {}};
                    for (int c = 0; c < r.channels; ++c) {
                        first->golden.push_back(item.golden.at(x, y, c));
                        first->candidate.push_back(item.candidate.at(x, y, c));
                    }
                }
                continue;
            }
            ++attributed;
            if (std::find(r.attributed_to.begin(), r.attributed_to.end(), by->name) ==
                r.attributed_to.end())
                r.attributed_to.push_back(by->name);
        }
        if (attributed == 0) continue;
        r.attributed_pixels = attributed;
        r.first_failing = first;
        r.pass = r.nonfinite_mismatches == 0 &&
                 r.failing_pixels - attributed <= r.allowed_failing_pixels;
        item.pass = r.pass;
    }
}

}  // namespace fovref
