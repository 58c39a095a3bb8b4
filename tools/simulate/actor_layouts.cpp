#include "tools/simulate/actor_layouts.hpp"
#include "tools/simulate/angles.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>

#include "tools/simulate/placement_space.hpp"

namespace dammloam::sim {

namespace {

constexpr int kTries = 300;  // per actor (or group, door) before it is left out
constexpr double kSceneMargin = 0.02;  // metres between an actor and a wall, tree or pillar

// Seeds the actors' generator apart from the range noise (per column streams) and the carrier
// (MotionSpec::seed), so adding actors changes neither.
std::uint64_t ActorStream(std::uint64_t seed) {
  std::uint64_t z = seed + 0xA5C7F0E5D1B2C3A4ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Draws that do not depend on the standard library's distribution implementations.
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(ActorStream(seed)) {}
  double Uniform(double a, double b) {
    return a + (b - a) * static_cast<double>(rng_() >> 11) * (1.0 / 9007199254740992.0);
  }
  int Int(int a, int b) { return a + static_cast<int>(rng_() % static_cast<std::uint64_t>(b - a + 1)); }
  bool Chance(double p) { return Uniform(0.0, 1.0) < p; }
  double Sign() { return Chance(0.5) ? 1.0 : -1.0; }

 private:
  std::mt19937_64 rng_;
};


// Places along a centreline as (s, lateral): s metres along it, lateral metres to its left.
// A corridor's frame is its axis; open ground's is the carrier's own path (its footway).
struct WalkFrame {
  Path centre;
  bool closed = false;
  double s_min = 0.0, s_max = 0.0;
  double walk_band = 0.0;   // |lateral| of walking lines
  double cross_band = 0.0;  // |lateral| reached by people crossing the footway
  std::vector<double> sample_s;
  std::vector<Eigen::Vector2d> sample_xy;

  Eigen::Vector2d ToWorld(const Eigen::Vector2d& s_lat) const {
    const Path::State at = centre.At(s_lat.x(), closed);
    return at.position + s_lat.y() * LeftOf(at.heading);
  }
  Eigen::Vector2d Left(double s) const { return LeftOf(centre.At(s, closed).heading); }
  bool Inside(double s) const { return closed || (s >= s_min && s <= s_max); }
  Eigen::Vector2d Project(const Eigen::Vector2d& xy) const {
    std::size_t best = 0;
    for (std::size_t i = 1; i < sample_xy.size(); ++i) {
      if ((sample_xy[i] - xy).squaredNorm() < (sample_xy[best] - xy).squaredNorm()) best = i;
    }
    const double s = sample_s[best];
    return {s, (xy - sample_xy[best]).dot(Left(s))};
  }
  void Sample() {
    for (double s = 0.0; s <= centre.length(); s += 0.25) {
      sample_s.push_back(s);
      sample_xy.push_back(centre.At(s, closed).position);
    }
  }
};

WalkFrame CorridorFrame(const Bounds2d& floor) {
  WalkFrame f;
  const double mid = 0.5 * (floor.min.y() + floor.max.y());
  f.centre = Path({Eigen::Vector2d(floor.min.x(), mid), 0.0}).Line(floor.max.x() - floor.min.x());
  f.s_min = 0.4;
  f.s_max = f.centre.length() - 0.4;
  f.walk_band = f.cross_band = 0.5 * (floor.max.y() - floor.min.y()) - 0.26;
  f.Sample();
  return f;
}

WalkFrame OpenFrame(const Path& path) {
  WalkFrame f;
  f.centre = path;
  f.closed = (path.At(path.length()).position - path.At(0.0).position).norm() < 0.5;
  f.s_min = 0.0;
  f.s_max = path.length();
  // Inside the row of trees 3-4.5 m either side of the footway, and up to it when crossing.
  f.walk_band = 2.45;
  f.cross_band = 4.6;
  f.Sample();
  return f;
}

// A route given by corners in the frame, turned into a world polyline that follows the frame's
// curves (a point every metre), with the distance along it at each corner.
struct FramePath {
  std::vector<Eigen::Vector2d> corners;  // (s, lateral), in walking order
  std::vector<Eigen::Vector2d> points;   // world
  std::vector<double> corner_distance;

