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

// The estimate's protection levels, alert limits and alert are copied; levels of 0 (a publisher
// without integrity) and a miss's (in alert, levels 0) are none.
TEST(Evaluator, IntegrityOfTheEstimateIsCopied) {
  Evaluator eval(1.0, 3);
  Estimate e = At(-34.4);
  e.protection_level_position = 0.5;
  e.protection_level_attitude = 1.5;
  e.alert_limit_position = 1.0;
  e.alert_limit_attitude = 2.0;
  e.alert = true;
  Estimate miss = At(0.0, false);
  miss.alert = true;
  eval.AddFrame(2 * kSecond);
  eval.AddEstimate(2 * kSecond, e);
  eval.AddFrame(3 * kSecond);
  eval.AddEstimate(3 * kSecond, At(-34.4));
  eval.AddFrame(4 * kSecond);
  eval.AddEstimate(4 * kSecond, miss);
  const auto settled = eval.SettleAll(Truth);
  ASSERT_EQ(settled.size(), 3u);
  const FrameRecord& with = settled[0].record;
  EXPECT_EQ(with.pl_position_m, 0.5);
  EXPECT_EQ(with.pl_attitude_deg, 1.5);
  EXPECT_EQ(with.al_position_m, 1.0);
  EXPECT_EQ(with.al_attitude_deg, 2.0);
  EXPECT_TRUE(with.alert);
  for (const auto& s : {settled[1], settled[2]}) {
    EXPECT_TRUE(std::isnan(s.record.pl_position_m));
    EXPECT_TRUE(std::isnan(s.record.pl_attitude_deg));
    EXPECT_TRUE(std::isnan(s.record.al_position_m));
    EXPECT_TRUE(std::isnan(s.record.al_attitude_deg));
  }
  EXPECT_FALSE(settled[1].record.alert);
  EXPECT_FALSE(settled[2].record.estimated);
  EXPECT_TRUE(settled[2].record.alert);
}

bool Always(int64_t) { return true; }

TEST(Evaluator, LateEstimatesCountUntilTheFrameIsDue) {
  // A busy machine: estimates lag frames behind, by time, not by a count of frames.
  Evaluator eval(1.0, 0, 10.0);
  for (int k = 2; k <= 6; ++k) eval.AddFrame(k * kSecond, 0.1 * k);
  EXPECT_TRUE(eval.SettleReady(5.0, Always, Truth).empty());  // none resolved, none due
  EXPECT_TRUE(eval.AddEstimate(2 * kSecond, At(-34.4)));      // four frames late: kept
  eval.AddFrame(7 * kSecond, 5.0);
  auto settled = eval.SettleReady(5.0, Always, Truth);
  ASSERT_EQ(settled.size(), 1u);  // frame 2 on its estimate; 3 waits (and 4 behind it)
  EXPECT_TRUE(settled[0].record.estimated);
  EXPECT_EQ(settled[0].ledger.outcome, "estimated");
  EXPECT_FALSE(eval.AddEstimate(2 * kSecond, At(-34.4)));
  EXPECT_TRUE(eval.AddEstimate(4 * kSecond, At(-34.4)));
  settled = eval.SettleReady(10.35, Always, Truth);  // 3 due (announced at 0.3 s), then 4
  ASSERT_EQ(settled.size(), 2u);
  EXPECT_FALSE(settled[0].record.estimated);
  EXPECT_EQ(settled[0].ledger.outcome, "dropped");
  EXPECT_EQ(settled[0].ledger.reason, "never_paired");
  EXPECT_TRUE(settled[1].record.estimated);
}

