#include "api/tandem_schema.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>

#include "api/field_column.h"
#include "api/scenario_schema.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

using std::string_view_literals::operator""sv;

// The bounds of a mill quantity that is also a scenario field: the same physical plausibility
// in both documents (a mill's entry thickness is a stand's entry thickness).
Interval scenario_range(std::string_view path) {
    const ScenarioField* field = find_scenario_field(path);
    return field == nullptr ? Interval{} : field->range;
}

TandemField number(std::string path, Unit unit, Interval range, std::string description,
                   std::function<double(const core::Mill&)> get,
                   std::function<void(core::Mill&, double)> set) {
    TandemField field;
    field.path = std::move(path);
    field.kind = TandemFieldKind::number;
    field.unit = unit;
    field.range = range;
    field.description = std::move(description);
    field.get = std::move(get);
    field.set = std::move(set);
    return field;
}

TandemField list(std::string path, Unit unit, Interval range, ListLength length,
                 std::string description, std::vector<double> core::Mill::*member) {
    TandemField field;
    field.path = std::move(path);
    field.kind = TandemFieldKind::number_list;
    field.unit = unit;
    field.range = range;
    field.length = length;
    field.description = std::move(description);
    field.get_list = [member](const core::Mill& mill) { return mill.*member; };
    field.set_list = [member](core::Mill& mill, const std::vector<double>& values) {
        mill.*member = values;
    };
    return field;
}

// A choice field over an enum member of the mill: its names and values in one list, the first
// name for any value not listed (there is none: every value has its name).
template <class Enum>
TandemField choice(std::string path, Enum core::Mill::*member,
                   std::vector<std::pair<std::string_view, Enum>> options,
                   std::string description) {
    TandemField field;
    field.path = std::move(path);
    field.kind = TandemFieldKind::choice;
    for (const auto& [name, value] : options) field.choices.push_back(name);
    field.description = std::move(description);
    field.read_choice = [member, options](const core::Mill& mill) {
        for (const auto& [name, value] : options)
            if (mill.*member == value) return name;
        return options.front().first;
    };
    field.write_choice = [member, options](core::Mill& mill, std::string_view chosen) {
        for (const auto& [name, value] : options)
            if (name == chosen) mill.*member = value;
    };
    return field;
}

TandemField boundary(bool entry) {
    return choice(
        entry ? "/entry/boundary" : "/exit/boundary",
        entry ? &core::Mill::entry : &core::Mill::exit,
        {{"span", core::MillBoundary::span}, {"constant", core::MillBoundary::constant}},
        entry ? "What holds the strip before stand 1 (docs/model.md §12.1): span = a bridle or "
                "uncoiler held at the steady entry speed, span_length_m upstream, its strip force "
                "a state (the default); constant = the back tension of stand 1 held at "
                "tension_MPa."
              : "What holds the strip after the last stand (docs/model.md §12.1): span = a coiler "
                "or exit bridle held at the steady exit speed, span_length_m downstream, its "
                "strip force a state (the default: at 100-700 Hz a coiler is a speed source); "
                "constant = the last stand's front tension held at tension_MPa, which decouples "
                "its front side (the single stand's convention).");
}