  bool Build(const WalkFrame& frame) {
    points.clear();
    corner_distance.clear();
    double walked = 0.0;
    for (std::size_t i = 0; i < corners.size(); ++i) {
      if (!frame.Inside(corners[i].x())) return false;
      if (i == 0) {
        points.push_back(frame.ToWorld(corners[0]));
        corner_distance.push_back(0.0);
        continue;
      }
      const Eigen::Vector2d from = corners[i - 1], to = corners[i];
      const int steps = std::max(1, static_cast<int>(std::ceil((to - from).cwiseAbs().maxCoeff())));
      for (int k = 1; k <= steps; ++k) {
        const Eigen::Vector2d p = frame.ToWorld(from + (to - from) * k / steps);
        walked += (p - points.back()).norm();
        points.push_back(p);
      }
      corner_distance.push_back(walked);
    }
    return true;
  }
  void Turn(double dir, double lateral, Draw& draw) {
    const Eigen::Vector2d last = corners.back();
    const double run = std::max(0.5, std::abs(lateral - last.y()) * draw.Uniform(1.0, 2.0));
    corners.push_back({last.x() + dir * run, lateral});
  }
  void Straight(double dir, double length) {
    corners.push_back({corners.back().x() + dir * length, corners.back().y()});
  }
};

class Placer {
 public:
  Placer(const ActorConfig& config, const World& world, const Trajectory& trajectory, double duration,
         std::uint64_t seed)
      : config_(config),
        world_(world),
        carrier_(std::make_shared<const Trajectory>(trajectory)),
        space_(world, trajectory, duration),
        draw_(seed),
        frame_(world.layout.corridor ? CorridorFrame(*world.layout.corridor)
                                     : OpenFrame(trajectory.spec().path)) {}

  ActorSet Place() {
    PlaceDoors();
    if (config_.follow_me) PlaceLeader();
    for (int i = 0; i < config_.groups; ++i) PlaceGroup();
    if (!world_.layout.corridor) {
      PlaceTraffic();
      if (config_.park_and_leave) PlaceParkAndLeave();
    }
    for (int i = 0; i < config_.walkers; ++i) PlaceWalker(i < config_.close_passes);
    if (!world_.layout.corridor) {
      for (int i = 0; i < config_.standing; ++i) PlaceStanding();
    }
    return ActorSet(space_.TakeActors(), world_.scene.ground());
  }

 private:
  double duration() const { return space_.duration(); }
  double Height() { return draw_.Uniform(config_.height_min, config_.height_max); }
  float Clothes() { return static_cast<float>(draw_.Uniform(0.15, 0.6)); }
  double WalkSpeed() { return draw_.Uniform(config_.walk_speed_min, config_.walk_speed_max); }

  // Accepts the actor if it keeps its distances; `close_pass`: it must also pass within 1 m.
  bool TryAccept(Actor actor, bool close_pass = false, bool check_scene = true) {
    const bool vehicle = actor.kind == ActorKind::Vehicle;
    if (space_.PopDistance(actor) < (vehicle ? config_.vehicle_pop_distance : config_.pop_distance)) {
      return false;
    }
    ActorTrack track = space_.Track(actor);
    if (close_pass && space_.ClosestPass(track) > 1.0) return false;
    if (check_scene && !space_.ClearOfScene(track, kSceneMargin)) return false;
    if (space_.SensorGap(actor, track) < config_.sensor_clearance) return false;
    if (!space_.ClearOfActors(track)) return false;
    space_.Accept(std::move(actor), std::move(track));
    return true;
  }

  std::vector<Stop> Stops(const FramePath& path, double keep_clear_from, double keep_clear_to) {
    std::vector<Stop> stops;
    const double length = path.corner_distance.back();
    for (int n = draw_.Int(0, 2); n > 0; --n) {
      const double at = draw_.Uniform(0.1, 0.9) * length;
      if (at > keep_clear_from && at < keep_clear_to) continue;
      stops.push_back({at, draw_.Uniform(config_.stop_min, config_.stop_max)});
    }
    return stops;
  }

  // A pedestrian on `path` who is `at_distance` metres along it at time `at_time`; it may wait
  // at its ends instead of appearing and vanishing there.
  Actor Walker(const FramePath& path, double speed, std::vector<Stop> stops, double at_distance,
               double at_time) {
    const Route timing(path.points, speed, 0.0, stops);
    const Route route(path.points, speed, at_time - timing.TimeAt(at_distance), std::move(stops));
    Actor a = MakePedestrian(route, Height(), Clothes());
    a.appear = draw_.Chance(0.2) ? -kForever : route.start_time();
    a.vanish = draw_.Chance(0.2) ? kForever : route.end_time();
    return a;
  }

