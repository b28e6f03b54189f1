// A recorded gaze path for a sequence (issue 13, point 3): frame -> gaze point, read from a small
// CSV file so that an eye tracker's output can drive the foveated modes (`--param
// gaze_track=FILE`). docs/foveation.md, "Gaze".
//
// Format: one sample per line, `frame,x,y` (frame an integer >= 0, x and y finite numbers in
// screen pixels, any point, on screen or off); blank lines and lines starting with '#' are
// ignored, so is a first line `frame,x,y`. Frames strictly increase. Frame f uses the sample
// with the largest frame <= f (the gaze holds until the next sample); frames before the first
// sample use the first.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ref/stage/params.h"

namespace fovref {

struct GazeSample {
    int frame = 0;
    glm::vec2 gaze{0.0f};
    bool operator==(const GazeSample&) const = default;
};

/// Parses a gaze track; `name` names it in errors ("FILE:LINE: ..."). Throws fovref::Error for a
/// malformed line, a non-finite or absurd value (|x|, |y| > 1e7), frames not increasing, or no
/// sample.
std::vector<GazeSample> parse_gaze_track(const std::string& text, const std::string& name);

/// Reads and parses a gaze track file (size limit of docs/limits.md).
std::vector<GazeSample> read_gaze_track(const std::string& path);

/// The gaze of frame `frame` (see above). `track` must not be empty.
glm::vec2 gaze_at_frame(const std::vector<GazeSample>& track, int frame);

/// The gaze parameters every foveated mode takes: `gaze=X,Y` (any finite point) and
/// `gaze_track=FILE` (at most one of them).
std::vector<ParamSpec> gaze_param_specs();
/// Parses them into `point` and `track` (from `specs`, which holds gaze_param_specs()); throws
/// fovref::Error naming the parameter.
void parse_gaze_params(const Params& params, const std::vector<ParamSpec>& specs,
                       std::optional<glm::vec2>& point, std::vector<GazeSample>& track);
/// The gaze of frame `frame` on a W x H screen: the track's, else the point, else the centre
/// (W/2, H/2).
glm::vec2 gaze_of_frame(const std::optional<glm::vec2>& point, const std::vector<GazeSample>& track,
                        int width, int height, int frame);

}  // namespace fovref
