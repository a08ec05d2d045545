#pragma once
// Stability maps (docs/model.md, "Stability maps"): the critical speed over a grid of two
// scenario fields, every cell in parallel with the sweep machinery, and the neighbouring cells
// where the crossing mode changes its chatter type.

#include <vector>

#include "core/control.h"
#include "core/stability.h"
#include "core/sweep.h"

namespace rollgap::core {

struct StabilityMap {
    int rows = 0, columns = 0;               // values of the first and of the second field
    std::vector<CriticalSpeedResult> cells;  // row-major: cell (i, j) at i * columns + j; no scans
    std::vector<ChatterTypeChange> changes;  // along rows and columns, cell indices as above
};

// `cells` row-major, rows × columns scenarios. A cancelled run leaves cells "cancelled".
StabilityMap stability_map(const std::vector<Scenario>& cells, int rows, int columns,
                           const CriticalSpeedOptions& options, const Control& control = {});

// The neighbour pairs of a rows × columns grid: (i, j)-(i, j+1) and (i, j)-(i+1, j).
std::vector<std::pair<int, int>> grid_neighbours(int rows, int columns);

}  // namespace rollgap::core
