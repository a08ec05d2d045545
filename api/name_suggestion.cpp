#include "api/name_suggestion.h"

#include <algorithm>
#include <cctype>
#include <vector>

#include "api/text.h"

namespace rollgap::api {
namespace {

// Levenshtein distance, case-insensitive (a wrong case is a typo too).
std::size_t edit_distance(std::string_view a, std::string_view b) {
    const auto lower = [](char c) { return std::tolower(static_cast<unsigned char>(c)); };
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            const std::size_t substitution =
                diagonal + (lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1);
            row[j] = std::min({above + 1, row[j - 1] + 1, substitution});
            diagonal = above;
        }
    }
    return row[b.size()];
}

}  // namespace

std::optional<std::string_view> closest_name(std::string_view name,
                                             std::span<const std::string_view> known) {
    constexpr std::size_t longest_compared = 64;  // names are short; do not scan client blobs
    if (name.empty() || name.size() > longest_compared) return std::nullopt;
    std::optional<std::string_view> best;
    std::size_t best_distance = 0;
    for (const std::string_view candidate : known) {
        const std::size_t distance = edit_distance(name, candidate);
        if (!best || distance < best_distance) {
            best = candidate;
            best_distance = distance;
        }
    }
    // Up to a third of the name may differ: "speed_mps" → "speed_m_per_s" (4 edits) is
    // suggested, "thickness" → "width_mm" is not.
    const std::size_t tolerance =
        std::max<std::size_t>(3, std::max(name.size(), best ? best->size() : 0) / 3);
    if (best && best_distance <= tolerance) return best;
    return std::nullopt;
}

std::string did_you_mean(std::optional<std::string_view> suggestion) {
    return suggestion ? concat("; did you mean '", *suggestion, "'?") : std::string();
}

std::string did_you_mean(std::string_view name, std::span<const std::string_view> known) {
    return did_you_mean(closest_name(name, known));
}

}  // namespace rollgap::api
