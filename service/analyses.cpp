#include "service/analyses.h"

#include <algorithm>
#include <array>

#include "service/roll_gap_analysis.h"

namespace rollgap::service {
namespace {

constexpr std::array table{
    Analysis{"roll_gap", "steady roll-bite pressure, friction and film distributions (MODEL.md §7.1)",
             &prepare_roll_gap},
};

}  // namespace

std::span<const Analysis> analyses() { return table; }

const Analysis* find_analysis(std::span<const Analysis> offered, std::string_view name) {
    const auto row = std::find_if(offered.begin(), offered.end(),
                                  [name](const Analysis& analysis) { return analysis.name == name; });
    return row == offered.end() ? nullptr : &*row;
}

}  // namespace rollgap::service
