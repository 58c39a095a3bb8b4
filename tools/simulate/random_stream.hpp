#pragma once
#include <cmath>
#include <cstdint>
#include <numbers>

namespace dammloam::sim {

// SplitMix64, as the range noise (simulator.cpp) and the carriers (motion.cpp) use it; as
// RandomStream for the IMU and wheel streams. Each stream is seeded from the run's seed xor its own constant, so
// adding one never moves a number of another: scans and ground truth stay bit-identical.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t Next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double Uniform() { return static_cast<double>(Next() >> 11) * (1.0 / 9007199254740992.0); }
  double Range(double a, double b) { return a + (b - a) * Uniform(); }
  double Gaussian() {  // Box-Muller
    const double u1 = 1.0 - Uniform(), u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
};

struct RandomStream : SplitMix64 {
  RandomStream(std::uint64_t seed, std::uint64_t stream) : SplitMix64{seed ^ stream} { Next(); }
};

inline constexpr std::uint64_t kImuStream = 0x696D752D6E6F6973ull;    // "imu-nois"
inline constexpr std::uint64_t kWheelStream = 0x776865656C2D6F64ull;  // "wheel-od"

}  // namespace dammloam::sim