  void PlaceWalker(bool close_pass) {
    for (int i = 0; i < kTries; ++i) {
      if (close_pass ? TryPasser() : TryWanderer()) return;
    }
  }

  // Walks past the sensor at 0.78-0.95 m (centre to sensor), straight for 5 m around the pass.
  bool TryPasser() {
    const double t_meet = draw_.Uniform(3.0, duration() - 3.0);
    const Eigen::Vector2d carrier = frame_.Project(space_.SensorAt(t_meet).head<2>());
    const double offset = draw_.Uniform(0.78, 0.95);
    double lateral = carrier.y() + draw_.Sign() * offset;
    if (std::abs(lateral) > frame_.walk_band) lateral = 2.0 * carrier.y() - lateral;
    if (std::abs(lateral) > frame_.walk_band) return false;
    const double dir = draw_.Sign();
    FramePath path;
    const double before = draw_.Uniform(4.0, 18.0);
    const double start_lateral = draw_.Uniform(-frame_.walk_band, frame_.walk_band);
    const double diagonal = std::max(0.5, std::abs(lateral - start_lateral) * draw_.Uniform(1.0, 2.0));
    path.corners = {{carrier.x() - dir * (2.5 + diagonal + before), start_lateral},
                    {carrier.x() - dir * (2.5 + diagonal), start_lateral},
                    {carrier.x() - dir * 2.5, lateral},
                    {carrier.x(), lateral},
                    {carrier.x() + dir * 2.5, lateral}};
    path.Turn(dir, draw_.Uniform(-frame_.walk_band, frame_.walk_band), draw_);
    path.Straight(dir, draw_.Uniform(4.0, 18.0));
    if (!path.Build(frame_)) return false;
    const double meet = path.corner_distance[3];
    Actor a = Walker(path, WalkSpeed(), Stops(path, meet - 3.0, meet + 3.0), meet, t_meet);
    return TryAccept(std::move(a), true);
  }

  // Walks a few legs along the corridor or footway, or crosses the footway, with turns and stops.
  bool TryWanderer() {
    FramePath path;
    const double dir = draw_.Sign();
    const double s0 = draw_.Uniform(frame_.s_min, frame_.s_max);
    if (frame_.cross_band > frame_.walk_band + 1.0 && draw_.Chance(0.25)) {
      const double side = draw_.Sign();
      path.corners = {{s0, side * frame_.cross_band}, {s0 + draw_.Uniform(-2.0, 2.0), -side * frame_.cross_band}};
    } else {
      path.corners = {{s0, draw_.Uniform(-frame_.walk_band, frame_.walk_band)}};
    }
    for (int legs = draw_.Int(1, 3); legs > 0; --legs) {
      path.Turn(dir, draw_.Uniform(-frame_.walk_band, frame_.walk_band), draw_);
      path.Straight(dir, draw_.Uniform(5.0, 20.0));
    }
    if (!path.Build(frame_)) return false;
    Actor a = Walker(path, WalkSpeed(), Stops(path, 0.0, 0.0), 0.0, draw_.Uniform(-30.0, duration() - 5.0));
    return TryAccept(std::move(a));
  }

  void PlaceStanding() {
    for (int i = 0; i < kTries; ++i) {
      const double s = draw_.Uniform(frame_.s_min, frame_.s_max);
      const double lateral = draw_.Sign() * draw_.Uniform(1.3, frame_.walk_band);
      const Route here(frame_.ToWorld({s, lateral}), draw_.Uniform(-kPi, kPi));
      if (TryAccept(MakePedestrian(here, Height(), Clothes()))) return;
    }
  }

  void PlaceLeader() {
    Actor a = MakePedestrian(Leader{carrier_, config_.follow_distance}, Height(), Clothes(),
                             ActorRole::Leader);
    space_.Accept(a, space_.Track(a));  // on the carrier's own path: clear wherever it walks
  }

