#include "api/tandem_json.h"

#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <vector>

#include "api/plant_units.h"
#include "api/request_json.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"
#include "api/tandem_schema.h"
#include "api/text.h"
#include "api/units.h"

namespace rollgap::api {
namespace {

using nlohmann::json;

// An out-of-bounds number that a plant unit of its field would put in bounds.
std::optional<UnitSlip> out_of_range_slip(const TandemField& field, const json& value) {
    if (!value.is_number() || !std::isfinite(value.get<double>()) ||
        field.range.contains(value.get<double>()))
        return std::nullopt;
    return likely_unit_slip(field.path, field.unit.code, field.range, value.get<double>());
}

// What the reader collected before the stands are read: the lists' lengths are checked once
// the number of stands is known.
struct Reading {
    core::Mill mill = core::default_mill();
    std::vector<bool> list_read;  // per list field of the table (by index), read without error
    bool stands_valid = false;
    json stand_defaults = json::object();
    json stands = json::array();
    StandBases bases;  // one per stand once the stands are read
    // Tensions the document gave as forces (plant_units.h): the canonical field's path and the
    // member given, so that errors name what the client sent ("/spans/tension_MPa" →
    // "/spans/tension_kN").
    std::vector<std::pair<std::string, std::string>> given_as;

    // `path` (a field's, or below it) as the client gave it.
    std::string as_given(const std::string& path) const {
        for (const auto& [canonical, given] : given_as) {
            if (path == canonical || path.starts_with(canonical + "/"))
                return given + path.substr(canonical.size());
        }
        return path;
    }
};

void read_list(const TandemField& field, const json& value, const std::string& pointer,
               core::Mill& mill, FieldErrors& errors, bool& ok) {
    ok = false;
    if (!value.is_array()) {
        errors.add({pointer,
                    concat("must be an array of numbers (",
                           field.length == ListLength::stands ? "one per stand"
                                                              : "one per interstand span",
                           "), not ", json_type_name(value)),
                    field.range.text(), std::string(field.unit.code)});
        return;
    }
    // Bounded by the stand count's own bound: a longer list is refused by its length, and its
    // elements need not be read (a 10^5-element list costs one message).
    if (value.size() > static_cast<std::size_t>(core::max_mill_stands)) {
        errors.add({pointer,
                    concat("has ", std::to_string(value.size()), " values; a mill has at most ",
                           std::to_string(core::max_mill_stands), " stands"),
                    std::nullopt, std::nullopt});
        return;
    }
    std::vector<double> values;
    bool all = true;
    for (std::size_t i = 0; i < value.size(); ++i) {
        const auto number = read_number(value[i], concat(pointer, "/", std::to_string(i)),
                                        field.range, field.unit, errors);
        if (number) {
            values.push_back(to_si(*number, field.unit));
        } else {
            all = false;
        }
    }
    if (!all) return;
    field.set_list(mill, values);
    ok = true;
}

void read_group(const std::string& group, const json& node, const std::string& base,
                Reading& reading, FieldErrors& errors) {
    const std::string pointer = base + group;
    if (!require_object(node, pointer, errors)) return;
    const auto members = tandem_group_members(group);
    // A tension also as a force in kN (plant_units.h), read once the schedule is known.
    const std::vector<std::string> deferred = deferred_alternates(members);
    std::vector<std::string_view> known(members.begin(), members.end());
    known.insert(known.end(), deferred.begin(), deferred.end());
    reject_unknown_fields(node, pointer, known, errors, [&group](std::string_view name) {
        if (group.empty() && name == "mill") {
            return std::optional<std::string>(
                "the tandem document's fields sit at its top level; `mill` is a stand's "
                "structure group, set in stand_defaults or a stand's patch");
        }
        if (group.empty() && name == "scenario") {
            return std::optional<std::string>(
                "the stands' scenarios are stand_defaults (shared) and stands (one patch each)");
        }
        return std::optional<std::string>();
    });
    const auto& fields = tandem_fields();
    for (const std::string_view member : members) {
        const auto value = node.find(std::string(member));
        if (value == node.end()) continue;  // missing: the default stays
        const std::string path = concat(group, "/", member);
        if (group.empty() && member == stand_defaults_member) {
            if (value->is_null()) continue;
            if (require_object(*value, base + path, errors)) reading.stand_defaults = *value;
            continue;
        }
        if (group.empty() && member == stands_member) {
            if (!value->is_array()) {
                errors.add({base + path,
                            concat("must be an array of scenario patches, one per stand, not ",
                                   json_type_name(*value)),
                            "1 to 6 stands", std::nullopt});
            } else if (value->empty() ||
                       value->size() > static_cast<std::size_t>(core::max_mill_stands)) {
                errors.add({base + path,
                            concat("a mill has 1 to ", std::to_string(core::max_mill_stands),
                                   " stands; this one has ", std::to_string(value->size())),
                            concat("[1, ", std::to_string(core::max_mill_stands), "] stands"),
                            std::nullopt});
            } else {
                reading.stands = *value;
                reading.stands_valid = true;
            }
            continue;
        }
        if (is_tandem_group(path)) {
            read_group(path, *value, base, reading, errors);
            continue;
        }
        const TandemField* field = find_tandem_field(path);
        if (field == nullptr)
            throw std::logic_error(concat("tandem member without a field: ", path));
        const std::string at = base + path;
        switch (field->kind) {
            case TandemFieldKind::number:
                if (field->integer) {
                    if (const auto count = read_integer(*value, at, field->range, false, errors))
                        field->set(reading.mill, static_cast<double>(*count));
                } else if (const auto slip = out_of_range_slip(*field, *value)) {
                    // out of bounds, but a plant unit would fit (plant_units.h)
                    errors.add({at,
                                concat(format_number(value->get<double>()), " ", field->unit.code,
                                       " is outside ", field->range.text(), " ", field->unit.code,
                                       "; ", slip->text),
                                field->range.text(), std::string(field->unit.code)});
                } else if (const auto number =
                               read_number(*value, at, field->range, field->unit, errors)) {
                    field->set(reading.mill, to_si(*number, field->unit));
                }
                break;
            case TandemFieldKind::choice:
                if (const auto choice = read_choice(*value, at, field->choices, errors))
                    field->write_choice(reading.mill, *choice);
                break;
            case TandemFieldKind::number_list: {
                bool ok = false;
                read_list(*field, *value, at, reading.mill, errors, ok);
                reading.list_read[static_cast<std::size_t>(field - fields.data())] = ok;
                break;
            }
        }
    }
}

// Each list as long as the mill needs, the schedule falling, spans under tension.
void check_mill(const std::string& base, Reading& reading, FieldErrors& errors) {
    const core::Mill& mill = reading.mill;
    const int stands = static_cast<int>(reading.stands.size());
    const auto& fields = tandem_fields();
    for (std::size_t f = 0; f < fields.size(); ++f) {
        const TandemField& field = fields[f];
        if (field.kind != TandemFieldKind::number_list) continue;
        const std::string at = base + reading.as_given(field.path);
        if (errors.has_error_at_or_below(at)) continue;
        const int wanted = field.length == ListLength::stands ? stands : stands - 1;
        const int given = static_cast<int>(field.get_list(mill).size());
        if (given == wanted) continue;
        errors.add({at,
                    concat("has ", std::to_string(given), given == 1 ? " value" : " values",
                           "; this mill of ", std::to_string(stands),
                           stands == 1 ? " stand needs " : " stands needs ", std::to_string(wanted),
                           field.length == ListLength::stands ? " (one per stand)"
                                                              : " (one per interstand span)"),
                    concat(std::to_string(wanted), " values"),
                    at == base + field.path ? std::string(field.unit.code) : "kN"});
    }
    // The schedule: every stand makes the strip thinner.
    const std::string exits = base + "/exit_thickness_mm";
    if (!errors.has_error_at_or_below(exits) &&
        !errors.has_error_at_or_below(base + "/entry_thickness_mm")) {
        for (std::size_t i = 1; i < mill.thickness.size(); ++i) {
            if (mill.thickness[i] < mill.thickness[i - 1]) continue;
            const std::string previous = i == 1 ? "the entry thickness" : "the stand before";
            errors.add(
                {concat(exits, "/", std::to_string(i - 1)),
                 concat("the strip must get thinner at every stand: stand ", std::to_string(i),
                        " would deliver ",
                        format_number(from_si(mill.thickness[i], units::millimetre)), " mm from ",
                        format_number(from_si(mill.thickness[i - 1], units::millimetre)), " mm (",
                        previous, "); the thickness may not grow downstream"),
                 concat("< ", format_number(from_si(mill.thickness[i - 1], units::millimetre))),
                 "mm"});
        }
    }
    // A span (not a constant boundary) at zero tension is slack: there is no steady state.
    for (const bool entry : {true, false}) {
        const core::MillBoundary boundary = entry ? mill.entry : mill.exit;
        const double tension = entry ? mill.entry_tension : mill.exit_tension;
        const std::string at =
            base + reading.as_given(entry ? "/entry/tension_MPa" : "/exit/tension_MPa");
        if (boundary != core::MillBoundary::span || tension > 0.0 ||
            errors.has_error_at_or_below(at))
            continue;
        errors.add({at,
                    concat("an ", entry ? "entry" : "exit",
                           " span at zero tension is slack: give a positive tension, or a "
                           "constant boundary (",
                           base, entry ? "/entry" : "/exit", "/boundary)"),
                    at.ends_with("_kN") ? "> 0" : "(0, 3000)", at.ends_with("_kN") ? "kN" : "MPa"});
    }
}

// Tensions given as forces (`/entry/tension_kN`, `/spans/tension_kN`, `/exit/tension_kN`):
// the stresses over the strip's cross-section in each span — the mill's width × the entry
// thickness for the entry span, × stand i's exit thickness for span i and the exit span — set
// into the mill before anything judges its tensions.
void resolve_mill_tension_forces(const json& document, const std::string& base, Reading& reading,
                                 FieldErrors& errors) {
    core::Mill& mill = reading.mill;
    const int stands = static_cast<int>(reading.stands.size());
    const bool schedule = static_cast<int>(mill.thickness.size()) == stands + 1 &&
                          !errors.has_error_at_or_below(base + "/entry_thickness_mm") &&
                          !errors.has_error_at_or_below(base + "/exit_thickness_mm") &&
                          !errors.has_error_at_or_below(base + "/strip/width_mm");
    // One force: its stress in MPa over `area` m², or an error at `at` with the bound in kN.
    const auto stress_of = [&errors](const json& force, const std::string& at, double area,
                                     const Interval& range) {
        return stress_of_force(force, at, area, range, "mill width × thickness in that span",
                               errors);
    };
    for (const std::string_view group :
         {std::string_view("/entry"), std::string_view("/spans"), std::string_view("/exit")}) {
        const json::json_pointer at{concat(std::string(group), "/tension_kN")};
        if (!document.contains(at) || document.at(at).is_null()) continue;
        const std::string canonical = concat(group, "/tension_MPa");
        reading.given_as.emplace_back(canonical, concat(group, "/tension_kN"));
        const std::string pointer = base + concat(group, "/tension_kN");
        const TandemField* field = find_tandem_field(canonical);
        if (field == nullptr) throw std::logic_error("a tension without its field");
        // Over a schedule and a width that read cleanly; else their own errors say why.
        if (!schedule || errors.has_error_at_or_below(pointer)) continue;
        const json& given = document.at(at);
        if (group != "/spans") {
            const double thickness = mill.thickness[group == "/entry" ? 0 : stands];
            if (const auto stress = stress_of(given, pointer, mill.width * thickness, field->range))
                field->set(mill, to_si(*stress, units::megapascal));
            continue;
        }
        if (!given.is_array()) {
            errors.add(
                {pointer, "must be an array of numbers in kN, one per span", std::nullopt, "kN"});
            continue;
        }
        std::vector<double> stresses;
        bool ok = true;
        for (std::size_t i = 0; i < given.size(); ++i) {
            // span i leaves stand i (0-based) at its exit thickness; more values than spans:
            // the length check says so at the list
            const double thickness = i + 1 < mill.thickness.size() ? mill.thickness[i + 1] : 0.0;
            if (thickness <= 0.0) {
                stresses.push_back(0.0);
                continue;
            }
            const auto stress = stress_of(given[i], concat(pointer, "/", std::to_string(i)),
                                          mill.width * thickness, field->range);
            ok = ok && stress.has_value();
            stresses.push_back(stress ? to_si(*stress, units::megapascal) : 0.0);
        }
        mill.interstand_tension = std::move(stresses);
        reading.list_read[static_cast<std::size_t>(field - tandem_fields().data())] = ok;
    }
}

// The stand's roll speed: the mill's in schedule mode, the stand's own in speeds mode (§12.3).
constexpr std::string_view roll_speed_path = "/rolls/speed_m_per_s";
bool given_by_mill(const MillOwnedField& owned, const core::Mill& mill) {
    return mill.mode != core::MillMode::speeds || owned.stand_path != roll_speed_path;
}

// A stand's patch (or the shared defaults) setting what the mill gives.
void reject_mill_owned(const json& patch, const std::string& pointer, const core::Mill& mill,
                       FieldErrors& errors) {
    if (!patch.is_object()) return;
    for (const MillOwnedField& owned : mill_owned_stand_fields()) {
        if (!given_by_mill(owned, mill)) continue;
        const json::json_pointer at{std::string(owned.stand_path)};
        if (!patch.contains(at) || patch.at(at).is_null()) continue;
        errors.add({pointer + std::string(owned.stand_path),
                    concat("the mill gives every stand this value: set it in ", owned.given_by,
                           ", not in a stand's scenario"),
                    std::nullopt, std::nullopt});
    }
}

// The stand's scenario document with the values the mill gives it, so that the single stand's
// own rules (bounds, the bite angle, tension below the flow stress) judge the stand as it runs.
json stand_document(const json& shared, const json& patch, const core::Mill& mill, int stand) {
    json document = default_scenario_json();
    document.merge_patch(shared);
    if (patch.is_object()) document.merge_patch(patch);  // null: the shared stand as it is
    const core::Scenario given = core::stand_scenario(mill, stand, mill.speed);
    const json resolved = resolved_scenario_json(given);
    for (const MillOwnedField& owned : mill_owned_stand_fields()) {
        if (!given_by_mill(owned, mill)) continue;
        const json::json_pointer at{std::string(owned.stand_path)};
        document[at] = resolved.at(at);
    }
    return document;
}

// A stand's "base" (docs/http-api.md, "Stored stands in a mill"), taken out of its patch: the
// resolved form is recorded, a name is refused here (only the service has the store).
void read_stand_base(json& patch, const std::string& pointer, std::optional<ScenarioBase>& base,
                     FieldErrors& errors) {
    if (!patch.is_object()) return;
    const auto found = patch.find("base");
    if (found == patch.end()) return;
    const std::string at = pointer + "/base";
    if (found->is_string()) {
        const std::string& name = found->get_ref<const std::string&>();
        if (auto error = stored_scenario_name_error(name, at)) {
            errors.add(std::move(*error));
        } else {
            errors.add({at,
                        concat("a stored stand is read by the service when it accepts an "
                               "analysis request (not by rollgap run, nor into a stored mill): "
                               "here send the stand itself, e.g. the body of GET /v1/scenarios/",
                               name, " without the fields the mill gives a stand"),
                        std::nullopt, std::nullopt});
        }
    } else if (found->is_object()) {
        base = read_resolved_base(*found, at, errors);
    } else if (!found->is_null()) {
        errors.add({at,
                    concat("must be the name of a stored stand scenario (a string), not ",
                           json_type_name(*found)),
                    std::string(stored_scenario_name_pattern), std::nullopt});
    }
    patch.erase(found);
}

void read_stands(const std::string& base, Reading& reading, FieldErrors& errors) {
    core::Mill& mill = reading.mill;
    const int stands = static_cast<int>(reading.stands.size());
    const std::string defaults_pointer = concat(base, "/", stand_defaults_member);
    reject_mill_owned(reading.stand_defaults, defaults_pointer, mill, errors);
    // The shared defaults alone, so that their violations are reported once, where they are.
    const json no_patch = json::object();
    FieldErrors shared_errors;
    {
        json document = default_scenario_json();
        document.merge_patch(reading.stand_defaults);
        (void)scenario_from_json(document, defaults_pointer, shared_errors);
    }
    // The rules that involve what the mill gives (a tension against the flow stress, the bite
    // angle) are judged per stand below, with the mill's values, not here with the defaults'.
    const auto involves_mill = [&](const std::string& at) {
        const std::string path = at.substr(defaults_pointer.size());
        return !tandem_pointer_of_stand_field(path, 0, stands).empty();
    };
    bool shared_valid = true;
    for (const FieldError& error : shared_errors.reported()) {
        if (involves_mill(error.pointer)) continue;
        shared_valid = false;
        if (!errors.has_error_at_or_below(error.pointer)) errors.add(error);
    }
    // The mill's own values, judged per stand, only where the mill's fields read cleanly.
    const bool schedule_valid = static_cast<int>(mill.thickness.size()) == stands + 1 &&
                                static_cast<int>(mill.span_length.size()) == stands - 1 &&
                                static_cast<int>(mill.interstand_tension.size()) == stands - 1;
    mill.stands.assign(static_cast<std::size_t>(stands), core::Scenario{});
    reading.bases.assign(static_cast<std::size_t>(stands), std::nullopt);
    for (int i = 0; i < stands; ++i) {
        const std::string pointer = concat(base, "/", stands_member, "/", std::to_string(i));
        json patch = reading.stands[static_cast<std::size_t>(i)];
        if (!patch.is_null() && !require_object(patch, pointer, errors)) continue;
        read_stand_base(patch, pointer, reading.bases[static_cast<std::size_t>(i)], errors);
        reject_mill_owned(patch, pointer, mill, errors);
        // speeds mode: every stand's roll speed is its own, in its patch or the shared defaults
        const json::json_pointer speed_at{std::string(roll_speed_path)};
        const auto gives_speed = [&speed_at](const json& p) {
            return p.is_object() && p.contains(speed_at) && !p.at(speed_at).is_null();
        };
        if (mill.mode == core::MillMode::speeds && !gives_speed(patch) &&
            !gives_speed(reading.stand_defaults)) {
            errors.add({pointer + std::string(roll_speed_path),
                        concat("speeds mode needs every stand's roll speed: stand ",
                               std::to_string(i + 1), " has none"),
                        std::nullopt, "m/s"});
        }
        if (!schedule_valid) continue;
        FieldErrors stand_errors;
        const json document =
            stand_document(shared_valid ? reading.stand_defaults : no_patch, patch, mill, i);
        mill.stands[static_cast<std::size_t>(i)] =
            scenario_from_json(document, pointer, stand_errors);
        for (const FieldError& error : stand_errors.reported()) {
            // A value the mill gives: reported at the mill's field, naming the stand.
            const std::string stand_path = error.pointer.substr(pointer.size());
            const bool own_speed =
                mill.mode == core::MillMode::speeds && stand_path.starts_with(roll_speed_path);
            const std::string given =
                own_speed ? std::string() : tandem_pointer_of_stand_field(stand_path, i, stands);
            FieldError moved = error;
            if (!given.empty()) {
                moved.pointer = base + reading.as_given(given);
                moved.detail = concat("stand ", std::to_string(i + 1), ": ", error.detail);
            }
            if (!errors.has_error_at_or_below(moved.pointer)) errors.add(std::move(moved));
        }
    }
}

// Speeds mode: the mill speed is the last stand's roll speed (§12.3).
void check_mill_speed(const std::string& base, const core::Mill& mill, FieldErrors& errors) {
    if (mill.mode != core::MillMode::speeds || mill.stands.empty()) return;
    const std::string last =
        concat(base, "/", stands_member, "/", std::to_string(mill.stands.size() - 1),
               std::string(roll_speed_path));
    if (errors.has_error_at_or_below(last) || errors.has_error_at_or_below(base + "/speed_m_per_s"))
        return;
    const double v = mill.stands.back().rolls.speed;
    if (std::abs(mill.speed - v) <= 1e-12 * v) return;
    errors.add({base + "/speed_m_per_s",
                concat("in speeds mode the mill speed is the last stand's roll speed (",
                       format_number(v), " m/s at ", last, "), not ", format_number(mill.speed)),
                format_number(v), "m/s"});
}

}  // namespace

nlohmann::json without_mill_owned_fields(nlohmann::json stand, bool speeds_mode) {
    if (!stand.is_object()) return stand;
    for (const MillOwnedField& owned : mill_owned_stand_fields()) {
        if (speeds_mode && owned.stand_path == roll_speed_path) continue;  // the stand's own
        const std::string path(owned.stand_path);
        const auto slash = path.rfind('/');
        const json::json_pointer parent_at(path.substr(0, slash));
        if (!stand.contains(parent_at)) continue;
        json& parent = stand[parent_at];
        if (parent.is_object()) parent.erase(path.substr(slash + 1));
    }
    return stand;
}

nlohmann::json resolved_tandem_json(const core::Mill& mill, const StandBases* bases) {
    json document = json::object();
    for (const TandemField& field : tandem_fields()) {
        json& slot = document[json::json_pointer(field.path)];
        switch (field.kind) {
            case TandemFieldKind::number:
                if (field.integer) slot = static_cast<long long>(field.get(mill));
                else slot = from_si(field.get(mill), field.unit);
                break;
            case TandemFieldKind::choice: slot = std::string(field.read_choice(mill)); break;
            case TandemFieldKind::number_list: {
                slot = json::array();
                for (const double value : field.get_list(mill))
                    slot.push_back(from_si(value, field.unit));
                break;
            }
        }
    }
    document[std::string(stand_defaults_member)] = json::object();
    json stands = json::array();
    for (std::size_t i = 0; i < mill.stands.size(); ++i) {
        json scenario = resolved_scenario_json(mill.stands[i]);
        for (const MillOwnedField& owned : mill_owned_stand_fields()) {
            if (!given_by_mill(owned, mill)) continue;  // speeds mode: the stand's own speed
            const std::string path(owned.stand_path);
            const auto slash = path.rfind('/');
            json& parent =
                slash == 0 ? scenario : scenario[json::json_pointer(path.substr(0, slash))];
            parent.erase(path.substr(slash + 1));
        }
        if (bases != nullptr && i < bases->size() && (*bases)[i])
            scenario["base"] = scenario_base_json(*(*bases)[i]);
        stands.push_back(std::move(scenario));
    }
    document[std::string(stands_member)] = std::move(stands);
    return document;
}

nlohmann::json default_tandem_json() {
    // Each default stand is the empty patch, so that a request's stand_defaults reach every
    // stand it does not patch itself (a complete scenario here would override them).
    static const json defaults = [] {
        json document = resolved_tandem_json(core::default_mill());
        for (json& stand : document[std::string(stands_member)]) stand = json::object();
        return document;
    }();
    return defaults;
}

core::Mill mill_from_json(const nlohmann::json& document, const std::string& pointer,
                          FieldErrors& errors, StandBases* bases) {
    Reading reading;
    reading.list_read.assign(tandem_fields().size(), false);
    read_group("", document, pointer, reading, errors);
    if (!document.is_object()) return reading.mill;
    if (reading.stands_valid) {
        resolve_mill_tension_forces(document, pointer, reading, errors);
        check_mill(pointer, reading, errors);
        read_stands(pointer, reading, errors);
        check_mill_speed(pointer, reading.mill, errors);
        if (bases != nullptr) *bases = std::move(reading.bases);
    }
    if (errors.empty()) {
        // core's own guard agrees with the field checks; a disagreement is a bug, said plainly
        if (const char* defect = core::mill_defect(reading.mill); *defect != '\0') {
            errors.add({pointer, concat("not a mill: ", defect), std::nullopt, std::nullopt});
        }
    }
    return reading.mill;
}

core::Mill mill_from_patch(const nlohmann::json& patch, const std::string& pointer,
                           FieldErrors& errors, StandBases* bases) {
    json document = default_tandem_json();
    document.merge_patch(patch);
    return mill_from_json(document, pointer, errors, bases);
}

}  // namespace rollgap::api
