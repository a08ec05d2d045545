#include "api/scenario_schema.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <utility>

#include "api/text.h"

namespace rollgap::api {
namespace {

// ---- builders: one line per field in the table below ---------------------------------------

template <class Access>
ScenarioField number_field(std::string path, Unit unit, Interval range, Access access) {
    ScenarioField field;
    field.path = std::move(path);
    field.kind = FieldKind::number;
    field.unit = unit;
    field.range = range;
    field.number = access;
    return field;
}

template <class Access>
ScenarioField integer_field(std::string path, Interval range, bool even, Access access) {
    ScenarioField field;
    field.path = std::move(path);
    field.kind = FieldKind::integer;
    field.range = range;
    field.even = even;
    field.integer = access;
    return field;
}

template <class Access>
ScenarioField boolean_field(std::string path, Access access) {
    ScenarioField field;
    field.path = std::move(path);
    field.kind = FieldKind::boolean;
    field.flag = access;
    return field;
}

template <class Enum>
struct EnumName {
    std::string_view name;
    Enum value;
};

template <class Enum, std::size_t N, class Access>
ScenarioField choice_field(std::string path, const std::array<EnumName<Enum>, N>& names, Access access) {
    ScenarioField field;
    field.path = std::move(path);
    field.kind = FieldKind::choice;
    for (const auto& entry : names) field.choices.push_back(entry.name);
    field.read_choice = [names, access](const core::Scenario& scenario) -> std::string_view {
        core::Scenario& readable = const_cast<core::Scenario&>(scenario);  // access only reads here
        for (const auto& entry : names) {
            if (entry.value == access(readable)) return entry.name;
        }
        throw std::logic_error("enum value without a name in the scenario schema");
    };
    field.write_choice = [names, access](core::Scenario& scenario, std::string_view name) {
        for (const auto& entry : names) {
            if (entry.name == name) {
                access(scenario) = entry.value;
                return;
            }
        }
        throw std::logic_error("write_choice called with a name that is not a choice");
    };
    return field;
}

constexpr std::array<EnumName<core::FrictionModel>, 2> friction_models{{
    {"mixed", core::FrictionModel::mixed},
    {"coulomb", core::FrictionModel::coulomb},
}};
constexpr std::array<EnumName<core::ContactModel>, 2> contact_models{{
    {"christensen_exact", core::ContactModel::christensen_exact},
    {"paper_fit", core::ContactModel::paper_fit},
}};
constexpr std::array<EnumName<core::InletFilmModel>, 2> inlet_film_models{{
    {"paper", core::InletFilmModel::paper},
    {"eulerian", core::InletFilmModel::eulerian},
}};
constexpr std::array<EnumName<core::RollFlattening>, 2> roll_flattenings{{
    {"none", core::RollFlattening::none},
    {"hitchcock", core::RollFlattening::hitchcock},
}};
constexpr std::array<EnumName<core::TensionMode>, 3> tension_modes{{
    {"span", core::TensionMode::span},
    {"constant", core::TensionMode::constant},
    {"sinusoid", core::TensionMode::sinusoid},
}};

using TensionSideAccess = core::TensionSide& (*)(core::Scenario&);

void add_tension_side(std::vector<ScenarioField>& fields, const std::string& side, TensionSideAccess access) {
    const std::string group = concat("/tension/", side);
    fields.push_back(choice_field(group + "/mode", tension_modes,
                                  [access](core::Scenario& s) -> auto& { return access(s).mode; }));
    // Upper bounds beyond the field's own range (below the flow stress, mean ± amplitude) are
    // cross-field rules: scenario_consistency.cpp.
    fields.push_back(number_field(group + "/stress_MPa", units::megapascal, closed_open(0.0, 3000.0),
                                  [access](core::Scenario& s) -> auto& { return access(s).stress; }));
    fields.push_back(number_field(group + "/span_length_m", units::metre, closed(0.1, 1000.0),
                                  [access](core::Scenario& s) -> auto& { return access(s).span_length; }));
    fields.push_back(number_field(group + "/amplitude_MPa", units::megapascal, closed_open(0.0, 3000.0),
                                  [access](core::Scenario& s) -> auto& { return access(s).amplitude; }));
    fields.push_back(number_field(group + "/frequency_Hz", units::hertz, open_closed(0.0, 1e4),
                                  [access](core::Scenario& s) -> auto& { return access(s).frequency; }));
}

// The bounds are physical plausibility, wide enough for any cold mill and laboratory rig,
// narrow enough that a unit mistake (m for mm, Pa for MPa) lands outside them.
std::vector<ScenarioField> build_fields() {
    using namespace units;
    std::vector<ScenarioField> fields;

    fields.push_back(number_field("/strip/entry_thickness_mm", millimetre, closed(0.05, 20.0),
                                  [](core::Scenario& s) -> auto& { return s.strip.entry_thickness; }));
    fields.push_back(number_field("/strip/reduction", one, open_closed(0.0, 0.7),
                                  [](core::Scenario& s) -> auto& { return s.strip.reduction; }));
    fields.push_back(number_field("/strip/flow_stress_MPa", megapascal, closed(10.0, 3000.0),
                                  [](core::Scenario& s) -> auto& { return s.strip.flow_stress; }));
    fields.push_back(number_field("/strip/width_mm", millimetre, closed(10.0, 5000.0),
                                  [](core::Scenario& s) -> auto& { return s.strip.width; }));
    fields.push_back(number_field("/strip/youngs_modulus_GPa", gigapascal, closed(10.0, 500.0),
                                  [](core::Scenario& s) -> auto& { return s.strip.youngs_modulus; }));

    fields.push_back(number_field("/rolls/radius_mm", millimetre, closed(10.0, 2000.0),
                                  [](core::Scenario& s) -> auto& { return s.rolls.radius; }));
    fields.push_back(number_field("/rolls/speed_m_per_s", metre_per_second, closed(0.01, 100.0),
                                  [](core::Scenario& s) -> auto& { return s.rolls.speed; }));
    fields.push_back(choice_field("/rolls/flattening", roll_flattenings,
                                  [](core::Scenario& s) -> auto& { return s.rolls.flattening; }));
    // Roll materials from cast iron to cemented carbide.
    fields.push_back(number_field("/rolls/youngs_modulus_GPa", gigapascal, closed(50.0, 1000.0),
                                  [](core::Scenario& s) -> auto& { return s.rolls.youngs_modulus; }));
    fields.push_back(number_field("/rolls/poisson_ratio", one, closed(0.0, 0.49),
                                  [](core::Scenario& s) -> auto& { return s.rolls.poisson_ratio; }));

    fields.push_back(number_field("/lubricant/viscosity_Pa_s", pascal_second, closed(1e-5, 10.0),
                                  [](core::Scenario& s) -> auto& { return s.lubricant.viscosity; }));
    // gamma = 0 (isoviscous) is allowed: core takes the finite limit of the inlet film there.
    fields.push_back(number_field("/lubricant/pressure_viscosity_per_MPa", per_megapascal, closed(0.0, 10.0),
                                  [](core::Scenario& s) -> auto& { return s.lubricant.pressure_viscosity; }));
    fields.push_back(boolean_field("/lubricant/limiting_shear",
                                   [](core::Scenario& s) -> auto& { return s.lubricant.limiting_shear; }));
    fields.push_back(number_field("/lubricant/limiting_shear_coefficient", one, open_closed(0.0, 1.0),
                                  [](core::Scenario& s) -> auto& { return s.lubricant.limiting_shear_coefficient; }));

    fields.push_back(number_field("/roughness/roll_rq_um", micrometre, closed(0.001, 50.0),
                                  [](core::Scenario& s) -> auto& { return s.roughness.roll_rq; }));
    fields.push_back(number_field("/roughness/strip_rq_um", micrometre, closed(0.001, 50.0),
                                  [](core::Scenario& s) -> auto& { return s.roughness.strip_rq; }));

    fields.push_back(choice_field("/friction/model", friction_models,
                                  [](core::Scenario& s) -> auto& { return s.friction.model; }));
    fields.push_back(choice_field("/friction/contact_model", contact_models,
                                  [](core::Scenario& s) -> auto& { return s.friction.contact; }));
    fields.push_back(number_field("/friction/asperity_factor", one, open_closed(0.0, 1.0),
                                  [](core::Scenario& s) -> auto& { return s.friction.asperity_factor; }));
    fields.push_back(number_field("/friction/coulomb_coefficient", one, closed(0.0, 1.0),
                                  [](core::Scenario& s) -> auto& { return s.friction.coulomb_coefficient; }));

    fields.push_back(choice_field("/inlet_film/model", inlet_film_models,
                                  [](core::Scenario& s) -> auto& { return s.inlet_film; }));

    add_tension_side(fields, "back", [](core::Scenario& s) -> core::TensionSide& { return s.tensions.back; });
    add_tension_side(fields, "front", [](core::Scenario& s) -> core::TensionSide& { return s.tensions.front; });

    for (std::size_t i = 0; i < 6; ++i) {
        fields.push_back(number_field(concat("/mill/masses_t/m", std::to_string(i + 1)), tonne, closed(0.001, 1e4),
                                      [i](core::Scenario& s) -> auto& { return s.mill.mass[i]; }));
    }
    // k4 is not an input: the strip's stiffness comes from the roll-bite model (MODEL.md §5).
    using StiffnessAccess = double& (*)(core::Scenario&);
    const std::array<std::pair<const char*, StiffnessAccess>, 6> stiffnesses{{
        {"k1", [](core::Scenario& s) -> double& { return s.mill.k1; }},
        {"k2", [](core::Scenario& s) -> double& { return s.mill.k2; }},
        {"k3", [](core::Scenario& s) -> double& { return s.mill.k3; }},
        {"k5", [](core::Scenario& s) -> double& { return s.mill.k5; }},
        {"k6", [](core::Scenario& s) -> double& { return s.mill.k6; }},
        {"k7", [](core::Scenario& s) -> double& { return s.mill.k7; }},
    }};
    for (const auto& [name, access] : stiffnesses) {
        fields.push_back(number_field(concat("/mill/stiffness_GN_per_m/", name),
                                      giganewton_per_metre, closed(1e-3, 1e4), access));
    }
    fields.push_back(number_field("/mill/damping_MN_s_per_m/c1", meganewton_second_per_metre, closed(0.0, 1e4),
                                  [](core::Scenario& s) -> auto& { return s.mill.c1; }));
    fields.push_back(number_field("/mill/damping_MN_s_per_m/c2", meganewton_second_per_metre, closed(0.0, 1e4),
                                  [](core::Scenario& s) -> auto& { return s.mill.c2; }));
    fields.push_back(boolean_field("/mill/rayleigh/enabled",
                                   [](core::Scenario& s) -> auto& { return s.mill.rayleigh; }));
    fields.push_back(number_field("/mill/rayleigh/damping_ratio", one, closed_open(0.0, 0.5),
                                  [](core::Scenario& s) -> auto& { return s.mill.rayleigh_damping_ratio; }));
    // low < high is a cross-field rule: scenario_consistency.cpp.
    fields.push_back(number_field("/mill/rayleigh/low_frequency_Hz", hertz, open_closed(0.0, 1e5),
                                  [](core::Scenario& s) -> auto& { return s.mill.rayleigh_frequency_low; }));
    fields.push_back(number_field("/mill/rayleigh/high_frequency_Hz", hertz, open_closed(0.0, 1e5),
                                  [](core::Scenario& s) -> auto& { return s.mill.rayleigh_frequency_high; }));

    // Even: the bite is integrated in steps on each side of the neutral point.
    fields.push_back(integer_field("/numerics/bite_intervals", closed(8.0, 4096.0), true,
                                   [](core::Scenario& s) -> auto& { return s.numerics.bite_intervals; }));
    return fields;
}

using GroupMembers = std::map<std::string, std::vector<std::string_view>, std::less<>>;

// Every prefix of every field path is a group; its members are the next path segments.
GroupMembers build_groups(const std::vector<ScenarioField>& fields) {
    GroupMembers groups;
    for (const ScenarioField& field : fields) {
        const std::string_view path = field.path;
        std::size_t segment_start = 1;  // after the leading '/'
        while (true) {
            const std::size_t segment_end = path.find('/', segment_start);
            const std::string_view group = path.substr(0, segment_start - 1);
            const std::string_view member =
                path.substr(segment_start, segment_end == std::string_view::npos
                                               ? std::string_view::npos
                                               : segment_end - segment_start);
            auto& members = groups[std::string(group)];
            if (std::find(members.begin(), members.end(), member) == members.end()) {
                members.push_back(member);
            }
            if (segment_end == std::string_view::npos) break;
            segment_start = segment_end + 1;
        }
    }
    return groups;
}

const GroupMembers& groups() {
    static const GroupMembers members = build_groups(scenario_fields());
    return members;
}

}  // namespace

const std::vector<ScenarioField>& scenario_fields() {
    static const std::vector<ScenarioField> fields = build_fields();
    return fields;
}

const ScenarioField* find_scenario_field(std::string_view path) {
    const auto& fields = scenario_fields();
    const auto found = std::find_if(fields.begin(), fields.end(),
                                    [path](const ScenarioField& field) { return field.path == path; });
    return found == fields.end() ? nullptr : &*found;
}

bool is_scenario_group(std::string_view path) { return groups().find(path) != groups().end(); }

std::span<const std::string_view> scenario_group_members(std::string_view path) {
    const auto found = groups().find(path);
    if (found == groups().end()) return {};
    return found->second;
}

}  // namespace rollgap::api