  // How far the lateral band beside the carrier reaches on `side` at path distance s.
  double RoomBeside(double s, double side) const {
    if (!world_.layout.corridor) return config_.group_offset_max;
    const Bounds2d& floor = *world_.layout.corridor;
    const Eigen::Vector2d at = carrier_->spec().path.At(s).position;
    const Eigen::Vector2d left = side * LeftOf(carrier_->spec().path.At(s).heading);
    double room = kForever;
    for (int axis = 0; axis < 2; ++axis) {
      if (left[axis] > 1e-6) room = std::min(room, (floor.max[axis] - at[axis]) / left[axis]);
      if (left[axis] < -1e-6) room = std::min(room, (floor.min[axis] - at[axis]) / left[axis]);
    }
    return room;
  }

  // A line beside the path keeps its shape only where the path turns wider than its offset
  // (in a U-turn it would cross the path and meet the carrier).
  bool WideTurnsOnly(double s_from, double s_to, double radius) const {
    const Path& path = carrier_->spec().path;
    const double length = path.length();
    for (double s = s_from; s <= s_to; s += 0.25) {
      const double on_path = frame_.closed ? s - length * std::floor(s / length) : s;
      if (std::abs(path.Curvature(on_path)) * radius > 1.0) return false;
    }
    return true;
  }

  // The time before (direction -1) or after (+1) `from` when a companion walking at `speed`
  // along the carrier's path is pop_distance (plus room for the lateral offset) away from it.
  double GapReached(double from, double direction, double speed) const {
    const double wanted = config_.pop_distance + 1.5;
    const double s_from = carrier_->PathDistance(from);
    double t = from;
    for (; std::abs(t - from) < 120.0; t += direction * 0.5) {
      const double companion = s_from + speed * (t - from);
      if (std::abs(companion - carrier_->PathDistance(t)) >= wanted) break;
    }
    return t;
  }

  void PlaceGroup() {
    for (int i = 0; i < kTries; ++i) {
      if (TryGroup()) return;
    }
  }

  // When a group walks with the carrier: before, it stands waiting where the carrier will join
  // it; after, it walks on faster. It appears and vanishes pop_distance away from the carrier.
  struct GroupTiming {
    double join = 0.0, leave = 0.0, before = 0.0, after = 0.0, appear = 0.0, vanish = 0.0;
  };
  std::optional<GroupTiming> DrawGroupTiming() {
    GroupTiming g;
    const double together = draw_.Uniform(config_.group_time_min, config_.group_time_max);
    g.join = draw_.Uniform(0.05 * duration(), 0.9 * duration() - together);
    g.leave = g.join + together;
    const double pace = (carrier_->PathDistance(g.leave) - carrier_->PathDistance(g.join)) / together;
    g.after = config_.walk_speed_max;
    if (pace < 0.4 || g.after < pace + 0.2) return std::nullopt;
    g.appear = GapReached(g.join, -1.0, g.before);
    g.vanish = GapReached(g.leave, 1.0, g.after);
    return g;
  }

  // Where the group walks beside the carrier: on which side, how far out its first file is,
  // and how many fit side by side.
  struct Formation {
    double side = 1.0, nearest = 0.0;
    int abreast = 1;
  };
  static constexpr double kShoulderToShoulder = 0.56, kRowToRow = 0.9;
  std::optional<Formation> DrawFormation(double s_middle) {
    Formation f;
    // In a corridor, the side with more room; on open ground, either.
    f.side = draw_.Sign();
    if (RoomBeside(s_middle, -f.side) > RoomBeside(s_middle, f.side)) f.side = -f.side;
    f.nearest = world_.layout.corridor ? config_.sensor_clearance + 0.325 : config_.group_offset_min;
    const double farthest = std::min(RoomBeside(s_middle, f.side) - 0.25, config_.group_offset_max);
    if (farthest < f.nearest) return std::nullopt;
    f.abreast = std::min(3, 1 + static_cast<int>((farthest - f.nearest) / kShoulderToShoulder));
    return f;
  }

