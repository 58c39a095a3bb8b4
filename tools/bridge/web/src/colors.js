// Point classes of core/geometry/point_class.hpp (the label field) and the colours drawn for
// them; the bridge test looks for these exact colours in a screenshot (tests/bridge).
export const CLASS_COLORS = [
  { id: 0, name: "unknown", hex: 0x9e9e9e },
  { id: 1, name: "ground", hex: 0x8d6e63 },
  { id: 2, name: "roof", hex: 0xe53935 },
  { id: 3, name: "wall", hex: 0x1e88e5 },
  { id: 4, name: "edge", hex: 0xfdd835 },
  { id: 5, name: "moving", hex: 0xff6d00 },
];
export const TRAJECTORY_COLOR = 0x00ffff;
export const LOOP_COLOR = 0xff00ff;
export const SCAN_COLOR = 0xffffff;