std::vector<TandemField> make_fields() {
    using namespace units;
    const Interval thickness = scenario_range("/strip/entry_thickness_mm");
    const Interval span_length = scenario_range("/tension/back/span_length_m");
    const Interval stress = scenario_range("/tension/back/stress_MPa");
    const Interval positive_stress = open_closed(0.0, stress.max);
    std::vector<TandemField> fields;
    fields.push_back(number(
        "/entry_thickness_mm", millimetre, thickness,
        "Strip thickness entering stand 1, y1 of stand 1 (docs/model.md §12.3). Hot bands into a "
        "cold tandem mill typically 1.8-4 mm.",
        [](const core::Mill& mill) { return mill.thickness.empty() ? 0.0 : mill.thickness[0]; },
        [](core::Mill& mill, double value) {
            if (mill.thickness.empty()) mill.thickness.resize(1);
            mill.thickness[0] = value;
        }));
    {
        TandemField exits;
        exits.path = "/exit_thickness_mm";
        exits.kind = TandemFieldKind::number_list;
        exits.unit = millimetre;
        exits.range = thickness;
        exits.length = ListLength::stands;
        exits.description =
            "The pass schedule: the strip thickness leaving each stand, one per stand, falling "
            "(docs/model.md §12.3); stand i+1 receives what stand i delivers. The default "
            "2.25 / 1.88 / 1.60 / 1.36 / 1.20 mm is a light 57 % schedule inside the rigid-roll "
            "bite; thin-gauge schedules (below ~0.5 mm) need roll flattening.";
        exits.get_list = [](const core::Mill& mill) {
            return mill.thickness.size() < 2
                       ? std::vector<double>{}
                       : std::vector<double>(mill.thickness.begin() + 1, mill.thickness.end());
        };
        exits.set_list = [](core::Mill& mill, const std::vector<double>& values) {
            const double entry = mill.thickness.empty() ? 0.0 : mill.thickness[0];
            mill.thickness.assign(1, entry);
            mill.thickness.insert(mill.thickness.end(), values.begin(), values.end());
        };
        fields.push_back(std::move(exits));
    }
    fields.push_back(number(
        "/speed_m_per_s", metre_per_second, scenario_range("/rolls/speed_m_per_s"),
        "Mill speed V: the last stand's work-roll surface speed (docs/model.md §12.3); every other "
        "stand's roll speed follows from the mass flow. Tandem cold mills typically 5-30 m/s.",
        [](const core::Mill& mill) { return mill.speed; },
        [](core::Mill& mill, double value) { mill.speed = value; }));
    fields.push_back(choice(
        "/mode", &core::Mill::mode,
        {{"schedule", core::MillMode::schedule}, {"speeds", core::MillMode::speeds}},
        "How the steady state is set (docs/model.md §12.3): schedule = the thicknesses, the "
        "tension set points and the mill speed are given, every other stand's roll speed "
        "solves the mass flow (a stand's rolls/speed_m_per_s is then refused); speeds = every "
        "stand's roll speed is given in its own patch (rolls/speed_m_per_s, required; the "
        "last equal to speed_m_per_s) and the interstand tensions solve the mass flow "
        "(spans/tension_MPa is then only the search's start)."));
    fields.push_back(number(
        "/strip/width_mm", millimetre, scenario_range("/strip/width_mm"),
        "Strip width w, common to the mill. Typically 600-2000 mm on a wide cold mill.",
        [](const core::Mill& mill) { return mill.width; },
        [](core::Mill& mill, double value) { mill.width = value; }));
    fields.push_back(number(
        "/strip/youngs_modulus_GPa", gigapascal, scenario_range("/strip/youngs_modulus_GPa"),
        "Young's modulus E of the strip: the spans' stiffness E y / L (docs/model.md §12.1). "
        "Steel 200-210 GPa.",
        [](const core::Mill& mill) { return mill.youngs_modulus; },
        [](core::Mill& mill, double value) { mill.youngs_modulus = value; }));
    fields.push_back(number(
        "/strip/density_kg_per_m3", kilogram_per_cubic_metre, closed(1000.0, 25000.0),
        "Strip density rho: the speed of longitudinal waves c = sqrt(E / rho) against which the "
        "spring law's range is judged (omega L / c, docs/model.md §12.7). Steel 7850 kg/m3.",
        [](const core::Mill& mill) { return mill.strip_density; },
        [](core::Mill& mill, double value) { mill.strip_density = value; }));
    fields.push_back(list("/spans/length_m", metre, span_length, ListLength::spans,
                          "Length L_i of each interstand span, stand i to stand i+1 (N - 1 "
                          "values): the spring law's stiffness E y / L and the transport delay "
                          "L / u (docs/model.md §12.1-12.2). Typically 4-6 m.",
                          &core::Mill::span_length));
    fields.push_back(list("/spans/tension_MPa", megapascal, positive_stress, ListLength::spans,
                          "Tension set point of each interstand span as a stress (N - 1 values), "
                          "over the span's steady thickness: its force per width is T = sigma y "
                          "(docs/model.md §12.1). A span at zero tension is slack. Typically "
                          "60-210 MPa, rising towards the last stands.",
                          &core::Mill::interstand_tension));
    {
        fields.push_back(choice(
            "/spans/model", &core::Mill::span_model,
            {{"spring", core::SpanModel::spring}, {"segments", core::SpanModel::segments}},
            "How every span (entry, interstand, exit) carries its strip force (docs/model.md "
            "§12.1): spring = one force per span, the strip massless (the default; valid well "
            "below the span's first longitudinal mode c / 2L, about 517 Hz on 5 m of steel); "
            "segments = the span cut into segment_count springs with the strip's mass between "
            "them, which carries longitudinal strip waves (2 segment_count - 1 states per span "
            "instead of 1)."));
        TandemField count = number(
            "/spans/segment_count", one, closed(2.0, core::max_span_segments),
            "Number of segments n per span under the segments model, a whole number (ignored "
            "under spring): the first strip wave is within 1 % of c / 2L from n = 10 (docs/model.md "
            "§12.1); each segment adds two states per span.",
            [](const core::Mill& mill) { return static_cast<double>(mill.span_segments); },
            [](core::Mill& mill, double value) { mill.span_segments = static_cast<int>(value); });
        count.integer = true;
        fields.push_back(std::move(count));
    }
    for (const bool entry : {true, false}) {
        fields.push_back(boundary(entry));
        const std::string group = entry ? "/entry" : "/exit";
        fields.push_back(number(
            group + "/span_length_m", metre, span_length,
            entry ? "Length L_0 of the entry span, from the bridle or uncoiler to stand 1 (used "
                    "when boundary is span)."
                  : "Length L_N of the exit span, from the last stand to the coiler or exit "
                    "bridle (used when boundary is span).",
            [entry](const core::Mill& mill) {
                return entry ? mill.entry_span_length : mill.exit_span_length;
            },
            [entry](core::Mill& mill, double value) {
                (entry ? mill.entry_span_length : mill.exit_span_length) = value;
            }));
        fields.push_back(number(
            group + "/tension_MPa", megapascal, stress,
            entry ? "Entry tension set point (stand 1's back tension) as a stress. A span needs "
                    "a positive tension. Typically 10-60 MPa."
                  : "Exit tension set point (the last stand's front tension) as a stress. A span "
                    "needs a positive tension. Typically 30-70 MPa.",
            [entry](const core::Mill& mill) {
                return entry ? mill.entry_tension : mill.exit_tension;
            },
            [entry](core::Mill& mill, double value) {
                (entry ? mill.entry_tension : mill.exit_tension) = value;
            }));
    }
    // The name column, as the scenario fields' (every field has one; a test checks).
    const std::pair<std::string_view, std::string_view> names[] = {
        {"/entry_thickness_mm", "Mill entry thickness"},
        {"/exit_thickness_mm", "Exit thickness"},
        {"/speed_m_per_s", "Mill speed"},
        {"/mode", "Speed mode"},
        {"/strip/width_mm", "Strip width"},
        {"/strip/youngs_modulus_GPa", "Strip Young's modulus"},
        {"/strip/density_kg_per_m3", "Strip density"},
        {"/spans/length_m", "Span length"},
        {"/spans/tension_MPa", "Interstand tension"},
        {"/spans/model", "Span model"},
        {"/spans/segment_count", "Segments per span"},
        {"/entry/boundary", "Entry boundary"},
        {"/entry/span_length_m", "Entry span length"},
        {"/entry/tension_MPa", "Entry tension"},
        {"/exit/boundary", "Exit boundary"},
        {"/exit/span_length_m", "Exit span length"},
        {"/exit/tension_MPa", "Exit tension"},
    };
    set_column(fields, names, &TandemField::name, "a name");
    return fields;
}