  // 3-5 people in rows side by side keeping pace with the carrier for 10-30 s; all or none.
  // (Strolling ahead slower before would take them tens of metres back, often round a turn.)
  bool TryGroup() {
    const std::optional<GroupTiming> g = DrawGroupTiming();
    if (!g) return false;
    const std::optional<Formation> f = DrawFormation(carrier_->PathDistance(0.5 * (g->join + g->leave)));
    if (!f) return false;
    const double s_first = carrier_->PathDistance(g->join) - g->before * (g->join - g->appear) - 2 * kRowToRow;
    const double s_last = carrier_->PathDistance(g->leave) + g->after * (g->vanish - g->leave);
    const double outermost = f->nearest + kShoulderToShoulder * (f->abreast - 1);
    if (!WideTurnsOnly(s_first, s_last, outermost + 1.0)) return false;
    const std::size_t placed_before = space_.accepted().size();
    for (int m = 0, members = draw_.Int(3, 5); m < members; ++m) {
      const Companion c{carrier_, -kRowToRow * (m / f->abreast),
                        f->side * (f->nearest + kShoulderToShoulder * (m % f->abreast)),
                        g->join, g->leave, g->before, g->after};
      Actor a = MakePedestrian(c, Height(), Clothes(), ActorRole::Companion);
      a.appear = g->appear;
      a.vanish = g->vanish;
      if (!TryAccept(std::move(a))) {
        space_.Truncate(placed_before);
        return false;
      }
    }
    return true;
  }

  // Doors open into the corridor while the sensor is 4-12 m away, so it sees them move.
  void PlaceDoors() {
    std::vector<DoorRecess> recesses = world_.layout.doors;
    for (std::size_t i = recesses.size(); i > 1; --i) {
      std::swap(recesses[i - 1], recesses[static_cast<std::size_t>(draw_.Int(0, static_cast<int>(i) - 1))]);
    }
    int placed = 0;
    for (const DoorRecess& recess : recesses) {
      if (placed == config_.doors) return;
      for (int i = 0; i < 20; ++i) {
        if (TryDoor(recess)) {
          ++placed;
          break;
        }
      }
    }
  }

  bool TryDoor(const DoorRecess& recess) {
    const double leaf = 2.0 * recess.half_width - 0.1;
    const bool hinge_low_x = draw_.Chance(0.5);
    Swing swing;
    // 2.5 cm in front of the recess back (the static door), so the closed leaf is seen first.
    swing.hinge = {recess.x + (hinge_low_x ? -0.5 : 0.5) * leaf, recess.back_y - recess.side * 0.025};
    swing.closed_yaw = hinge_low_x ? 0.0 : kPi;
    swing.open_angle = -recess.side * (hinge_low_x ? 1.0 : -1.0) * 0.5 * kPi;  // into the corridor
    swing.duration = config_.door_open_time;
    std::vector<double> visible;
    const Eigen::Vector2d centre(recess.x, recess.wall_y);
    for (std::size_t k = 0; k < space_.sensor_samples().size(); ++k) {
      const double t = static_cast<double>(k) * kPlacementStep;
      const double d = (space_.sensor_samples()[k].head<2>() - centre).norm();
      if (d > 4.0 && d < 12.0 && t > 2.0 && t < duration() - 3.0) visible.push_back(t);
    }
    if (visible.empty()) return false;
    swing.open_time = visible[static_cast<std::size_t>(draw_.Int(0, static_cast<int>(visible.size()) - 1))];
    return TryAccept(MakeDoor(swing, leaf, recess.height - 0.1, 0.35f), false, false);
  }

  // A closed lane parallel to the carrier's path `offset` metres to its left, where a car fits
  // all the way round.
  std::optional<std::vector<Eigen::Vector2d>> Lane(double offset) const {
    const Path& path = carrier_->spec().path;
    if (!frame_.closed) return std::nullopt;
    std::vector<Eigen::Vector2d> lane;
    for (double s = 0.0; s < path.length() - 0.25; s += 0.5) {
      const Path::State at = path.At(s);
      lane.push_back(at.position + offset * LeftOf(at.heading));
    }
    for (std::size_t i = 0; i < lane.size(); i += 2) {
      const Eigen::Vector2d along = lane[(i + 1) % lane.size()] - lane[(i + lane.size() - 1) % lane.size()];
      const Actor parked = MakeVehicle(Route(lane[i], std::atan2(along.y(), along.x())), 0.5f);
      if (!space_.ClearOfScene(BodyInWorld(parked, ActorFrame(parked, 0.0, space_.ground())), 0.3)) {
        return std::nullopt;
      }
    }
    return lane;
  }

  void FindLanes() {
    for (const double sign : {-1.0, 1.0}) {
      for (const double offset : {6.0, 6.5, 5.5, 7.0}) {
        if (auto lane = Lane(sign * offset)) {
          (sign < 0 ? outer_lane_ : inner_lane_) = std::move(lane);
          break;
        }
      }
    }
    if (!outer_lane_) std::swap(outer_lane_, inner_lane_);
  }