// A lost estimate (the first frame's, sent before eval's subscription was linked: seen under
// load, when no /aar/pose_error came for 10 s) does not hold the later frames: once a later
// announced frame's estimate came, the earlier frame settles as a miss. An estimate for a frame
// not yet announced (or never: a stray stamp) settles nothing before it.
TEST(Evaluator, ALaterEstimateSettlesAFrameWhoseEstimateWasLost) {
  Evaluator eval(1.0, 0, 10.0);
  for (int k = 2; k <= 4; ++k) eval.AddFrame(k * kSecond, 0.1 * k);
  EXPECT_TRUE(eval.AddEstimate(99 * kSecond, At(-34.4)));  // never announced
  EXPECT_TRUE(eval.SettleReady(1.0, Always, Truth).empty());
  EXPECT_TRUE(eval.AddEstimate(3 * kSecond, At(-34.4)));
  const auto settled = eval.SettleReady(1.0, Always, Truth);
  ASSERT_EQ(settled.size(), 2u);  // 2 (lost) and 3; 4 waits for its own
  EXPECT_FALSE(settled[0].record.estimated);
  EXPECT_EQ(settled[0].ledger.outcome, "dropped");
  EXPECT_TRUE(settled[1].record.estimated);
}

// A frame settles on its estimate only once its truth is there; until it is due.
TEST(Evaluator, AFrameWaitsForItsTruth) {
  Evaluator eval(1.0, 0, 10.0);
  eval.AddFrame(2 * kSecond, 0.0);
  eval.AddEstimate(2 * kSecond, At(-34.4));
  EXPECT_TRUE(eval.SettleReady(
                      1.0, [](int64_t) { return false; }, Truth)
                  .empty());
  EXPECT_EQ(eval.SettleReady(1.0, Always, Truth).size(), 1u);
}

TEST(Evaluator, SettlesOnTheEstimateOrADropOrInTimeAndRecordsMisses) {
  Evaluator eval(1.0, 6, 10.0);
  EXPECT_EQ(eval.AddFrame(2 * kSecond), Evaluator::FrameStatus::kNew);
  EXPECT_TRUE(eval.AddEstimate(2 * kSecond, At(-34.4)));
  EXPECT_EQ(eval.AddFrame(2 * kSecond), Evaluator::FrameStatus::kRepeat);
  EXPECT_EQ(eval.AddFrame(3 * kSecond), Evaluator::FrameStatus::kNew);
  EXPECT_TRUE(eval.AddEstimate(3 * kSecond, At(0.0, false)));  // registration gave no pose
  eval.AddFrame(4 * kSecond);                                  // dropped by stereo, below
  eval.AddFrame(5 * kSecond);                                  // lost in occlusion's queue
  const auto first = eval.SettleReady(1.0, Always, Truth);
  ASSERT_EQ(first.size(), 2u);  // 2 and 3: their estimates came
  EXPECT_EQ(first[0].stamp_ns, 2 * kSecond);
  EXPECT_TRUE(first[0].record.estimated);
  EXPECT_NEAR(first[0].record.t, 1.0, 1e-12);  // stamp minus the stamp offset
  EXPECT_NEAR(first[0].record.error[0], 0.1, 1e-9);
  EXPECT_EQ(first[0].record.iterations, 7);
  EXPECT_EQ(first[0].record.region, aar_geometry::Region::kC);
  EXPECT_EQ(first[0].progress.rfind("eval: frame 1 of 6, 35.9 m (region C): error 0.100 m", 0), 0u)
      << first[0].progress;
  EXPECT_EQ(first[1].ledger.outcome, "no_pose");
  EXPECT_FALSE(eval.AddEstimate(2 * kSecond, At(-34.4)));  // its frame is settled: too late
  EXPECT_EQ(eval.AddFrame(1 * kSecond), Evaluator::FrameStatus::kOlder);

  EXPECT_TRUE(eval.AddOutcome(4 * kSecond, {"stereo", true, "stale", "waited 0.3 s"}));
  const auto dropped = eval.SettleReady(1.0, Always, Truth);  // 4 on its drop; 5 not yet due
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_FALSE(dropped[0].record.estimated);
  EXPECT_NE(dropped[0].progress.find("MISSED"), std::string::npos) << dropped[0].progress;
  EXPECT_EQ(dropped[0].ledger.stage, "stereo");
  EXPECT_EQ(dropped[0].ledger.reason, "stale");
  // The misses publish the last estimate again: its error against their truth.
  EXPECT_TRUE(dropped[0].record.published);
  EXPECT_NEAR(dropped[0].record.published_error[0], 0.1, 1e-9);

  eval.AddOutcome(5 * kSecond, {"stereo", false, "", ""});
  eval.AddFrame(6 * kSecond);
  eval.AddEstimate(99 * kSecond, At(-34.4));  // a frame never announced
  const auto rest = eval.SettleAll(Truth);
  ASSERT_EQ(rest.size(), 2u);  // 5, 6
  EXPECT_EQ(rest[0].ledger.stage, "occlusion");
  EXPECT_EQ(rest[0].ledger.reason, "queue");
  EXPECT_EQ(rest[1].no_truth, "extrapolation into the future");
  EXPECT_EQ(rest[1].ledger.stage, "eval");
  EXPECT_EQ(rest[1].ledger.reason, "no_truth");
  EXPECT_EQ(eval.records().size(), 4u);  // 2, 3, 4, 5: frame 6 had no truth
  EXPECT_EQ(eval.ledger().size(), 5u);   // every frame, 6 too
  EXPECT_EQ(eval.frames_without_truth(), 1);
  EXPECT_EQ(eval.estimates_without_frame(), 1u);
  EXPECT_EQ(LedgerSummary(eval.ledger()),
            "5 frames: 1 estimated, 0 coasted, 0 lost, 1 no pose, 3 dropped (eval no_truth 1, "
            "occlusion queue 1, stereo stale 1)");
}

