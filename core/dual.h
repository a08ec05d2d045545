#pragma once
// Forward-mode derivatives for the bite sensitivities (docs/model.md §6.1): a value and its
// derivatives in N directions, carried through the same arithmetic as the value. Only what the
// bite kernel uses is defined. Comparisons look at the value alone: a branch taken by the value
// is the branch whose derivative is wanted (the kernel's branches are one-sided limits or
// regime switches, and its solution is smooth between them).

#include <array>
#include <cmath>

namespace rollgap::core {

template <int N>
struct Dual {
    double v = 0.0;
    std::array<double, N> d{};

    Dual() = default;
    Dual(double value) : v(value) {}  // NOLINT: a constant is a dual with zero derivatives
    static Dual variable(double value, int direction) {
        Dual x(value);
        x.d[direction] = 1.0;
        return x;
    }

    Dual& operator+=(const Dual& o) {
        v += o.v;
        for (int i = 0; i < N; ++i) d[i] += o.d[i];
        return *this;
    }
    Dual& operator-=(const Dual& o) {
        v -= o.v;
        for (int i = 0; i < N; ++i) d[i] -= o.d[i];
        return *this;
    }
    Dual& operator*=(const Dual& o) {
        for (int i = 0; i < N; ++i) d[i] = d[i] * o.v + v * o.d[i];
        v *= o.v;
        return *this;
    }
    Dual& operator/=(const Dual& o) {
        const double q = v / o.v;
        for (int i = 0; i < N; ++i) d[i] = (d[i] - q * o.d[i]) / o.v;
        v = q;
        return *this;
    }
};

template <int N>
Dual<N> operator-(Dual<N> a) {
    a.v = -a.v;
    for (double& x : a.d) x = -x;
    return a;
}
template <int N>
Dual<N> operator+(Dual<N> a, const Dual<N>& b) {
    return a += b;
}
template <int N>
Dual<N> operator-(Dual<N> a, const Dual<N>& b) {
    return a -= b;
}
template <int N>
Dual<N> operator*(Dual<N> a, const Dual<N>& b) {
    return a *= b;
}
template <int N>
Dual<N> operator/(Dual<N> a, const Dual<N>& b) {
    return a /= b;
}

// with a constant: no products of derivatives with zeros
template <int N>
Dual<N> operator+(Dual<N> a, double b) {
    a.v += b;
    return a;
}
template <int N>
Dual<N> operator+(double a, Dual<N> b) {
    b.v += a;
    return b;
}
template <int N>
Dual<N> operator-(Dual<N> a, double b) {
    a.v -= b;
    return a;
}
template <int N>
Dual<N> operator-(double a, const Dual<N>& b) {
    return a + (-b);
}
template <int N>
Dual<N> operator*(Dual<N> a, double b) {
    a.v *= b;
    for (double& x : a.d) x *= b;
    return a;
}
template <int N>
Dual<N> operator*(double a, Dual<N> b) {
    return b * a;
}
template <int N>
Dual<N> operator/(Dual<N> a, double b) {
    a.v /= b;
    for (double& x : a.d) x /= b;
    return a;
}
template <int N>
Dual<N> operator/(double a, const Dual<N>& b) {
    Dual<N> out(a / b.v);
    const double scale = -out.v / b.v;
    for (int i = 0; i < N; ++i) out.d[i] = scale * b.d[i];
    return out;
}

template <int N>
bool operator<(const Dual<N>& a, const Dual<N>& b) {
    return a.v < b.v;
}
template <int N>
bool operator>(const Dual<N>& a, const Dual<N>& b) {
    return a.v > b.v;
}
template <int N>
bool operator<=(const Dual<N>& a, const Dual<N>& b) {
    return a.v <= b.v;
}
template <int N>
bool operator>=(const Dual<N>& a, const Dual<N>& b) {
    return a.v >= b.v;
}
template <int N>
bool operator==(const Dual<N>& a, const Dual<N>& b) {
    return a.v == b.v;
}
template <int N>
bool operator!=(const Dual<N>& a, const Dual<N>& b) {
    return a.v != b.v;
}
template <int N>
bool operator<(const Dual<N>& a, double b) {
    return a.v < b;
}
template <int N>
bool operator>(const Dual<N>& a, double b) {
    return a.v > b;
}
template <int N>
bool operator<=(const Dual<N>& a, double b) {
    return a.v <= b;
}
template <int N>
bool operator>=(const Dual<N>& a, double b) {
    return a.v >= b;
}
template <int N>
bool operator==(const Dual<N>& a, double b) {
    return a.v == b;
}
template <int N>
bool operator!=(const Dual<N>& a, double b) {
    return a.v != b;
}
template <int N>
bool operator<(double a, const Dual<N>& b) {
    return a < b.v;
}
template <int N>
bool operator>(double a, const Dual<N>& b) {
    return a > b.v;
}

// f(a) with f'(a) = slope: the chain rule
template <int N>
Dual<N> chain(const Dual<N>& a, double value, double slope) {
    Dual<N> out(value);
    for (int i = 0; i < N; ++i) out.d[i] = slope * a.d[i];
    return out;
}

template <int N>
Dual<N> exp(const Dual<N>& a) {
    const double e = std::exp(a.v);
    return chain(a, e, e);
}
template <int N>
Dual<N> expm1(const Dual<N>& a) {
    return chain(a, std::expm1(a.v), std::exp(a.v));
}
template <int N>
Dual<N> sqrt(const Dual<N>& a) {
    const double r = std::sqrt(a.v);
    return chain(a, r, 0.5 / r);
}
template <int N>
Dual<N> abs(const Dual<N>& a) {
    return a.v < 0.0 ? -a : a;
}
template <int N>
bool isfinite(const Dual<N>& a) {
    if (!std::isfinite(a.v)) return false;
    for (double x : a.d) {
        if (!std::isfinite(x)) return false;
    }
    return true;
}

// the value of a double or a dual
inline double value_of(double x) { return x; }
template <int N>
double value_of(const Dual<N>& x) {
    return x.v;
}

}  // namespace rollgap::core