constexpr std::array root_members{"entry_thickness_mm"sv,
                                  "exit_thickness_mm"sv,
                                  "speed_m_per_s"sv,
                                  "mode"sv,
                                  "strip"sv,
                                  "spans"sv,
                                  "entry"sv,
                                  "exit"sv,
                                  stand_defaults_member,
                                  stands_member};
constexpr std::array strip_members{"width_mm"sv, "youngs_modulus_GPa"sv, "density_kg_per_m3"sv};
constexpr std::array span_members{"length_m"sv, "tension_MPa"sv, "model"sv, "segment_count"sv};
constexpr std::array boundary_members{"boundary"sv, "span_length_m"sv, "tension_MPa"sv};

constexpr std::array owned{
    MillOwnedField{"/strip/entry_thickness_mm",
                   "/tandem/entry_thickness_mm and /tandem/exit_thickness_mm"},
    MillOwnedField{"/strip/reduction", "/tandem/exit_thickness_mm"},
    MillOwnedField{"/strip/width_mm", "/tandem/strip/width_mm"},
    MillOwnedField{"/strip/youngs_modulus_GPa", "/tandem/strip/youngs_modulus_GPa"},
    MillOwnedField{"/rolls/speed_m_per_s",
                   "/tandem/speed_m_per_s (the last stand; the others follow the mass flow)"},
    MillOwnedField{"/tension", "/tandem/spans, /tandem/entry and /tandem/exit"},
};

}  // namespace

