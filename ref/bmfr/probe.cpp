#include "ref/bmfr/probe.h"

#include "ref/bmfr/bmfr.h"

namespace fovref {

void explain_bmfr_block(const ProbeContext& c, const VisualPolarMap& m, int i, int j,
                        ProbeReport& report) {
    ProbeSection b{"bmfr_fit", "the BMFR block of this texel (staircase grid, rows wrap)", {}};
    const BmfrGrid g = bmfr_grid(m.width, m.height, c.frame->frame, &m);
    const glm::ivec2 cell = g.cell_of(i, j);
    const glm::ivec2 o = g.origin(cell.x, cell.y);
    b.add("cell", "(" + std::to_string(cell.x) + ", " + std::to_string(cell.y) + ") of " +
                      std::to_string(g.cells_x) + " block columns");
    b.add("block column",
          "phi height H = " + std::to_string(g.cell_rows[static_cast<std::size_t>(cell.x)]) +
              " rows, " + std::to_string(g.cells_in_column(cell.x)) + " blocks");
    b.add("origin", "(" + std::to_string(o.x) + ", " + std::to_string(o.y) +
                        "): columns clamped to [0, w - 1], rows modulo H; offset (" +
                        std::to_string(g.offset.x) + ", " + std::to_string(g.offset.y) + ")");
    const Image& w = c.frame->find("bmfr_weights")->image;
    std::string red;
    for (int k = 0; k < bmfr_feature_count; ++k)
        red += (k ? ", " : "") + probe_float(w.at(cell.x, cell.y, k));
    b.add("red weights", red);
    report.sections.push_back(b);
}

}  // namespace fovref
