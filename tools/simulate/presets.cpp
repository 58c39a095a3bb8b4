#include "tools/simulate/presets.hpp"

#include <algorithm>

namespace dammloam::sim {

SimOptions Preset::Options(std::uint64_t seed) const {
  SimOptions options;
  options.seed = seed;
  options.noise_sigma = noise_sigma;
  options.motion = motion;
  options.num_scans = scans;
  options.full_range_reflectivity = full_range_reflectivity;
  return options;
}

const std::vector<Preset>& Presets() {
  static const std::vector<Preset> presets = [] {
    std::vector<Preset> p;
    auto add = [&](std::string name, SceneKind scene, MotionKind motion, int scans, std::string what) {
      Preset preset;
      preset.name = std::move(name);
      preset.scene = scene;
      preset.motion = motion;
      preset.scans = scans;
      preset.what = std::move(what);
      p.push_back(std::move(preset));
    };
    add("handheld-corridor", SceneKind::LongCorridor, MotionKind::Handheld, 1700,
        "walking speed changes, stops and a U-turn in a featureless corridor (end walls fade)");
    add("wheeled-corridor", SceneKind::StraightCorridor, MotionKind::Wheeled, 800,
        "smooth speed changes and a stop along a short featureless corridor");
    add("legged-tunnel", SceneKind::Tunnel, MotionKind::Legged, 1500,
        "trot pitch/roll and bobbing in a curved, self-similar tunnel");
    add("handheld-endless", SceneKind::EndlessCorridor, MotionKind::Handheld, 3500,
        "no end wall ever in range: only the motion model constrains the corridor axis");
    add("handheld-campus", SceneKind::Campus, MotionKind::Handheld, 2500,
        "walking outdoors on uneven ground, a 300 m loop back to the start");
    add("wheeled-zigzag", SceneKind::Zigzag, MotionKind::Wheeled, 850,
        "speed changes and stops on a zig-zag through a corridor with doors and pillars");
    return p;
  }();
  return presets;
}

std::vector<std::string> PresetNames() {
  std::vector<std::string> names;
  for (const Preset& p : Presets()) names.push_back(p.name);
  return names;
}

std::optional<Preset> FindPreset(std::string_view name) {
  const auto& all = Presets();
  const auto it = std::find_if(all.begin(), all.end(), [&](const Preset& p) { return p.name == name; });
  if (it == all.end()) return std::nullopt;
  return *it;
}

double DefaultNoise(MotionKind motion) { return motion == MotionKind::Constant ? 0.01 : 0.015; }

double DefaultFullRangeReflectivity(MotionKind motion) {
  return motion == MotionKind::Constant ? 0.0 : kRealisticFullRangeReflectivity;
}

}  // namespace dammloam::sim
