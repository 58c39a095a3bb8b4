#pragma once
#include "tools/simulate/scenes.hpp"

// Scenes where odometry drifts and loop closure is tempted (issue 53): a long campus route with
// revisits, a building with two identical floors, a warehouse of identical aisles. Used by
// BuildWorld (scenes.cpp); `arrive_time` is when a carrier's walk is planned to end.
namespace dammloam::sim {

// A ~1.55 km route on a 3 x 2 grid of blocks (85 x 65 m) between buildings, parks and an open
// field, with trees, poles and parked cars, on rolling ground; streets are revisited several
// times, some in the opposite direction. `speed` (the carrier's top speed) sizes the corners:
// radius 4 m on foot, up to 10 m for a car.
World CampusLong(double speed, double arrive_time);

// Two floors of the same ring corridor (40 x 18 m centreline) 3 m apart, joined by a straight
// staircase of 18 steps: once round floor 1, up, once round floor 2 right above, a little on.
World TwoFloor(double arrive_time);
inline constexpr double kTwoFloorStorey = 3.0;  // metres from floor 1 to floor 2

// Five identical aisles between pallet racks, driven up and down, then two of them again.
World Warehouse(double arrive_time);
// The aisles run along x between the racks' ends; aisle k's centre line is at
// y = kWarehouseAisleY0 + k * kWarehouseAislePitch.
inline constexpr int kWarehouseAisles = 5;
inline constexpr double kWarehouseAisleY0 = 3.7, kWarehouseAislePitch = 5.4;
inline constexpr double kWarehouseRackX0 = 8.0, kWarehouseRackX1 = 38.0;

}  // namespace dammloam::sim
