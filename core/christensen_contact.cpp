#include "core/christensen_contact.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rollgap::core {

// Both polynomials are evaluated in factored form: H_t has a five-fold root at Z = -1 and
// 1 - A a four-fold one, so the expanded forms of (23) and (25) lose every digit near Z = -1
// (terms of ~0.4 cancel to ~1e-12). Expanding the factored forms gives (23) and (25) exactly.
//   H_t = 3 (1 + Z)^5 (35 - 47Z + 25Z^2 - 5Z^3) / 256
//   A   = (1 - Z)^4 (16 + 29Z + 20Z^2 + 5Z^3) / 32,   1 - A = A(-Z).
double christensen_film_ratio(double Z) {
    if (Z <= -1.0) return 0.0;
    if (Z >= 1.0) return 3.0 * Z;
    const double s = 1.0 + Z, s2 = s * s;
    return 3.0 * s2 * s2 * s * (35.0 + Z * (-47.0 + Z * (25.0 - 5.0 * Z))) / 256.0;
}

double christensen_contact_ratio_of_separation(double Z) {
    if (Z <= -1.0) return 1.0;
    if (Z >= 1.0) return 0.0;
    const double s = 1.0 - Z, s2 = s * s;
    return s2 * s2 * (16.0 + Z * (29.0 + Z * (20.0 + 5.0 * Z))) / 32.0;
}

namespace {

double bisect_separation(double film_ratio) {
    double lo = -1.0, hi = 1.0;
    for (int k = 0; k < 200 && hi - lo > 1e-16; ++k) {
        const double mid = 0.5 * (lo + hi);
        (christensen_film_ratio(mid) < film_ratio ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double one_minus_contact(double Z) { return christensen_contact_ratio_of_separation(-Z); }

// Starting points for Newton. For u = H_t / 3 >= 1/64 (A <= 0.9) Z(u) is smooth, with
// dZ/du = 1 / (1 - A): a cubic Hermite table starts Newton within ~1e-12, and one step makes it
// exact. Below, Z(u) ~ -1 + c u^(1/5) (1 - A ~ (1 + Z)^4): there the table is uniform in
// t = u^(1/5), where Z is smooth too, and Newton runs to convergence (the boundary regime).
constexpr double smooth_start = 1.0 / 64.0;
constexpr int smooth_cells = 1024;
constexpr int root_cells = 256;

struct InverseTables {
    std::array<double, smooth_cells + 1> Z{}, slope{};
    std::array<double, root_cells + 1> Z_root{};
    InverseTables() {
        for (int i = 0; i <= smooth_cells; ++i) {
            const double u = smooth_start + (1.0 - smooth_start) * i / smooth_cells;
            Z[i] = bisect_separation(3.0 * u);
            slope[i] = 1.0 / one_minus_contact(Z[i]);
        }
        for (int i = 0; i <= root_cells; ++i) {
            const double t = std::pow(smooth_start, 0.2) * i / root_cells;
            Z_root[i] = bisect_separation(3.0 * std::pow(t, 5.0));
        }
    }
};

const InverseTables& inverse_tables() {
    static const InverseTables tables;
    return tables;
}

double newton_step(double Z, double film_ratio) {
    return Z - (christensen_film_ratio(Z) - film_ratio) / (3.0 * one_minus_contact(Z));
}

double boundary_separation(double film_ratio, const InverseTables& tables) {
    const double t = std::pow(film_ratio / 3.0, 0.2) / std::pow(smooth_start, 0.2) * root_cells;
    const int i = std::min(static_cast<int>(t), root_cells - 1);
    double Z = tables.Z_root[i] + (t - i) * (tables.Z_root[i + 1] - tables.Z_root[i]);
    // Newton kept inside a shrinking bracket; bisect whenever a step would leave it.
    double lo = -1.0, hi = 1.0;
    for (int k = 0; k < 100; ++k) {
        const double residual = christensen_film_ratio(Z) - film_ratio;
        if (residual == 0.0) break;
        (residual < 0.0 ? lo : hi) = Z;
        const double slope = 3.0 * one_minus_contact(Z);
        double next = slope > 0.0 ? Z - residual / slope : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        const double step = std::abs(next - Z);
        Z = next;
        if (step <= 1e-15 || hi - lo <= 4e-16) break;
    }
    return Z;
}

}  // namespace

double christensen_separation(double film_ratio) {
    if (!(film_ratio > 0.0)) return -1.0;
    if (film_ratio >= 3.0) return film_ratio / 3.0;
    const auto& tables = inverse_tables();
    const double u = film_ratio / 3.0;
    if (u < smooth_start) return boundary_separation(film_ratio, tables);

    const double width = (1.0 - smooth_start) / smooth_cells;
    const double cell = (u - smooth_start) / width;
    const int i = std::min(static_cast<int>(cell), smooth_cells - 1);
    const double f = cell - i, f2 = f * f, f3 = f2 * f;
    const double Z = (2 * f3 - 3 * f2 + 1) * tables.Z[i] +
                     (f3 - 2 * f2 + f) * width * tables.slope[i] +
                     (-2 * f3 + 3 * f2) * tables.Z[i + 1] + (f3 - f2) * width * tables.slope[i + 1];
    return newton_step(Z, film_ratio);
}

double christensen_contact_ratio(double film_ratio) {
    if (film_ratio >= 3.0) return 0.0;
    return christensen_contact_ratio_of_separation(christensen_separation(film_ratio));
}

double paper_fit_contact_ratio(double H) {
    double A;
    if (H < 0.5) {
        A = 1.0;
    } else if (H <= 1.5) {
        A = 1.0 + H * (-2.4398 +
                       H * (6.2049 + H * (-11.8410 + H * (12.5350 + H * (-6.6134 + H * 1.3618)))));
    } else if (H <= 3.0) {
        A = 0.8855 + H * (-1.1982 +
                          H * (0.7614 + H * (-0.3394 + H * (0.1116 + H * (-0.0220 + H * 0.0018)))));
    } else {
        A = 0.0;
    }
    return std::clamp(A, 0.0, 1.0);
}

double contact_ratio(ContactModel model, double film_ratio) {
    switch (model) {
        case ContactModel::paper_fit: return paper_fit_contact_ratio(film_ratio);
        case ContactModel::christensen_exact: break;
    }
    return christensen_contact_ratio(film_ratio);
}

ContactRatioAndSlope contact_ratio_and_slope(ContactModel model, double H) {
    if (model == ContactModel::paper_fit) {
        const double A = paper_fit_contact_ratio(H);
        if (H < 0.5 || H > 3.0 || A <= 0.0 || A >= 1.0) return {A, 0.0};
        const double slope =
            H <= 1.5 ? -2.4398 + H * (2 * 6.2049 +
                                      H * (3 * -11.8410 +
                                           H * (4 * 12.5350 + H * (5 * -6.6134 + H * 6 * 1.3618))))
                     : -1.1982 + H * (2 * 0.7614 +
                                      H * (3 * -0.3394 +
                                           H * (4 * 0.1116 + H * (5 * -0.0220 + H * 6 * 0.0018))));
        return {A, slope};
    }
    if (H >= 3.0) return {0.0, 0.0};
    if (!(H > 0.0)) return {1.0, 0.0};
    const double Z = christensen_separation(H);
    const double w = 1.0 - Z * Z;
    return {christensen_contact_ratio_of_separation(Z),
            -(35.0 / 32.0) * w * w * w / (3.0 * one_minus_contact(Z))};
}

}  // namespace rollgap::core
