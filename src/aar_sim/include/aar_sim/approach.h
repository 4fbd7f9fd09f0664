#pragma once

#include <cstdint>
#include <vector>

#include <aar_description/receiver_model.h>

#include "aar_sim/flight_path.h"

namespace aar_sim {

// The default approach: the receiver flies in trail from `start_range` to the contact position,
// closing fast far out and slowly and steadily inside 50 m, holding there for `hold` seconds,
// with seeded low-frequency attitude and position wander that fades out at contact.
struct ApproachOptions {
  double start_range = 174.0;  // [m] from the tanker origin at t = 0; wander keeps it <= 175
  double elevation = 13.0;     // [deg] of the start point below the contact position, seen from it
  double far_speed = 6.0;      // [m/s] closure beyond 70 m
  double mid_speed = 2.5;      // [m/s] closure from 70 m to 50 m
  double near_speed = 0.6;     // [m/s] closure inside 50 m (steady, as a receiver would fly)
  double hold = 3.0;           // [s] stationary at contact at the end
  double rate = 10.0;          // [Hz] rows per second
  double position_wander = 0.6;  // [m] peak wander far out, fading to 0 at contact
  double attitude_wander = 1.5;  // [deg] peak roll/pitch/yaw wander far out
  double pitch = 2.0;            // [deg] nose-up trim of the receiver
  // [deg] of the start point about the contact position, seen from it: positive towards the
  // tanker's +y (left); the lateral start offset.
  double azimuth = 0.0;
  // Boom motion: 0 keeps the boom at its static pose and writes no boom columns; s > 0 swings
  // it by up to s x (5 deg pitch, 8 deg roll, 1 m extension) with seeded periods and phases
  // while the receiver is beyond 60 m, settling to the static pose by 45 m so that the nozzle
  // meets the receptacle at contact.
  double boom_swing = 0.0;
  uint64_t seed = 7;
  // [m] the receiver's receptacle in its body frame (a receiver description's `receptacle`)
  Eigen::Vector3d receptacle = aar_description::ReceptacleInReceiver();
};

// One approach of a suite: the default's shape with start offset (elevation 8-18 deg, azimuth
// +/-10 deg), closure profile (far 4-8, mid 1.5-3.5, near 0.4-0.9 m/s), wander (position 0.2-1.0
// m, attitude 0.5-2.5 deg) and boom swing (0-1) drawn from `seed`, which also seeds the wander.
ApproachOptions VariedApproach(uint64_t seed);

// Rows from t = 0 to the end of the hold; the last rows put the receptacle exactly on
// `contact_receptacle_in_tanker` [m] (the boom's nozzle tip) at the trim attitude.
std::vector<FlightPathRow> GenerateApproach(const ApproachOptions& options,
                                            const Eigen::Vector3d& contact_receptacle_in_tanker);

}  // namespace aar_sim
