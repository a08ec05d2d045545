#pragma once
// The scenarios the dynamics tests share (test_coupled_model.cpp, test_bite_jacobian.cpp): the
// film models and tension boundaries the suite checks, each with a name for CAPTURE. `more`
// adds operating points away from the defaults: another reduction, speed and tension, Rayleigh
// damping off, the flattened rolls, Coulomb friction.

#include <string>
#include <vector>

#include "core/scenario.h"

namespace rollgap::test {

struct NamedScenario {
    std::string name;
    core::Scenario s;
};

inline std::vector<NamedScenario> dynamics_scenarios(bool more = false) {
    using namespace rollgap::core;
    std::vector<NamedScenario> out;
    out.push_back({"defaults (paper film, back span)", Scenario{}});
    Scenario e;
    e.inlet_film = InletFilmModel::eulerian;
    out.push_back({"eulerian film", e});
    Scenario c;
    c.tensions.back.mode = TensionMode::constant;
    out.push_back({"constant back tension", c});
    Scenario f;
    f.tensions.front.mode = TensionMode::span;
    f.tensions.front.stress = 5e6;
    out.push_back({"back and front spans", f});
    if (!more) return out;
    Scenario r;
    r.strip.reduction = 0.25;
    r.rolls.speed = 30.0;
    r.tensions.back.stress = 40e6;
    out.push_back({"25 % reduction, 30 m/s, 40 MPa back tension", r});
    Scenario n;
    n.structure.rayleigh = false;
    n.rolls.speed = 8.0;
    out.push_back({"no Rayleigh damping, 8 m/s", n});
    Scenario h;
    h.rolls.flattening = RollFlattening::hitchcock;
    out.push_back({"hitchcock flattening", h});
    Scenario k;
    k.friction.model = FrictionModel::coulomb;
    out.push_back({"coulomb friction", k});
    return out;
}

}  // namespace rollgap::test
