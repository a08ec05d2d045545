#pragma once
// The tandem document's own fields as one table (docs/model.md §12.8), beside the scenario's
// (api/scenario_schema.h): every mill-level field of core::Mill is one row with its JSON path
// relative to the "tandem" document, unit, bounds, description and accessors. Reading, writing,
// the default document, unknown-field detection, the OpenAPI schemas and the glossary
// (`rollgap scenario --explain`) all come from this table and the scenario's.
//
// A tandem document:
//   {"entry_thickness_mm": 2.8, "exit_thickness_mm": [2.25, 1.88, 1.6, 1.36, 1.2],
//    "speed_m_per_s": 15, "mode": "schedule",
//    "strip": {"width_mm", "youngs_modulus_GPa", "density_kg_per_m3"},
//    "spans": {"length_m": [...N-1], "tension_MPa": [...N-1], "model": "spring",
//              "segment_count": 10},
//    "entry": {"boundary": "span", "span_length_m": 5, "tension_MPa": 18},
//    "exit": {"boundary": "span", "span_length_m": 5, "tension_MPa": 40},
//    "stand_defaults": {<scenario patch shared by every stand>},
//    "stands": [{<scenario patch of stand 1>}, ...]}
// Each stand is a complete single-stand scenario: the default scenario, then stand_defaults,
// then its own patch (RFC 7396). The fields the mill gives a stand (its thicknesses, width, E,
// roll speed and tensions) are not set in a stand's patch: `mill_owned_stand_fields`.
//
// The name `mill` (DECISIONS T): the scenario's group `/mill/` is one stand's structure (masses,
// stiffnesses, damping) and keeps that v1 name; the mill as a whole is the `tandem` document,
// whose own fields never sit under a member named `mill`. So /tandem/stands/2/mill/masses_t/m1
// is stand 3's backup-roll crosshead mass, and nothing else in a tandem document is a `mill`.

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "api/interval.h"
#include "api/units.h"
#include "core/mill/mill.h"

namespace rollgap::api {

enum class TandemFieldKind { number, number_list, choice };
// The length of a list field: one value per stand, or per interstand span.
enum class ListLength { stands, spans };

struct TandemField {
    std::string path;  // JSON pointer relative to the tandem document: "/spans/length_m"
    TandemFieldKind kind = TandemFieldKind::number;
    std::string description;  // for a plant engineer, as the scenario fields' descriptions
    std::string name;         // for a label or an axis title, as the scenario fields' names
    // numbers and every element of a list, in `unit` (as the client writes them)
    Unit unit = units::one;
    Interval range{0.0, 0.0};
    bool integer = false;  // a number that must be whole (a count)
    ListLength length = ListLength::stands;
    std::vector<std::string_view> choices;

    // Exactly the accessors of `kind` are set; values are SI inside core::Mill.
    std::function<double(const core::Mill&)> get;
    std::function<void(core::Mill&, double)> set;
    std::function<std::vector<double>(const core::Mill&)> get_list;
    std::function<void(core::Mill&, const std::vector<double>&)> set_list;
    std::function<std::string_view(const core::Mill&)> read_choice;
    std::function<void(core::Mill&, std::string_view)> write_choice;  // choice is valid
};

// The tandem document's members that are scenario patches, not fields of this table.
inline constexpr std::string_view stand_defaults_member = "stand_defaults";
inline constexpr std::string_view stands_member = "stands";

const std::vector<TandemField>& tandem_fields();
const TandemField* find_tandem_field(std::string_view path);
// "" (the document), "/strip", "/spans", "/entry", "/exit"; members in schema order (the root
// lists stand_defaults and stands last).
bool is_tandem_group(std::string_view path);
std::span<const std::string_view> tandem_group_members(std::string_view path);

// A field of a stand's scenario that the mill gives (schedule mode): the stand's entry
// thickness and reduction (the schedule's thicknesses), width and Young's modulus (the mill's
// strip), roll speed (solved from the mass flow), tensions (the spans and boundaries).
struct MillOwnedField {
    std::string_view stand_path;  // in the scenario document; "/tension" is the whole group
    std::string_view given_by;    // for the message: where the tandem document sets it
};
std::span<const MillOwnedField> mill_owned_stand_fields();

// The pointer, relative to the tandem document, of the value the mill gives stand `stand`
// (0-based) of `stand_count` for its scenario field `stand_path` (a mill-owned field or one
// below "/tension"), e.g. "/strip/reduction" of stand 2 -> "/exit_thickness_mm/2"; "" if it
// is not mill-owned.
std::string tandem_pointer_of_stand_field(std::string_view stand_path, int stand, int stand_count);

}  // namespace rollgap::api
