#pragma once
// A rolling scenario in SI units (m, s, Pa, kg, N). The defaults are docs/model.md §8.

#include <array>

namespace rollgap::core {

enum class InletFilmModel { paper, eulerian };
enum class FrictionModel { mixed, coulomb };
enum class ContactModel { christensen_exact, paper_fit };
enum class TensionMode { constant, span, sinusoid };
// none: the paper's rigid rolls; hitchcock: the elastically flattened radius (docs/model.md,
// "Roll flattening").
enum class RollFlattening { none, hitchcock };

struct Strip {
    double entry_thickness = 1.6e-3;  // y1
    double reduction = 0.15;          // R, y2 = y1 (1 - R)
    double flow_stress = 380e6;       // sigma, plane-strain flow stress
    double width = 1.8;               // w
    double youngs_modulus = 210e9;    // E, for the tension spans
};

struct Rolls {
    double radius = 0.280;  // a
    double speed = 19.0;    // v, roll surface speed
    RollFlattening flattening = RollFlattening::none;
    double youngs_modulus = 210e9;  // E_r, for the flattening (steel work rolls)
    double poisson_ratio = 0.3;     // nu_r
};

struct Lubricant {
    double viscosity = 5.5e-4;           // eta0
    double pressure_viscosity = 1.7e-6;  // gamma, 1/Pa (1.7 MPa^-1 as printed)
    bool limiting_shear = true;          // [extension] |tau_f| <= lambda_L p
    double limiting_shear_coefficient = 0.05;
};

struct Roughness {
    double roll_rq = 1.2e-6;   // Rq1
    double strip_rq = 1.6e-6;  // Rq2
};

struct Friction {
    FrictionModel model = FrictionModel::mixed;
    ContactModel contact = ContactModel::christensen_exact;
    double asperity_factor = 1.0;      // m_a, tau_a = m_a sigma / 2
    double coulomb_coefficient = 0.1;  // mu of the verification law tau = mu p sgn(u - v)
};

struct TensionSide {
    TensionMode mode = TensionMode::constant;
    double stress = 0.0;       // mean tension stress
    double span_length = 5.0;  // L, for span mode
    double amplitude = 9e6;    // for sinusoid mode
    double frequency = 10.0;   // Hz, for sinusoid mode
};

struct Tensions {
    TensionSide back{TensionMode::span, 18e6, 5.0, 9e6, 10.0};
    TensionSide front{TensionMode::constant, 0.0, 5.0, 9e6, 10.0};
};

// Six masses, x upward: m1 upper crosshead, m2 upper backup roll, m3 upper work roll,
// m4 lower work roll, m5 lower backup roll, m6 lower crosshead (docs/model.md §5).
struct StandStructure {
    std::array<double, 6> mass{40e3, 60e3, 11e3, 11e3, 60e3, 40e3};
    // k1, k2, k3, k5, k6, k7; k4 (the strip) is derived from the roll-bite model.
    double k1 = 25e9, k2 = 30e9, k3 = 35e9, k5 = 35e9, k6 = 30e9, k7 = 25e9;
    double c1 = 2.0e6;     // hydraulic cylinder, m1-m2
    double c2 = 0.1e6;     // strip, m3-m4
    bool rayleigh = true;  // [extension]
    double rayleigh_damping_ratio = 0.04;
    double rayleigh_frequency_low = 100.0;   // Hz
    double rayleigh_frequency_high = 400.0;  // Hz
};

struct Numerics {
    int bite_intervals = 32;  // fixed RK4 steps on each side of the neutral point (force to ~1e-10)
    // The bite inside the dynamics (thousands of solves per analysis). 16 steps move the default
    // critical speed by 1e-8 relative against 64 and halve the cost.
    int dynamics_bite_intervals = 16;
};

struct Scenario {
    Strip strip;
    Rolls rolls;
    Lubricant lubricant;
    Roughness roughness;
    Friction friction;
    InletFilmModel inlet_film = InletFilmModel::paper;
    Tensions tensions;
    StandStructure structure;
    Numerics numerics;
};

inline double exit_thickness(const Scenario& s) {
    return s.strip.entry_thickness * (1.0 - s.strip.reduction);
}

}  // namespace rollgap::core
