#include "aar_eval/integrity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace aar_eval {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// An estimated frame at `range_m` with position error `x` [m] and yaw error `yaw` [deg], levels
// `pl_m`, `pl_deg` and the alert limits 1 m and 2 deg.
FrameRecord Frame(double range_m, double x, double yaw, double pl_m, double pl_deg,
                  double nees = kNan) {
  FrameRecord f;
  f.range_m = range_m;
  f.region = aar_geometry::RegionOfRange(range_m);
  f.estimated = true;
  f.error = {x, 0.0, 0.0, 0.0, 0.0, yaw};
  f.nees = nees;
  f.pl_position_m = pl_m;
  f.pl_attitude_deg = pl_deg;
  f.al_position_m = 1.0;
  f.al_attitude_deg = 2.0;
  f.published = true;
  f.published_error = f.error;
  return f;
}

TEST(Integrity, ErrorNormAndAttitudeAngle) {
  FrameRecord f = Frame(35.0, 0.0, 0.0, 1.0, 1.0);
  f.error = {3.0, -4.0, 12.0, 0.0, 0.0, -30.0};
  EXPECT_DOUBLE_EQ(PositionErrorNorm(f), 13.0);
  EXPECT_NEAR(AttitudeErrorAngleDeg(f), 30.0, 1e-9);
  // Roll and pitch together: the angle of Rz(0) Ry(10 deg) Rx(10 deg), not the larger of the two
  // nor their sum.
  f.error = {0.0, 0.0, 0.0, 10.0, 10.0, 0.0};
  const double d = M_PI / 18.0;
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(d, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(d, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const double expected = std::acos((R.trace() - 1.0) / 2.0) * 180.0 / M_PI;  // 14.1 deg
  EXPECT_NEAR(AttitudeErrorAngleDeg(f), expected, 1e-9);
  EXPECT_GT(expected, 14.0);
  EXPECT_LT(expected, 14.2);
}

// One frame of each kind in region C (limits 1 m, 2 deg), and two in region A.
std::vector<FrameRecord> EachKind() {
  std::vector<FrameRecord> frames;
  frames.push_back(Frame(35.0, 0.1, 0.5, 0.5, 1.0, 6.0));     // 0 nominal
  frames.push_back(Frame(35.0, 0.6, 0.5, 0.5, 1.0, 30.0));    // 1 misleading (position)
  frames.push_back(Frame(35.0, 0.1, 1.5, 0.5, 1.0, 4.0));     // 2 misleading (attitude)
  frames.push_back(Frame(35.0, 1.5, 0.5, 0.5, 1.0, 40.0));    // 3 HMI (position beyond 1 m)
  frames.push_back(Frame(35.0, 0.1, -3.0, 0.5, 1.0, 8.0));    // 4 HMI (attitude beyond 2 deg)
  frames.push_back(Frame(35.0, 5.0, 10.0, 0.5, 1.0, 100.0));  // 5 in alert: nothing counts
  frames.back().alert = true;
  frames.push_back(Frame(35.0, 0.0, 0.0, kNan, kNan));  // 6 a miss
  frames.back().estimated = false;
  frames.push_back(Frame(35.0, 5.0, 10.0, kNan, kNan, 2.0));  // 7 no levels (an old publisher)
  frames.push_back(Frame(35.0, 0.2, 0.5, 2.0, 1.0));  // 8 unavailable: bounded, 2 m > 1 m limit
  frames.push_back(Frame(100.0, 0.2, 0.5, 0.5, 1.0, 6.0));  // 9 region A, nominal
  frames.push_back(Frame(100.0, 0.2, 0.5, 0.5, 1.0, 6.0));  // 10 outside every region
  frames.back().range_m = 20.0;
  frames.back().region = aar_geometry::Region::kOutside;
  return frames;
}

TEST(Integrity, EachKindOfFrameClassified) {
  const auto frames = EachKind();
  auto is = [&](size_t i, bool misleading, bool available, bool hazardous) {
    const FrameIntegrity c = ClassifyIntegrity(frames[i]);
    EXPECT_EQ(c.misleading, misleading) << "frame " << i;
    EXPECT_EQ(c.available, available) << "frame " << i;
    EXPECT_EQ(c.hazardous, hazardous) << "frame " << i;
  };
  is(0, false, true, false);
  is(1, true, true, false);
  is(2, true, true, false);
  is(3, true, true, true);
  is(4, true, true, true);
  is(5, false, false, false);
  is(6, false, false, false);
  is(7, false, false, false);
  is(8, false, false, false);
}

TEST(Integrity, RegionCountsByHand) {
  const auto stats = ComputeIntegrityStats(EachKind());
  ASSERT_EQ(stats.count("B"), 0u);
  const IntegrityStats& c = stats.at("C");
  EXPECT_EQ(c.frames, 9);
  EXPECT_EQ(c.estimated, 8);    // all but the miss
  EXPECT_EQ(c.with_levels, 7);  // not the miss, not the frame without levels
  EXPECT_EQ(c.alert, 1);
  EXPECT_EQ(c.with_nees, 7);  // 6, 30, 4, 40, 8, 100, 2
  EXPECT_DOUBLE_EQ(c.NeesMean(), 190.0 / 7.0);
  EXPECT_EQ(c.beyond_nees_bound, 3);  // 30, 40, 100
  EXPECT_DOUBLE_EQ(c.BeyondNeesBoundShare(), 3.0 / 7.0);
  EXPECT_EQ(c.misleading, 4);
  EXPECT_EQ(c.hazardous, 2);
  EXPECT_EQ(c.available, 5);
  EXPECT_DOUBLE_EQ(c.Availability(), 5.0 / 9.0);  // the miss counts as unavailable
  const IntegrityStats& a = stats.at("A");
  EXPECT_EQ(a.frames, 1);
  EXPECT_EQ(a.available, 1);
  const IntegrityStats& all = stats.at("all");  // A and C, not the frame outside
  EXPECT_EQ(all.frames, 10);
  EXPECT_EQ(all.available, 6);
  EXPECT_EQ(all.with_nees, 8);
  EXPECT_DOUBLE_EQ(all.NeesMean(), 196.0 / 8.0);
  // Summing two runs adds the counts; the mean is over all frames with a NEES.
  IntegrityStats twice = c;
  twice += stats.at("A");
  EXPECT_EQ(twice.frames, 10);
  EXPECT_DOUBLE_EQ(twice.NeesMean(), all.NeesMean());
  EXPECT_TRUE(std::isnan(IntegrityStats{}.NeesMean()));
  EXPECT_TRUE(std::isnan(IntegrityStats{}.Availability()));
}

// Levels scaled down: frames in alert because their levels exceeded the limits (what the
// publisher does) lose that alert, and those whose error exceeds a limit are hazardously
// misleading; an alert for another reason (an unconfirmed track: levels within the limits) stays.
TEST(Integrity, ScaledLevelsCanFail) {
  std::vector<FrameRecord> frames = {Frame(35.0, 0.5, 0.5, 5.0, 5.0),   // error within the limits
                                     Frame(35.0, 2.0, 0.5, 5.0, 5.0),   // beyond 1 m
                                     Frame(35.0, 2.0, 0.5, 0.5, 1.0)};  // unconfirmed
  for (FrameRecord& f : frames) f.alert = true;
  const IntegrityStats one = ComputeIntegrityStats(frames).at("C");
  EXPECT_EQ(one.misleading, 0);
  EXPECT_EQ(one.hazardous, 0);
  EXPECT_EQ(one.available, 0);
  const IntegrityStats scaled = ComputeIntegrityStats(frames, {0.01}).at("C");
  EXPECT_EQ(scaled.misleading, 2);  // 0.5 m > 0.05 m; 2 m > 0.05 m
  EXPECT_EQ(scaled.hazardous, 1);   // 2 m > 1 m
  EXPECT_EQ(scaled.available, 2);
}

// Levels scaled up are what a larger overbound factor publishes: a frame whose scaled level
// passes its limit is in alert (so neither misleading nor available), one still within it is
// misleading no more once its level covers the error.
TEST(Integrity, LevelsScaledUpAlertAsTheirPublisherWould) {
  // Levels doubled: 0.6 m, within region C's 1 m limit here; 1.2 m, beyond it, and still below
  // the second frame's 1.5 m error, which is no longer misleading only because it is in alert.
  const std::vector<FrameRecord> frames = {Frame(35.0, 0.4, 0.1, 0.3, 0.5),
                                           Frame(35.0, 1.5, 0.1, 0.6, 0.5)};
  const IntegrityStats one = ComputeIntegrityStats(frames).at("C");
  EXPECT_EQ(one.misleading, 2);  // 0.4 > 0.3, 1.5 > 0.6
  EXPECT_EQ(one.hazardous, 1);   // 1.5 > 1
  EXPECT_EQ(one.available, 2);
  const IntegrityStats doubled = ComputeIntegrityStats(frames, {2.0}).at("C");
  EXPECT_EQ(doubled.misleading, 0);  // 0.4 < 0.6; the second is in alert
  EXPECT_EQ(doubled.available, 1);
  EXPECT_EQ(doubled.hazardous, 0);
}

}  // namespace
}  // namespace aar_eval