// Every frame gets exactly one outcome: from its estimate, else the first drop, else where it
// was last seen.
TEST(Ledger, EachFrameHasOneOutcomeNamingTheStageAndReason) {
  Estimate coasting = At(-34.4);
  coasting.track = "rejected";
  EXPECT_EQ(ClassifyFrame(&coasting, {}, "").outcome, "coasted");
  Estimate lost = At(0.0, false);
  lost.track = "lost";
  EXPECT_EQ(ClassifyFrame(&lost, {}, "").outcome, "lost");
  const Estimate none = At(0.0, false);
  const LedgerEntry no_pose =
      ClassifyFrame(&none, {{"registration", true, "no_pose", "no reference model yet"}}, "");
  EXPECT_EQ(no_pose.outcome, "no_pose");
  EXPECT_EQ(no_pose.detail, "no reference model yet");
  const LedgerEntry superseded = ClassifyFrame(
      nullptr, {{"stereo", false, "", ""}, {"occlusion", true, "superseded", "newer"}}, "");
  EXPECT_EQ(superseded.stage, "occlusion");
  EXPECT_EQ(superseded.reason, "superseded");
  const LedgerEntry after_registration = ClassifyFrame(
      nullptr,
      {{"stereo", false, "", ""}, {"occlusion", false, "", ""}, {"registration", false, "", ""}},
      "");
  EXPECT_EQ(after_registration.stage, "eval");
  EXPECT_EQ(after_registration.reason, "queue");
  // A registration drop comes with its estimate: it does not settle the frame alone.
  EXPECT_FALSE(IsFinal({"registration", true, "no_pose", ""}));
  EXPECT_TRUE(IsFinal({"stereo", true, "sync_mismatch", ""}));
  EXPECT_FALSE(IsFinal({"stereo", false, "", ""}));
  // A further rig's drop leaves the frame to registration, which has the other rigs.
  EXPECT_FALSE(IsFinal({"share_mirror/stereo", true, "sync_mismatch", ""}));
  EXPECT_FALSE(IsFinal({"share_mirror/occlusion", true, "error", ""}));
  LedgerEntry row{1500000000, 0.5, "dropped", "stereo", "sync_mismatch", "a \"quoted\", b"};
  EXPECT_EQ(LedgerCsvRow(row),
            "0.5,1.500000000,dropped,stereo,sync_mismatch,\"a \"\"quoted\"\", b\"");
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

// The simulator's visibility: the frame takes the camera that saw most of the receiver (the
// most visible pixels, not the largest share: the right camera's sliver at the image's edge); a
// frame whose receiver was in no view has 0 pixels, one never measured NaN; a visibility for a
// settled frame is refused.
TEST(Evaluator, VisibilityOfTheBestViewIsRecorded) {
  // Once visibility comes, a frame whose estimate came first waits for it (it once settled
  // without, its visibility "after its frame settled": 1 frame in 19,656 of a suite).
  Evaluator waits(1.0, 2, 10.0);
  auto ready = [](int64_t) { return true; };
  waits.AddFrame(2 * kSecond, 0.0);
  waits.AddVisibility(2 * kSecond, {{1000, 500}});
  waits.AddFrame(3 * kSecond, 0.0);
  waits.AddEstimate(2 * kSecond, At(-34.4));
  waits.AddEstimate(3 * kSecond, At(-34.4));
  EXPECT_EQ(waits.SettleReady(1.0, ready, Truth).size(), 1u);  // frame 3 waits
  waits.AddVisibility(3 * kSecond, {{1000, 600}});
  const auto later = waits.SettleReady(1.0, ready, Truth);
  ASSERT_EQ(later.size(), 1u);
  EXPECT_EQ(later[0].record.visible_fraction, 0.6);

  Evaluator eval(1.0, 3);
  for (int64_t s : {2, 3, 4}) eval.AddFrame(s * kSecond);
  EXPECT_TRUE(eval.AddVisibility(2 * kSecond, {{1000, 400}, {20, 20}}));
  EXPECT_TRUE(eval.AddVisibility(3 * kSecond, {{0, 0}, {0, 0}}));
  EXPECT_TRUE(eval.AddVisibility(4 * kSecond, {{1000, 250}, {800, 250}}));  // equals: the share
  const auto settled = eval.SettleAll(Truth);
  ASSERT_EQ(settled.size(), 3u);
  EXPECT_EQ(settled[0].record.visible_fraction, 0.4);
  EXPECT_EQ(settled[0].record.visible_px, 400);
  EXPECT_EQ(settled[0].record.visible_fraction_least, 0.4);  // the sliver's 1.0 is the most
  EXPECT_TRUE(std::isnan(settled[1].record.visible_fraction));
  EXPECT_EQ(settled[1].record.visible_px, 0);
  EXPECT_TRUE(std::isnan(settled[1].record.visible_fraction_least));
  EXPECT_EQ(settled[2].record.visible_fraction, 250.0 / 800.0);
  EXPECT_EQ(settled[2].record.visible_fraction_least, 0.25);
  EXPECT_FALSE(eval.AddVisibility(2 * kSecond, {{1000, 1000}}));
  eval.AddFrame(5 * kSecond);
  EXPECT_TRUE(std::isnan(eval.SettleAll(Truth)[0].record.visible_px));  // never measured
}

// Two rigs (issue 44): the best view of either, and the weaker camera of the rig that sees most
// with both (the first rig's cameras 10 % and 90 %, the second's 80 % and 70 %: 70 %).
TEST(Evaluator, VisibilityOfTwoRigsTakesTheRigThatSeesWithBoth) {
  Evaluator eval(1.0, 2);
  eval.AddFrame(2 * kSecond);
  EXPECT_TRUE(eval.AddVisibility(2 * kSecond, {{1000, 100}, {1000, 900}}));
  EXPECT_TRUE(eval.AddVisibility(2 * kSecond, {{1000, 800}, {1000, 700}}, 1));
  eval.AddFrame(3 * kSecond);  // the second rig's never came: the first rig's alone
  EXPECT_TRUE(eval.AddVisibility(3 * kSecond, {{1000, 100}, {1000, 900}}));
  const auto settled = eval.SettleAll(Truth);
  ASSERT_EQ(settled.size(), 2u);
  EXPECT_EQ(settled[0].record.visible_fraction, 0.9);
  EXPECT_EQ(settled[0].record.visible_fraction_least, 0.7);
  EXPECT_EQ(settled[1].record.visible_fraction_least, 0.1);
}

}  // namespace
}  // namespace aar_eval
