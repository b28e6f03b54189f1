// The Visual-Polar maps of the BMFR speed tests' trials (phases I and III, the TAA): a w x h
// buffer on a 120 x 90 screen, the gaze at the centre (off the screen in trial 3), BMFR's
// staircase (B = 8, offset 2), and the previous frame's map with the staircase moved (offset 5;
// the same in trial 2).
#pragma once

#include "ref/visual_polar/map.h"

namespace fovref::test {

struct VpTrialMaps {
    glm::vec2 gaze{0.0f};
    VisualPolarMap map, previous;
};

inline VpTrialMaps vp_trial_maps(int trial, int w, int h) {
    VpTrialMaps m;
    m.gaze = trial == 3 ? glm::vec2(-20.0f, 30.0f) : glm::vec2(60.0f, 45.0f);
    m.map = make_visual_polar_map(120, 90, m.gaze, w, h);
    m.map.staircase_block = 8;
    m.map.staircase_offset = 2;
    m.previous = m.map;
    m.previous.staircase_offset = trial == 2 ? 2 : 5;
    return m;
}

}  // namespace fovref::test
