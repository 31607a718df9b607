// The SVG plot of 'dynpm eval': the two-sided Hausdorff distance (% of the diagonal, y, linear)
// against the vertices kept (% of the full count, x, log scale); one polyline per chosen step
// and one, black and dashed, for the max over steps.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dynpm/pipeline.h"

namespace dynpm::cli {

// `v` with up to `digits` significant digits (printf's %g).
std::string format_number(double v, int digits = 4);

// The plot as a standalone SVG document (without the XML declaration): `table`'s rows, its
// chosen steps (legend "step T") and `max_label` for the max column; x in % of `full_vertices`.
std::string svg_plot(const LevelsTable& table, const std::string& max_label, uint32_t full_vertices,
                     const std::string& title);

}  // namespace dynpm::cli
