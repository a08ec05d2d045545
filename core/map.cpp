#include "core/map.h"

namespace rollgap::core {

std::vector<std::pair<int, int>> grid_neighbours(int rows, int columns) {
    std::vector<std::pair<int, int>> pairs;
    for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < columns; ++j) {
            const int here = i * columns + j;
            if (j + 1 < columns) pairs.emplace_back(here, here + 1);
            if (i + 1 < rows) pairs.emplace_back(here, here + columns);
        }
    }
    return pairs;
}

StabilityMap stability_map(const std::vector<Scenario>& cells, int rows, int columns,
                           const CriticalSpeedOptions& options, const Control& control) {
    StabilityMap map;
    map.rows = rows;
    map.columns = columns;
    map.cells = sweep_critical_speed(cells, options, control, false);
    if (static_cast<long>(map.cells.size()) == static_cast<long>(rows) * columns) {
        map.changes = chatter_type_changes(map.cells, grid_neighbours(rows, columns));
    }
    return map;
}

}  // namespace rollgap::core
