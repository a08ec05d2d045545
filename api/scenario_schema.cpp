#include "api/scenario_schema.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <utility>

#include "api/field_column.h"
#include "api/json_pointer.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

// ---- builders: one line per field in the table below ---------------------------------------

template <class Access>
ScenarioField number_field(std::string path, Unit unit, Interval range, std::string description,
                           Access access) {
    ScenarioField field;
    field.path = std::move(path);
    field.description = std::move(description);
    field.kind = FieldKind::number;
    field.unit = unit;
    field.range = range;
    field.number = access;
    return field;
}

template <class Access>
ScenarioField integer_field(std::string path, Interval range, bool even, std::string description,
                            Access access) {
    ScenarioField field;
    field.path = std::move(path);
    field.description = std::move(description);
    field.kind = FieldKind::integer;
    field.range = range;
    field.even = even;
    field.integer = access;
    return field;
}

template <class Access>
ScenarioField boolean_field(std::string path, std::string description, Access access) {
    ScenarioField field;
    field.path = std::move(path);
    field.description = std::move(description);
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
ScenarioField choice_field(std::string path, const std::array<EnumName<Enum>, N>& names,
                           std::string description, Access access) {
    ScenarioField field;
    field.path = std::move(path);
    field.description = std::move(description);
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

// The strip tension on one side of the stand: back = entry side (between the previous stand or
// the uncoiler and this stand), front = exit side (toward the next stand or the coiler).
void add_tension_side(std::vector<ScenarioField>& fields, const std::string& side,
                      TensionSideAccess access) {
    const std::string group = concat("/tension/", side);
    const bool back = side == "back";
    const std::string where = back ? "entry" : "exit";
    const std::string symbol = back ? "s_b" : "s_f";
    const std::string neighbour =
        back ? "the previous stand or the uncoiler" : "the next stand or the coiler";
    fields.push_back(choice_field(
        group + "/mode", tension_modes,
        concat(
            "How the ", where, "-side (", side, ") strip tension ", symbol,
            " behaves: span = it follows the strip speed through an elastic strip span of length "
            "span_length_m, ds/dt = (E/L)·(speed difference)",
            back
                ? " (the default here: this loop is the paper's \"negative damping of the inlet tension\" "
                  "and what makes the stand chatter)"
                : "",
            "; constant = held at stress_MPa", back ? "" : " (the default here)",
            "; sinusoid = stress_MPa + amplitude_MPa·sin(2π·frequency_Hz·t), a prescribed ripple "
            "(the tension_cycle analysis always runs the back side this way)."),
        [access](core::Scenario & s) -> auto& { return access(s).mode; }));
    // Upper bounds beyond the field's own range (below the flow stress, mean ± amplitude) are
    // cross-field rules: scenario_consistency.cpp.
    fields.push_back(number_field(
        group + "/stress_MPa", units::megapascal, closed_open(0.0, 3000.0),
        concat(
            back ? "Back" : "Front", " tension ", symbol,
            ": the mean tensile stress in the strip on the ", where,
            " side, between this stand and ", neighbour,
            " (the coiler or stand pull divided by the strip's cross-section). Typically 5–30 % of the flow "
            "stress, e.g. 10–100 MPa; must stay below the flow stress."),
        [access](core::Scenario & s) -> auto& { return access(s).stress; }));
    fields.push_back(number_field(
        group + "/span_length_m", units::metre, closed(0.1, 1000.0),
        concat(
            "Length L of the free strip span between this stand and ", neighbour,
            ", used in span mode: the tension changes at E/L times the speed difference at its ends. "
            "Inter-stand distances of tandem mills are typically 4–6 m."),
        [access](core::Scenario & s) -> auto& { return access(s).span_length; }));
    fields.push_back(number_field(
        group + "/amplitude_MPa", units::megapascal, closed_open(0.0, 3000.0),
        concat(
            "Amplitude of the sinusoidal ", side, " tension ripple (sinusoid mode",
            back ? ", and tension_cycle" : "",
            "): the tension swings between stress_MPa - amplitude_MPa and stress_MPa + amplitude_MPa, and "
            "must stay above 0 MPa (a strip cannot push). The paper uses 9 MPa around 18 MPa."),
        [access](core::Scenario & s) -> auto& { return access(s).amplitude; }));
    fields.push_back(number_field(
        group + "/frequency_Hz", units::hertz, open_closed(0.0, 1e4),
        concat(
            "Frequency f of the sinusoidal ", side, " tension ripple (sinusoid mode",
            back ? ", and tension_cycle" : "",
            "), e.g. an eccentric roll or coil upstream. The paper uses 10 Hz, well below the stand's lowest "
            "mode (about 64 Hz at the defaults)."),
        [access](core::Scenario & s) -> auto& { return access(s).frequency; }));
}

// What each of the six masses is (eq. 37's order, x upward; docs/model.md §5).
constexpr std::array<const char*, 6> mass_parts{
    "upper crosshead / top of the housing, where the screw-down or hydraulic cylinder bears (typically 20–80 t)",
    "upper backup roll with its chocks (typically 30–100 t)",
    "upper work roll with its chocks (typically 5–20 t)",
    "lower work roll with its chocks (typically 5–20 t)",
    "lower backup roll with its chocks (typically 30–100 t)",
    "lower crosshead / bottom of the housing (typically 20–80 t)",
};

// The bounds are physical plausibility, wide enough for any cold mill and laboratory rig,
// narrow enough that a unit mistake (m for mm, Pa for MPa) lands outside them.
std::vector<ScenarioField> build_fields() {
    using namespace units;
    std::vector<ScenarioField> fields;

    fields.push_back(number_field(
        "/strip/entry_thickness_mm", millimetre, closed(0.05, 20.0),
        "Entry thickness y1: the strip's thickness as it enters the roll bite, before this pass. Cold-rolling "
        "passes typically 0.2–4 mm.",
        [](core::Scenario & s) -> auto& { return s.strip.entry_thickness; }));
    fields.push_back(number_field(
        "/strip/reduction", one, open_closed(0.0, 0.7),
        "Reduction R of this pass, a fraction: 0.25 = 25 %. The exit thickness is y2 = y1·(1 - R). Cold passes "
        "typically 0.1–0.4.",
        [](core::Scenario & s) -> auto& { return s.strip.reduction; }));
    fields.push_back(number_field(
        "/strip/flow_stress_MPa", megapascal, closed(10.0, 3000.0),
        "Plane-strain flow stress σ of the strip in the bite (twice the shear yield stress k; about 1.15 times "
        "the uniaxial yield stress). Low-carbon steel during cold rolling typically 300–700 MPa, aluminium "
        "100–300 MPa.",
        [](core::Scenario & s) -> auto& { return s.strip.flow_stress; }));
    fields.push_back(number_field(
        "/strip/width_mm", millimetre, closed(10.0, 5000.0),
        "Strip width w: the roll force and torque are the bite's stresses times this width (plane strain, no "
        "spread). Typically 600–2000 mm on a wide cold mill.",
        [](core::Scenario & s) -> auto& { return s.strip.width; }));
    fields.push_back(number_field(
        "/strip/youngs_modulus_GPa", gigapascal, closed(10.0, 500.0),
        "Young's modulus E of the strip: how stiff a strip span is, so how fast its tension changes with a speed "
        "difference (span tension mode). Steel about 210 GPa, aluminium about 70 GPa.",
        [](core::Scenario & s) -> auto& { return s.strip.youngs_modulus; }));

    fields.push_back(number_field(
        "/rolls/radius_mm", millimetre, closed(10.0, 2000.0),
        "Work-roll radius a (half the work-roll diameter) of the unloaded roll; with flattening none the bite "
        "uses it as is (rigid rolls). Cold-mill work rolls typically 150–350 mm.",
        [](core::Scenario & s) -> auto& { return s.rolls.radius; }));
    fields.push_back(number_field(
        "/rolls/speed_m_per_s", metre_per_second, closed(0.01, 100.0),
        "Rolling speed v: the surface speed of the work rolls. Cold tandem mills typically 5–30 m/s; the critical "
        "chatter speed is a value of this field.",
        [](core::Scenario & s) -> auto& { return s.rolls.speed; }));
    fields.push_back(choice_field(
        "/rolls/flattening", roll_flattenings,
        "How the work rolls deform under the roll force. none = rigid rolls, the paper's model. hitchcock = the "
        "rolls flatten elastically in the bite (Hitchcock's formula), which lengthens the contact and raises the "
        "force; worth switching on for hard, thin strip and heavy reductions (docs/model.md §10).",
        [](core::Scenario & s) -> auto& { return s.rolls.flattening; }));
    // Roll materials from cast iron to cemented carbide.
    fields.push_back(number_field(
        "/rolls/youngs_modulus_GPa", gigapascal, closed(50.0, 1000.0),
        "Young's modulus E_r of the work-roll material, used only with flattening hitchcock: the stiffer the "
        "roll, the less it flattens. Forged steel rolls about 210 GPa, cast iron 150–180 GPa, cemented "
        "carbide 500–650 GPa.",
        [](core::Scenario & s) -> auto& { return s.rolls.youngs_modulus; }));
    fields.push_back(number_field(
        "/rolls/poisson_ratio", one, closed(0.0, 0.49),
        "Poisson's ratio ν_r of the work-roll material (dimensionless), used only with flattening hitchcock. "
        "Steel rolls about 0.3, cemented carbide about 0.22.",
        [](core::Scenario & s) -> auto& { return s.rolls.poisson_ratio; }));

    fields.push_back(number_field(
        "/lubricant/viscosity_Pa_s", pascal_second, closed(1e-5, 10.0),
        "Viscosity η0 of the lubricant at atmospheric pressure and inlet temperature. Emulsions typically "
        "0.0005–0.002 Pa.s (0.5–2 mPa·s), neat rolling oils 0.01–0.05 Pa.s.",
        [](core::Scenario & s) -> auto& { return s.lubricant.viscosity; }));
    // gamma = 0 (isoviscous) is allowed: core takes the finite limit of the inlet film there.
    fields.push_back(number_field(
        "/lubricant/pressure_viscosity_per_MPa", per_megapascal, closed(0.0, 10.0),
        "Pressure-viscosity coefficient γ of Barus' law, viscosity = η0·exp(γ·p); 0 = a viscosity that does not "
        "change with pressure. Mineral oils typically 0.01–0.03 /MPa; the default is the paper's printed "
        "1.7 /MPa, which with the emulsion's η0 gives a realistic film (the product η0·γ sets it; "
        "docs/model.md §8).",
        [](core::Scenario & s) -> auto& { return s.lubricant.pressure_viscosity; }));
    fields.push_back(boolean_field(
        "/lubricant/limiting_shear",
        "Whether the lubricant's shear stress in the bite is capped at λ_L·p (a limiting shear stress, as real "
        "lubricants show). On: the model's default. Off: the paper's fluid as printed, viscosity η0 in the bite; "
        "the default stand then skids above about 21 m/s.",
        [](core::Scenario & s) -> auto& { return s.lubricant.limiting_shear; }));
    fields.push_back(number_field(
        "/lubricant/limiting_shear_coefficient", one, open_closed(0.0, 1.0),
        "Limiting shear coefficient λ_L (dimensionless): the lubricant carries at most λ_L times the local "
        "pressure in shear. Traction coefficients of rolling lubricants typically 0.03–0.08.",
        [](core::Scenario & s) -> auto& { return s.lubricant.limiting_shear_coefficient; }));

    fields.push_back(number_field(
        "/roughness/roll_rq_um", micrometre, closed(0.001, 50.0),
        "RMS roughness Rq1 of the work-roll surface. Ground cold-mill work rolls typically 0.2–1.5 um, "
        "textured (shot-blasted, EDT) rolls 1–5 um. The bite sees the composite Rq = sqrt(Rq1² + Rq2²).",
        [](core::Scenario & s) -> auto& { return s.roughness.roll_rq; }));
    fields.push_back(number_field(
        "/roughness/strip_rq_um", micrometre, closed(0.001, 50.0),
        "RMS roughness Rq2 of the incoming strip surface. Typically 0.3–3 um. The bite sees the composite "
        "Rq = sqrt(Rq1² + Rq2²); the paper's Figs. 14–15 compare Rq = 1 and 6 um.",
        [](core::Scenario & s) -> auto& { return s.roughness.strip_rq; }));

    fields.push_back(choice_field(
        "/friction/model", friction_models,
        "Friction law in the bite. mixed = the paper's mixed lubrication: asperity contacts (a share A of the "
        "area) shear at m_a·σ/2, the lubricant film carries the rest. coulomb = τ = μ·p, a textbook law used to "
        "check the slab solution against published numbers.",
        [](core::Scenario & s) -> auto& { return s.friction.model; }));
    fields.push_back(choice_field(
        "/friction/contact_model", contact_models,
        "How the asperity contact ratio A follows from the film-to-roughness ratio H_t (Christensen's model). "
        "christensen_exact = the exact relation, default; paper_fit = the paper's polynomial fit, eq. (26), "
        "which jumps at H_t = 0.5 and 1.5.",
        [](core::Scenario & s) -> auto& { return s.friction.contact; }));
    fields.push_back(number_field(
        "/friction/asperity_factor", one, open_closed(0.0, 1.0),
        "Asperity friction factor m_a (dimensionless): asperity contacts shear at m_a·σ/2, 1 = sticking "
        "(the paper's value), lower for a boundary film on the asperities (typically 0.1–1).",
        [](core::Scenario & s) -> auto& { return s.friction.asperity_factor; }));
    fields.push_back(number_field(
        "/friction/coulomb_coefficient", one, closed(0.0, 1.0),
        "Coulomb friction coefficient μ (dimensionless), used only by the coulomb friction model: τ = μ·p. "
        "Lubricated cold rolling typically 0.02–0.1.",
        [](core::Scenario & s) -> auto& { return s.friction.coulomb_coefficient; }));

    fields.push_back(choice_field(
        "/inlet_film/model", inlet_film_models,
        "How the lubricant film drawn into the bite responds to a moving roll gap. paper = the paper's eq. (11), "
        "default; eulerian = with the squeeze of a moving gap derived at a fixed point (docs/model.md §2), "
        "which makes a ~450 Hz mode unstable at every speed on the default stand.",
        [](core::Scenario & s) -> auto& { return s.inlet_film; }));

    add_tension_side(fields, "back",
                     [](core::Scenario& s) -> core::TensionSide& { return s.tensions.back; });
    add_tension_side(fields, "front",
                     [](core::Scenario& s) -> core::TensionSide& { return s.tensions.front; });

    for (std::size_t i = 0; i < 6; ++i) {
        const std::string name = concat("m", std::to_string(i + 1));
        fields.push_back(number_field(
            concat("/mill/masses_t/", name), tonne, closed(0.001, 1e4),
            concat("Mass ", name, " of the six-mass stand model: the ", mass_parts[i], "."),
            [i](core::Scenario & s) -> auto& { return s.structure.mass[i]; }));
    }
    // k4 is not an input: the strip's stiffness comes from the roll-bite model (docs/model.md §5).
    using StiffnessAccess = double& (*)(core::Scenario&);
    struct Stiffness {
        const char* name;
        const char* where;
        StiffnessAccess access;
    };
    const std::array<Stiffness, 6> stiffnesses{{
        {"k1",
         "between the upper crosshead m1 and the foundation (the housing columns and upper beam)",
         [](core::Scenario& s) -> double& { return s.structure.k1; }},
        {"k2",
         "between the upper crosshead m1 and the upper backup roll m2 (screw-down or hydraulic cylinder and "
         "backup chocks)",
         [](core::Scenario& s) -> double& { return s.structure.k2; }},
        {"k3",
         "between the upper backup roll m2 and the upper work roll m3 (the roll-to-roll contact and the "
         "roll bodies)",
         [](core::Scenario& s) -> double& { return s.structure.k3; }},
        {"k5",
         "between the lower work roll m4 and the lower backup roll m5 (the roll-to-roll contact and the "
         "roll bodies)",
         [](core::Scenario& s) -> double& { return s.structure.k5; }},
        {"k6",
         "between the lower backup roll m5 and the lower crosshead m6 (backup chocks and their supports)",
         [](core::Scenario& s) -> double& { return s.structure.k6; }},
        {"k7",
         "between the lower crosshead m6 and the foundation (the bending of the housing's lower beam)",
         [](core::Scenario& s) -> double& { return s.structure.k7; }},
    }};
    for (const Stiffness& stiffness : stiffnesses) {
        fields.push_back(number_field(
            concat("/mill/stiffness_GN_per_m/", stiffness.name), giganewton_per_metre,
            closed(1e-3, 1e4),
            concat(
                "Spring ", stiffness.name, " ", stiffness.where,
                ". Stand components typically 10–50 GN/m. There is no k4: the spring between the work rolls is "
                "the strip in the bite, computed from the roll-bite model (docs/model.md §5)."),
            stiffness.access));
    }
    fields.push_back(number_field(
        "/mill/damping_MN_s_per_m/c1", meganewton_second_per_metre, closed(0.0, 1e4),
        "Damper c1 between the upper crosshead m1 and the upper backup roll m2: the hydraulic roll-gap cylinder. "
        "Typically 0.5–5 MN.s/m.",
        [](core::Scenario & s) -> auto& { return s.structure.c1; }));
    fields.push_back(number_field(
        "/mill/damping_MN_s_per_m/c2", meganewton_second_per_metre, closed(0.0, 1e4),
        "Damper c2 between the two work rolls m3 and m4: the damping of the strip in the bite. Typically "
        "0.01–0.5 MN.s/m.",
        [](core::Scenario & s) -> auto& { return s.structure.c2; }));
    fields.push_back(boolean_field(
        "/mill/rayleigh/enabled",
        "Whether the stand has Rayleigh (proportional) structural damping, α·M + β·K_s, on top of c1 and c2. "
        "On by default: with c1 and c2 alone, as in the paper, some modes of the stand are almost undamped.",
        [](core::Scenario & s) -> auto& { return s.structure.rayleigh; }));
    fields.push_back(number_field(
        "/mill/rayleigh/damping_ratio", one, closed_open(0.0, 0.5),
        "Damping ratio ζ (dimensionless, a fraction of critical damping: 0.04 = 4 %) that the Rayleigh damping "
        "gives at low_frequency_Hz and at high_frequency_Hz. Welded and bolted steel structures typically "
        "0.01–0.05. The critical speed depends strongly on it.",
        [](core::Scenario & s) -> auto& { return s.structure.rayleigh_damping_ratio; }));
    // low < high is a cross-field rule: scenario_consistency.cpp.
    fields.push_back(number_field(
        "/mill/rayleigh/low_frequency_Hz", hertz, open_closed(0.0, 1e5),
        "Lower frequency at which the Rayleigh damping ratio is exactly ζ; below it the damping rises. Choose it "
        "near the stand's lowest mode with roll-gap motion (about 100 Hz on the default stand).",
        [](core::Scenario & s) -> auto& { return s.structure.rayleigh_frequency_low; }));
    fields.push_back(number_field(
        "/mill/rayleigh/high_frequency_Hz", hertz, open_closed(0.0, 1e5),
        "Upper frequency at which the Rayleigh damping ratio is exactly ζ (between the two it is a little lower, "
        "above it rises); above low_frequency_Hz. Typically the highest mode of interest, e.g. 400 Hz.",
        [](core::Scenario & s) -> auto& { return s.structure.rayleigh_frequency_high; }));

    // Even: the bite is integrated in steps on each side of the neutral point.
    fields.push_back(integer_field(
        "/numerics/bite_intervals", closed(8.0, 4096.0), true,
        "Numerical resolution of the reported roll gap: integration steps on each side of the neutral point "
        "(even). 32 gives the force to about 1e-10 relative; raise it only for smoother distribution plots.",
        [](core::Scenario & s) -> auto& { return s.numerics.bite_intervals; }));

    // The typical column: where a cold mill's values lie (the descriptions' "typically"), kept
    // wide enough that only a unit slip or a typing error falls outside (warnings, not errors).
    const std::pair<std::string_view, Interval> typical[] = {
        {"/strip/entry_thickness_mm", closed(0.1, 8.0)},
        {"/strip/width_mm", closed(300.0, 2500.0)},
        {"/rolls/radius_mm", closed(100.0, 400.0)},
        {"/rolls/speed_m_per_s", closed(0.5, 45.0)},
        {"/lubricant/viscosity_Pa_s", closed(0.0001, 0.2)},
        {"/mill/masses_t/m1", closed(1.0, 300.0)},
        {"/mill/masses_t/m2", closed(1.0, 300.0)},
        {"/mill/masses_t/m3", closed(0.5, 100.0)},
        {"/mill/masses_t/m4", closed(0.5, 100.0)},
        {"/mill/masses_t/m5", closed(1.0, 300.0)},
        {"/mill/masses_t/m6", closed(1.0, 300.0)},
        // "5–30 % of the flow stress", a few hundred MPa at most on hard strip (0: none, a free
        // end); a force in kN sent as a stress lands far above (the likely unit names force_kN).
        {"/tension/back/stress_MPa", closed(0.0, 400.0)},
        {"/tension/front/stress_MPa", closed(0.0, 400.0)},
    };
    set_column(fields, typical, &ScenarioField::typical, "a typical range");
    // The name column: what a label or an axis calls each field (every field has one; a test
    // checks).
    const std::pair<std::string_view, std::string_view> names[] = {
        {"/strip/entry_thickness_mm", "Entry thickness"},
        {"/strip/reduction", "Reduction"},
        {"/strip/flow_stress_MPa", "Flow stress"},
        {"/strip/width_mm", "Strip width"},
        {"/strip/youngs_modulus_GPa", "Strip Young's modulus"},
        {"/rolls/radius_mm", "Work-roll radius"},
        {"/rolls/speed_m_per_s", "Roll speed"},
        {"/rolls/flattening", "Roll flattening"},
        {"/rolls/youngs_modulus_GPa", "Roll Young's modulus"},
        {"/rolls/poisson_ratio", "Roll Poisson's ratio"},
        {"/lubricant/viscosity_Pa_s", "Lubricant viscosity"},
        {"/lubricant/pressure_viscosity_per_MPa", "Pressure-viscosity coefficient"},
        {"/lubricant/limiting_shear", "Limiting shear stress"},
        {"/lubricant/limiting_shear_coefficient", "Limiting shear coefficient"},
        {"/roughness/roll_rq_um", "Roll roughness Rq"},
        {"/roughness/strip_rq_um", "Strip roughness Rq"},
        {"/friction/model", "Friction model"},
        {"/friction/contact_model", "Contact model"},
        {"/friction/asperity_factor", "Asperity friction factor"},
        {"/friction/coulomb_coefficient", "Coulomb friction coefficient"},
        {"/inlet_film/model", "Inlet film model"},
        {"/tension/back/mode", "Back tension mode"},
        {"/tension/back/stress_MPa", "Back tension"},
        {"/tension/back/span_length_m", "Entry span length"},
        {"/tension/back/amplitude_MPa", "Back tension ripple amplitude"},
        {"/tension/back/frequency_Hz", "Back tension ripple frequency"},
        {"/tension/front/mode", "Front tension mode"},
        {"/tension/front/stress_MPa", "Front tension"},
        {"/tension/front/span_length_m", "Exit span length"},
        {"/tension/front/amplitude_MPa", "Front tension ripple amplitude"},
        {"/tension/front/frequency_Hz", "Front tension ripple frequency"},
        {"/mill/masses_t/m1", "Upper crosshead mass"},
        {"/mill/masses_t/m2", "Upper backup roll mass"},
        {"/mill/masses_t/m3", "Upper work roll mass"},
        {"/mill/masses_t/m4", "Lower work roll mass"},
        {"/mill/masses_t/m5", "Lower backup roll mass"},
        {"/mill/masses_t/m6", "Lower crosshead mass"},
        {"/mill/stiffness_GN_per_m/k1", "Stiffness k1"},
        {"/mill/stiffness_GN_per_m/k2", "Stiffness k2"},
        {"/mill/stiffness_GN_per_m/k3", "Stiffness k3"},
        {"/mill/stiffness_GN_per_m/k5", "Stiffness k5"},
        {"/mill/stiffness_GN_per_m/k6", "Stiffness k6"},
        {"/mill/stiffness_GN_per_m/k7", "Stiffness k7"},
        {"/mill/damping_MN_s_per_m/c1", "Damping c1"},
        {"/mill/damping_MN_s_per_m/c2", "Damping c2"},
        {"/mill/rayleigh/enabled", "Rayleigh damping"},
        {"/mill/rayleigh/damping_ratio", "Rayleigh damping ratio"},
        {"/mill/rayleigh/low_frequency_Hz", "Rayleigh lower frequency"},
        {"/mill/rayleigh/high_frequency_Hz", "Rayleigh upper frequency"},
        {"/numerics/bite_intervals", "Bite integration steps"},
    };
    set_column(fields, names, &ScenarioField::name, "a name");
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
            const std::string_view member = path.substr(
                segment_start, segment_end == std::string_view::npos ? std::string_view::npos
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
    const auto found =
        std::find_if(fields.begin(), fields.end(),
                     [path](const ScenarioField& field) { return field.path == path; });
    return found == fields.end() ? nullptr : &*found;
}

bool is_scenario_group(std::string_view path) { return groups().find(path) != groups().end(); }

std::span<const std::string_view> scenario_group_members(std::string_view path) {
    const auto found = groups().find(path);
    if (found == groups().end()) return {};
    return found->second;
}

FieldLens FieldLens::member(std::string_view name) const {
    return FieldLens(append_pointer(prefix_, name));
}

FieldLens FieldLens::element(std::size_t index) const {
    return FieldLens(append_pointer(prefix_, std::to_string(index)));
}

std::string FieldLens::pointer(std::string_view schema_path) const {
    std::string out = prefix_;
    out += schema_path;
    return out;
}

std::optional<std::string_view> FieldLens::schema_path(std::string_view full_pointer) const {
    if (!full_pointer.starts_with(prefix_)) return std::nullopt;
    const std::string_view rest = full_pointer.substr(prefix_.size());
    // the prefix must end at a token boundary: "/stands/30" is not under "/stands/3"
    if (!rest.empty() && rest.front() != '/') return std::nullopt;
    return rest;
}

const ScenarioField* FieldLens::find_field(std::string_view full_pointer) const {
    const auto path = schema_path(full_pointer);
    return path ? find_scenario_field(*path) : nullptr;
}

bool FieldLens::is_group(std::string_view full_pointer) const {
    const auto path = schema_path(full_pointer);
    return path && is_scenario_group(*path);
}

std::span<const std::string_view> FieldLens::group_members(std::string_view full_pointer) const {
    const auto path = schema_path(full_pointer);
    return path ? scenario_group_members(*path) : std::span<const std::string_view>{};
}

std::vector<std::string> FieldLens::field_pointers() const {
    std::vector<std::string> out;
    for (const ScenarioField& field : scenario_fields()) out.push_back(pointer(field.path));
    return out;
}

}  // namespace rollgap::api
