#pragma once
// Reading a fuzzer's bytes as a stream of small decisions. An exhausted input reads as zeros,
// so every byte string, the empty one included, is a complete input.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace rollgap::fuzz {

class FuzzInput {
public:
    FuzzInput(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

    std::uint8_t byte() { return position_ < size_ ? data_[position_++] : 0; }
    bool flag() { return (byte() & 1) != 0; }
    // A fraction in [0, 1] with 16-bit resolution: both ends are reachable.
    double unit() {
        const unsigned high = byte();
        const unsigned low = byte();
        return static_cast<double>((high << 8) | low) / 65535.0;
    }
    // A value in [min, max], log-uniform when the interval spans more than two decades and
    // has positive ends (masses from 1 kg to 10^7 kg, viscosities from 1e-5 to 10 Pa s).
    double between(double min, double max) {
        const double t = unit();
        if (min > 0.0 && max / min > 100.0)
            return std::exp(std::log(min) + t * (std::log(max) - std::log(min)));
        return min + t * (max - min);
    }

private:
    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t position_ = 0;
};

// A broken invariant is a crash for libFuzzer: it saves the input and stops.
inline void require(bool holds, const char* invariant) {
    if (holds) return;
    std::fprintf(stderr, "invariant broken: %s\n", invariant);
    std::abort();
}

}  // namespace rollgap::fuzz
