#include "ref/gaze/gaze_track.h"

#include <charconv>
#include <cmath>

#include "ref/core/error.h"
#include "ref/image/image_io.h"

namespace fovref {

namespace {

std::string trim(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return "";
    return s.substr(first, s.find_last_not_of(" \t\r") + 1 - first);
}

template <class T>
bool parse_number(const std::string& text, T& value) {
    const std::string t = trim(text);
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
    return !t.empty() && ec == std::errc() && end == t.data() + t.size();
}

}  // namespace

std::vector<GazeSample> parse_gaze_track(const std::string& text, const std::string& name) {
    std::vector<GazeSample> track;
    std::size_t start = 0;
    for (int line_number = 1; start <= text.size(); ++line_number) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        const std::string line = trim(text.substr(start, end - start));
        start = end + 1;
        if (line.empty() || line[0] == '#') continue;
        if (track.empty() && line_number == 1 && line == "frame,x,y") continue;
        const auto c1 = line.find(','), c2 = line.find(',', c1 == std::string::npos ? c1 : c1 + 1);
        if (c1 == std::string::npos || c2 == std::string::npos ||
            line.find(',', c2 + 1) != std::string::npos)
            throw file_error(name, line_number, "expected 'frame,x,y', got '" + line + "'");
        GazeSample s;
        if (!parse_number(line.substr(0, c1), s.frame) || s.frame < 0)
            throw file_error(name, line_number,
                             "frame '" + trim(line.substr(0, c1)) + "' is not an integer >= 0");
        if (!parse_number(line.substr(c1 + 1, c2 - c1 - 1), s.gaze.x) ||
            !parse_number(line.substr(c2 + 1), s.gaze.y) || !std::isfinite(s.gaze.x) ||
            !std::isfinite(s.gaze.y) || std::fabs(s.gaze.x) > 1e7f || std::fabs(s.gaze.y) > 1e7f)
            throw file_error(
                name, line_number,
                "gaze '" + line.substr(c1 + 1) + "' is not two finite numbers within 1e7 pixels");
        if (!track.empty() && s.frame <= track.back().frame)
            throw file_error(name, line_number,
                             "frame " + std::to_string(s.frame) + " does not follow frame " +
                                 std::to_string(track.back().frame) +
                                 " (frames must strictly increase)");
        track.push_back(s);
        if (end == text.size()) break;
    }
    if (track.empty()) throw file_error(name, 0, "no gaze sample (expected lines 'frame,x,y')");
    return track;
}

std::vector<GazeSample> read_gaze_track(const std::string& path) {
    return parse_gaze_track(read_file(path), path);
}

glm::vec2 gaze_at_frame(const std::vector<GazeSample>& track, int frame) {
    glm::vec2 gaze = track.front().gaze;
    for (const GazeSample& s : track) {
        if (s.frame > frame) break;
        gaze = s.gaze;
    }
    return gaze;
}

std::vector<ParamSpec> gaze_param_specs() {
    return {{"gaze", "", "gaze point X,Y in screen pixels (any finite point); empty: the centre"},
            {"gaze_track", "",
             "CSV file of 'frame,x,y' lines: the gaze of each frame (held until the next "
             "sample)"}};
}

void parse_gaze_params(const Params& params, const std::vector<ParamSpec>& specs,
                       std::optional<glm::vec2>& point, std::vector<GazeSample>& track) {
    const std::vector<float> gaze = params.get_float_list(specs, "gaze");
    if (gaze.size() == 2)
        point = glm::vec2(gaze[0], gaze[1]);
    else if (!gaze.empty())
        throw Error("parameter 'gaze': expected X,Y (two numbers), got " +
                    std::to_string(gaze.size()));
    const std::string file = params.get_string(specs, "gaze_track");
    if (!file.empty()) {
        if (point) throw Error("parameters 'gaze' and 'gaze_track' both given: give one");
        track = read_gaze_track(file);
    }
}

glm::vec2 gaze_of_frame(const std::optional<glm::vec2>& point, const std::vector<GazeSample>& track,
                        int width, int height, int frame) {
    if (!track.empty()) return gaze_at_frame(track, frame);
    if (point) return *point;
    return {static_cast<float>(width) * 0.5f, static_cast<float>(height) * 0.5f};
}

}  // namespace fovref