const std::vector<TandemField>& tandem_fields() {
    static const std::vector<TandemField> fields = make_fields();
    return fields;
}

const TandemField* find_tandem_field(std::string_view path) {
    const auto& fields = tandem_fields();
    const auto found = std::find_if(fields.begin(), fields.end(), [path](const TandemField& field) {
        return field.path == path;
    });
    return found == fields.end() ? nullptr : &*found;
}

bool is_tandem_group(std::string_view path) {
    return path.empty() || path == "/strip" || path == "/spans" || path == "/entry" ||
           path == "/exit";
}

std::span<const std::string_view> tandem_group_members(std::string_view path) {
    if (path.empty()) return root_members;
    if (path == "/strip") return strip_members;
    if (path == "/spans") return span_members;
    if (path == "/entry" || path == "/exit") return boundary_members;
    return {};
}

std::span<const MillOwnedField> mill_owned_stand_fields() { return owned; }

std::string tandem_pointer_of_stand_field(std::string_view stand_path, int stand, int stand_count) {
    const auto index = [](int i) { return std::to_string(i); };
    if (stand_path == "/strip/entry_thickness_mm") {
        return stand == 0 ? "/entry_thickness_mm" : concat("/exit_thickness_mm/", index(stand - 1));
    }
    if (stand_path == "/strip/reduction") return concat("/exit_thickness_mm/", index(stand));
    if (stand_path == "/strip/width_mm") return "/strip/width_mm";
    if (stand_path == "/strip/youngs_modulus_GPa") return "/strip/youngs_modulus_GPa";
    if (stand_path == "/rolls/speed_m_per_s") return "/speed_m_per_s";
    if (stand_path.starts_with("/tension/back")) {
        return stand == 0 ? "/entry/tension_MPa" : concat("/spans/tension_MPa/", index(stand - 1));
    }
    if (stand_path.starts_with("/tension/front")) {
        return stand + 1 == stand_count ? "/exit/tension_MPa"
                                        : concat("/spans/tension_MPa/", index(stand));
    }
    if (stand_path.starts_with("/tension")) return "/spans/tension_MPa";
    return "";
}

}  // namespace rollgap::api
