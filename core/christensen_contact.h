#pragma once
// Christensen's roughness model, eqs. (19)-(26) of the paper with the typo of (25) corrected
// (docs/model.md §3). Z = h_sep / (3 Rq) is the separation of the mean planes in units of 3 Rq;
// H_t = h_t / Rq is the mean film thickness; A is the fraction of the area in asperity contact.

#include "core/scenario.h"

namespace rollgap::core {

// H_t(Z), eq. (23); for Z >= 1 no asperity touches and H_t = 3 Z; for Z <= -1, H_t = 0.
double christensen_film_ratio(double Z);

// A(Z) = (16 - 35Z + 35Z^3 - 21Z^5 + 5Z^7) / 32, eq. (25) corrected; 1 for Z <= -1, 0 for Z >= 1.
double christensen_contact_ratio_of_separation(double Z);

// The exact inverse of H_t(Z) on [0, 3]: the separation Z with christensen_film_ratio(Z) = H_t.
// Bracketed Newton; dH_t/dZ = 3 (1 - A) vanishes at Z = -1. Z = -1 for H_t <= 0, H_t / 3 above 3.
double christensen_separation(double film_ratio);

// A(H_t) from the exact inverse (the default contact model).
double christensen_contact_ratio(double film_ratio);

// The paper's polynomial fit, eq. (26), clamped to [0, 1]. Known defects (kept on purpose, this
// is the paper-faithful option): A = 1 for H_t < 0.5 where the exact A is 0.44-1; jumps at
// H_t = 0.5 (1 -> 0.449) and 1.5 (0.088 -> 0.074); the second branch is negative for
// 2.35 < H_t <= 3 and is clamped to 0 (the exact A is <= 0.004 there).
double paper_fit_contact_ratio(double film_ratio);

// The contact ratio under the selected model.
double contact_ratio(ContactModel model, double film_ratio);

// dA/dH_t under the selected model, for the bite sensitivities (docs/model.md §6.1). Exact
// inverse: dA/dH_t = A'(Z) / H_t'(Z) = -(35/32)(1 - Z^2)^3 / (3 (1 - A(Z))), 0 from H_t = 3 on.
// Paper fit: the derivative of the branch H_t falls in, 0 where it is constant or clamped (at a
// jump the branch the value takes).
struct ContactRatioAndSlope {
    double ratio, slope;  // A, dA/dH_t
};
ContactRatioAndSlope contact_ratio_and_slope(ContactModel model, double film_ratio);

}  // namespace rollgap::core
