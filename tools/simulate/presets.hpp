#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tools/simulate/simulator.hpp"

// Named realistic runs: a scene, a carrier and the scan count of the whole walk. They are the
// default rows of the benchmark. Build one with
//   const sim::Simulator simulator(*sim::FindPreset("handheld-corridor"), sim::Vlp16(), seed);
// or take preset->Options(seed), change what you need, and use Simulator(preset->scene, ...).
namespace dammloam::sim {

struct Preset {
  std::string name;
  SceneKind scene = SceneKind::LongCorridor;
  MotionKind motion = MotionKind::Handheld;
  double noise_sigma = 0.015;  // metres
  int scans = 0;               // the whole walk at 10 Hz (ends standing still)
  double full_range_reflectivity = kRealisticFullRangeReflectivity;
  std::string what;            // what the run tests, one line
  ActorConfig actors;          // moving people, vehicles and doors (none by default)
  double look_arounds_per_minute = 0.0;  // hand-held: sideways swings of the sensor (SimOptions)
  std::optional<HandheldProfile> handheld_profile;  // hand-held: not a walk (SimOptions)

  // scene-independent options: seed, noise, carrier, range model, num_scans = scans.
  SimOptions Options(std::uint64_t seed = 1) const;
};

const std::vector<Preset>& Presets();
std::vector<std::string> PresetNames();
std::optional<Preset> FindPreset(std::string_view name);

// Range noise a carrier gets unless told otherwise: 0.01 m (constant, as always), else 0.015 m.
double DefaultNoise(MotionKind motion);
// Range model a carrier gets unless told otherwise: ideal (0) for constant, else realistic.
double DefaultFullRangeReflectivity(MotionKind motion);

}  // namespace dammloam::sim