  float Paint() { return static_cast<float>(draw_.Uniform(0.3, 0.8)); }

  // Through traffic round the outer lane against the carrier's direction, evenly spaced.
  void PlaceTraffic() {
    FindLanes();
    if (!outer_lane_ || config_.traffic <= 0) return;
    std::vector<Eigen::Vector2d> lane(outer_lane_->rbegin(), outer_lane_->rend());
    const double speed = draw_.Uniform(config_.drive_speed_min, config_.drive_speed_max);
    const double length = Route(lane, speed, 0.0, {}, true).length();
    const double phase = draw_.Uniform(0.0, length);
    for (int i = 0; i < config_.traffic; ++i) {
      const double ahead = phase + length * i / config_.traffic;
      TryAccept(MakeVehicle(Route(lane, speed, -ahead / speed, {}, true), Paint()), false, false);
    }
  }

  // `length` metres of the inner lane ending (parking) or starting (leaving) at `spot`.
  std::vector<Eigen::Vector2d> LanePiece(std::size_t spot, double length, bool ending) const {
    const std::vector<Eigen::Vector2d>& lane = *inner_lane_;
    const auto n = static_cast<std::ptrdiff_t>(length / 0.5);
    const auto size = static_cast<std::ptrdiff_t>(lane.size());
    std::vector<Eigen::Vector2d> piece;
    for (std::ptrdiff_t k = ending ? -n : 0; k <= (ending ? 0 : n); ++k) {
      piece.push_back(lane[static_cast<std::size_t>(((static_cast<std::ptrdiff_t>(spot) + k) % size + size) % size)]);
    }
    return piece;
  }

  std::size_t LaneSpotNear(const Eigen::Vector2d& xy) const {
    const std::vector<Eigen::Vector2d>& lane = *inner_lane_;
    std::size_t best = 0;
    for (std::size_t i = 1; i < lane.size(); ++i) {
      if ((lane[i] - xy).squaredNorm() < (lane[best] - xy).squaredNorm()) best = i;
    }
    return best;
  }

  // One car drives in along the inner lane and parks just before the carrier gets there; one
  // parked there from the start drives off just after the carrier passed it.
  void PlaceParkAndLeave() {
    if (!inner_lane_) return;
    const double slowest = config_.drive_speed_min, fastest = std::min(6.0, config_.drive_speed_max);
    for (int i = 0; i < kTries; ++i) {
      const double speed = draw_.Uniform(slowest, fastest), parked = draw_.Uniform(0.2, 0.6) * duration();
      const std::size_t spot = LaneSpotNear(space_.SensorAt(parked + draw_.Uniform(0.0, 10.0)).head<2>());
      const Route route(LanePiece(spot, draw_.Uniform(40.0, 80.0), true), speed, 0.0);
      Actor a = MakeVehicle(Route(route.points(), speed, parked - route.end_time()), Paint(), ActorRole::Parking);
      a.appear = std::get<Route>(a.motion).start_time();
      if (TryAccept(std::move(a), false, false)) break;
    }
    for (int i = 0; i < kTries; ++i) {
      const double speed = draw_.Uniform(slowest, fastest), leaves = draw_.Uniform(0.15, 0.55) * duration();
      const std::size_t spot = LaneSpotNear(space_.SensorAt(leaves - draw_.Uniform(0.0, 6.0)).head<2>());
      const Route route(LanePiece(spot, draw_.Uniform(40.0, 80.0), false), speed, leaves);
      Actor a = MakeVehicle(route, Paint(), ActorRole::Leaving);
      a.vanish = route.end_time();
      if (TryAccept(std::move(a), false, false)) break;
    }
  }

  const ActorConfig& config_;
  const World& world_;
  std::shared_ptr<const Trajectory> carrier_;
  PlacementSpace space_;
  Draw draw_;
  WalkFrame frame_;
  std::optional<std::vector<Eigen::Vector2d>> outer_lane_, inner_lane_;
};

}  // namespace

ActorSet PlaceActors(const ActorConfig& config, const World& world, const Trajectory& trajectory,
                     double duration, std::uint64_t seed) {
  if (!config.any()) return {};
  return Placer(config, world, trajectory, duration, seed).Place();
}

}  // namespace dammloam::sim
