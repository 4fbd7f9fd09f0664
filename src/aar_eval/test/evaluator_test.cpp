#include "aar_eval/evaluator.h"

#include <gtest/gtest.h>

#include <cmath>

namespace aar_eval {
namespace {

constexpr int64_t kSecond = 1000000000;

// Truth: the receiver 36 m aft and below (region C), at every stamp but 6 s.
std::optional<Eigen::Isometry3d> Truth(int64_t stamp_ns, std::string* error) {
  if (stamp_ns == 6 * kSecond) {
    *error = "extrapolation into the future";
    return std::nullopt;
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(-34.5, 0.0, -10.0);
  return T;
}

Estimate At(double x, bool valid = true) {
  Estimate e;
  e.valid = valid;
  e.T_tanker_receiver.translation() = Eigen::Vector3d(x, 0.0, -10.0);
  e.converged = true;
  e.iterations = 7;
  return e;
}

// The NEES of an estimate 0.1 m off in x with a 0.05 m position sigma is (0.1 / 0.05)^2 = 4;
// without a covariance it is NaN; the tracker's outcome is copied.
TEST(Evaluator, NeesOfTheEstimateAgainstItsCovariance) {
  Evaluator eval(1.0, 3);
  Estimate e = At(-34.4);
  e.covariance.diagonal() << 0.0025, 0.0025, 0.0025, 1e-4, 1e-4, 1e-4;
  e.track = "accepted";
  eval.AddFrame(2 * kSecond);
  eval.AddEstimate(2 * kSecond, e);
  eval.AddFrame(3 * kSecond);
  eval.AddEstimate(3 * kSecond, At(-34.4));
  const auto settled = eval.SettleAll(Truth);
  ASSERT_EQ(settled.size(), 2u);
  EXPECT_NEAR(settled[0].record.nees, 4.0, 1e-9);
  EXPECT_EQ(settled[0].record.track, "accepted");
  EXPECT_TRUE(std::isnan(settled[1].record.nees));
  EXPECT_EQ(settled[1].record.track, "off");
}

TEST(Evaluator, LongerGraceKeepsLateEstimates) {
  // Real time: estimates lag frames behind; with 5 frames of grace the 5th-newest still counts.
  Evaluator eval(1.0, 0, 5);
  for (int k = 2; k <= 6; ++k) eval.AddFrame(k * kSecond);
  EXPECT_TRUE(eval.SettleReady(Truth).empty());
  EXPECT_TRUE(eval.AddEstimate(2 * kSecond, At(-34.4)));  // four frames late: kept
  eval.AddFrame(7 * kSecond);
  const auto settled = eval.SettleReady(Truth);
  ASSERT_EQ(settled.size(), 1u);
  EXPECT_TRUE(settled[0].record.estimated);
  EXPECT_FALSE(eval.AddEstimate(2 * kSecond, At(-34.4)));
}

TEST(Evaluator, SettlesAllButTheNewestTwoFramesAndRecordsMisses) {
  Evaluator eval(1.0, 6);
  EXPECT_EQ(eval.AddFrame(2 * kSecond), Evaluator::FrameStatus::kNew);
  EXPECT_TRUE(eval.AddEstimate(2 * kSecond, At(-34.4)));
  EXPECT_EQ(eval.AddFrame(2 * kSecond), Evaluator::FrameStatus::kRepeat);
  EXPECT_EQ(eval.AddFrame(3 * kSecond), Evaluator::FrameStatus::kNew);
  EXPECT_TRUE(eval.SettleReady(Truth).empty());  // two frames: both may still get estimates
  EXPECT_TRUE(eval.AddEstimate(3 * kSecond, At(0.0, false)));  // registration gave no pose
  eval.AddFrame(4 * kSecond);                                  // never estimated
  const auto first = eval.SettleReady(Truth);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].stamp_ns, 2 * kSecond);
  EXPECT_TRUE(first[0].record.estimated);
  EXPECT_NEAR(first[0].record.t, 1.0, 1e-12);  // stamp minus the stamp offset
  EXPECT_NEAR(first[0].record.error[0], 0.1, 1e-9);
  EXPECT_EQ(first[0].record.iterations, 7);
  EXPECT_EQ(first[0].record.region, aar_geometry::Region::kC);
  EXPECT_EQ(first[0].progress.rfind("eval: frame 1 of 6, 35.9 m (region C): error 0.100 m", 0), 0u)
      << first[0].progress;

  EXPECT_FALSE(eval.AddEstimate(2 * kSecond, At(-34.4)));  // its frame is settled: too late
  EXPECT_EQ(eval.AddFrame(1 * kSecond), Evaluator::FrameStatus::kOlder);
  eval.AddFrame(5 * kSecond);
  eval.AddFrame(6 * kSecond);
  eval.AddEstimate(99 * kSecond, At(-34.4));  // a frame never announced
  const auto rest = eval.SettleAll(Truth);
  ASSERT_EQ(rest.size(), 4u);  // 3, 4, 5, 6
  EXPECT_FALSE(rest[0].record.estimated);
  EXPECT_NE(rest[0].progress.find("MISSED"), std::string::npos) << rest[0].progress;
  EXPECT_FALSE(rest[1].record.estimated);
  // The misses publish the last estimate again: its error against their truth.
  EXPECT_TRUE(first[0].record.published);
  for (int k : {0, 1}) {
    EXPECT_TRUE(rest[k].record.published);
    EXPECT_NEAR(rest[k].record.published_error[0], 0.1, 1e-9);
  }
  EXPECT_EQ(rest[3].no_truth, "extrapolation into the future");
  EXPECT_EQ(eval.records().size(), 4u);  // 2, 3, 4, 5: frame 6 had no truth
  EXPECT_EQ(eval.frames_without_truth(), 1);
  EXPECT_EQ(eval.estimates_without_frame(), 1u);
}

// Before the first estimate nothing is published; a held estimate is scored against the truth
// of the frame it is held into.
TEST(Evaluator, MissesBeforeTheFirstEstimatePublishNothing) {
  Evaluator eval(1.0, 3);
  eval.AddFrame(2 * kSecond);
  eval.AddEstimate(2 * kSecond, At(0.0, false));
  eval.AddFrame(3 * kSecond);
  eval.AddEstimate(3 * kSecond, At(-34.0));
  eval.AddFrame(4 * kSecond);
  auto truth = [](int64_t stamp_ns, std::string*) -> std::optional<Eigen::Isometry3d> {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();  // 1 m/s closer each second
    T.translation() = Eigen::Vector3d(-40.0 + static_cast<double>(stamp_ns / kSecond), 0, -10);
    return T;
  };
  const auto settled = eval.SettleAll(truth);
  ASSERT_EQ(settled.size(), 3u);
  EXPECT_FALSE(settled[0].record.published);
  EXPECT_TRUE(settled[1].record.estimated);
  EXPECT_NEAR(settled[1].record.published_error[0], 3.0, 1e-9);  // -34 against -37
  EXPECT_FALSE(settled[2].record.estimated);
  EXPECT_TRUE(settled[2].record.published);
  EXPECT_NEAR(settled[2].record.published_error[0], 2.0, 1e-9);  // -34 held against -36
}

}  // namespace
}  // namespace aar_eval
