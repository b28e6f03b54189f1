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

#include <string>
#include <vector>

#include <glm/glm.hpp>

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

}  // namespace fovref
