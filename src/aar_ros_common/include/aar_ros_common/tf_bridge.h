#pragma once

#include <optional>
#include <string>

#include <ros/time.h>
#include <tf2_ros/buffer.h>
#include <Eigen/Geometry>

namespace aar_ros_common {

// Waits for a transform in wall-clock time. tf2's own timed wait counts simulated time, which
// stands still in lockstep while the simulator waits for the pipeline.
bool WaitForTransform(const tf2_ros::Buffer& buffer, const std::string& target,
                      const std::string& source, const ros::Time& time, double timeout_s);

// T_target_source at `time` after waiting up to `timeout_s` [s wall]; std::nullopt with `error`
// set ("no tf TARGET -> 'SOURCE' at STAMP_WHAT within T s") when it does not come.
std::optional<Eigen::Isometry3d> LookupTransform(const tf2_ros::Buffer& buffer,
                                                 const std::string& target,
                                                 const std::string& source, const ros::Time& time,
                                                 double timeout_s, const std::string& stamp_what,
                                                 std::string* error);

// The latest T_target_source, if tf has one no older than `max_age` [s] and not newer than
// `time`.
std::optional<Eigen::Isometry3d> LatestTransform(const tf2_ros::Buffer& buffer,
                                                 const std::string& target,
                                                 const std::string& source, const ros::Time& time,
                                                 double max_age);

// LookupTransform, and when that fails and `fallback_age` > 0, LatestTransform within
// `fallback_age` (error cleared then): for a stage that can use a joint's pose a frame old rather
// than wait for tf that comes after the data (real time; issue 28). 0: LookupTransform alone.
std::optional<Eigen::Isometry3d> LookupTransformOrLatest(
    const tf2_ros::Buffer& buffer, const std::string& target, const std::string& source,
    const ros::Time& time, double timeout_s, double fallback_age, const std::string& stamp_what,
    std::string* error);

}  // namespace aar_ros_common
