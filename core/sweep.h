#pragma once
// Sweeps (docs/model.md §7.5): one analysis over many scenarios, in parallel. Each scenario is
// independent and its result lands in its own slot, so the results do not depend on the thread
// count.

#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "core/amplitude.h"
#include "core/control.h"
#include "core/stability.h"

namespace rollgap::core {

// keep_scan = false drops each point's scan and damping branches as soon as it is done (a map's
// thousands of cells would otherwise hold some 100 kB each).
// The scenarios are a span so that a caller can run a slice of a larger sweep (a chunk of its
// points) without copying it.
std::vector<CriticalSpeedResult> sweep_critical_speed(std::span<const Scenario> scenarios,
                                                      const CriticalSpeedOptions& options,
                                                      int threads, const Control& control = {},
                                                      bool keep_scan = true);

std::vector<AmplitudeResult> sweep_amplitude(std::span<const Scenario> scenarios,
                                             const AmplitudeOptions& options, int threads,
                                             const Control& control = {});

// The chatter type of the mode that goes unstable first (docs/model.md, "Chatter type"): when
// the search found a crossing or the range starts unstable, nothing otherwise.
std::optional<ChatterType> crossing_chatter_type(const CriticalSpeedResult& result);

// A pair of neighbouring points whose crossing modes are of different types: the critical speed
// on either side belongs to a different vibration, so it may jump between them.
struct ChatterTypeChange {
    int from = 0, to = 0;  // indices into the results
    ChatterType from_type = ChatterType::other, to_type = ChatterType::other;
};

// The pairs of `neighbours` (index pairs into `results`) where the crossing type changes; a
// pair where either side has no crossing mode is not a change.
std::vector<ChatterTypeChange> chatter_type_changes(
    const std::vector<CriticalSpeedResult>& results,
    const std::vector<std::pair<int, int>>& neighbours);

// The same from the crossing types alone (crossing_chatter_type of each point, nothing where a
// point has none): what a caller holding only the points' written results (a sweep assembled
// from chunks computed apart) still knows.
std::vector<ChatterTypeChange> chatter_type_changes(
    const std::vector<std::optional<ChatterType>>& crossing_types,
    const std::vector<std::pair<int, int>>& neighbours);

// The neighbour pairs of a sweep: each value and the next, in the order given.
std::vector<std::pair<int, int>> sequence_neighbours(int count);

// The same for a sweep: each value against the next, in the order given.
std::vector<ChatterTypeChange> chatter_type_changes(
    const std::vector<CriticalSpeedResult>& results);

}  // namespace rollgap::core
