#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "aar_registration/integrity.h"

namespace aar_registration {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Published chi-square quantiles (3 degrees of freedom): 11.345 at 1 - 1e-2, 25.902 at 1 - 1e-5.
TEST(Integrity, ProtectionFactorIsTheChiSquareBoundOfA3dError) {
  EXPECT_NEAR(ProtectionFactor(1e-2), std::sqrt(11.345), 1e-3);
  EXPECT_NEAR(ProtectionFactor(1e-5), std::sqrt(25.902), 1e-3);
  EXPECT_NEAR(ProtectionFactor(1e-3, 6), std::sqrt(22.458), 1e-3);  // tracker's gate_chi2
  EXPECT_GT(ProtectionFactor(1e-7), ProtectionFactor(1e-5));
}

// An elongated covariance: the level follows its largest axis (3 m along the line of sight, 0.1 m
// across), the attitude level its largest rotation sigma, in degrees; factor and bias add on.
TEST(Integrity, LevelsFollowTheLargestSigmaTimesTheFactorPlusTheBias) {
  Matrix6d c = Matrix6d::Zero();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  c.topLeftCorner<3, 3>() = R * Eigen::Vector3d(9.0, 0.01, 0.01).asDiagonal() * R.transpose();
  c.bottomRightCorner<3, 3>().diagonal() << std::pow(0.5 * kDeg, 2), std::pow(2.0 * kDeg, 2),
      std::pow(0.1 * kDeg, 2);
  IntegrityOptions o;
  o.integrity_risk = 1e-5;
  o.overbound_factor = 1.0;
  const double k = std::sqrt(25.902);
  ProtectionLevels pl = ComputeProtectionLevels(c, o);
  EXPECT_NEAR(pl.position_m, 3.0 * k, 1e-3);
  EXPECT_NEAR(pl.attitude_deg, 2.0 * k, 1e-3);
  o.overbound_factor = 1.5;
  o.position_bias_m = 0.2;
  o.attitude_bias_deg = 0.3;
  pl = ComputeProtectionLevels(c, o);
  EXPECT_NEAR(pl.position_m, 1.5 * 3.0 * k + 0.2, 1e-3);
  EXPECT_NEAR(pl.attitude_deg, 1.5 * 2.0 * k + 0.3, 1e-3);
}

// Drawn from the covariance, errors beyond the level are about as rare as the risk says, or rarer
// (the bound is conservative for a covariance that is not a sphere).
TEST(Integrity, GaussianErrorsExceedTheLevelNoMoreOftenThanTheRisk) {
  Matrix6d c = Matrix6d::Zero();
  c.topLeftCorner<3, 3>().diagonal() << 1.0, 1.0, 1.0;  // the sphere: the bound is exact
  c.bottomRightCorner<3, 3>().diagonal() << 1.0, 0.25, 0.01;
  IntegrityOptions o;
  o.integrity_risk = 1e-2;
  o.overbound_factor = 1.0;
  const ProtectionLevels pl = ComputeProtectionLevels(c, o);
  std::mt19937 rng(7);
  std::normal_distribution<double> n;
  const int draws = 200000;
  int beyond_p = 0, beyond_r = 0;
  for (int i = 0; i < draws; ++i) {
    const Eigen::Vector3d p(n(rng), n(rng), n(rng));
    const Eigen::Vector3d r(n(rng), 0.5 * n(rng), 0.1 * n(rng));
    beyond_p += p.norm() > pl.position_m;
    beyond_r += r.norm() / kDeg > pl.attitude_deg;
  }
  std::printf("[ integrity ] beyond the levels: position %.4f, attitude %.4f of the draws\n",
              static_cast<double>(beyond_p) / draws, static_cast<double>(beyond_r) / draws);
  // Measured: 0.0099 and 0.0009 of the draws.
  EXPECT_NEAR(static_cast<double>(beyond_p) / draws, 1e-2, 1.5e-3);
  EXPECT_LT(static_cast<double>(beyond_r) / draws, 1e-2);
}

TEST(Integrity, TheBandOfARangeIsTheFirstThatReachesIt) {
  const IntegrityOptions o;
  EXPECT_EQ(BandOfRange(o.bands, 35.0).position_m, 0.5);
  EXPECT_EQ(BandOfRange(o.bands, 38.0).position_m, 0.5);
  EXPECT_EQ(BandOfRange(o.bands, 50.0).position_m, 2.0);
  EXPECT_EQ(BandOfRange(o.bands, 500.0).position_m, 10.0);
}

IntegrityInput Frame(TrackOutcome outcome, bool agreeing, double sigma = 0.01) {
  IntegrityInput in;
  in.valid = true;
  in.T_tanker_receiver.translation() << -35.0, 0.0, -10.0;  // 36.5 m: region C
  in.covariance.diagonal() << Eigen::Vector3d::Constant(sigma * sigma),
      Eigen::Vector3d::Constant(std::pow(0.01 * kDeg, 2));
  in.tracking = true;
  in.outcome = outcome;
  in.agreeing = agreeing;
  return in;
}

// A start is in alert until confirm_frames frames in a row agree; a disagreement before then
// starts the count again; once confirmed, a frame that disagrees is no alert by itself.
TEST(Integrity, AStartIsInAlertUntilConfirmed) {
  IntegrityOptions o;
  o.confirm_frames = 3;
  IntegrityMonitor m(o);
  IntegrityResult r = m.Assess(Frame(TrackOutcome::kStarted, true));
  EXPECT_TRUE(r.alert);
  EXPECT_NE(r.reason.find("unconfirmed track: 0 of 3"), std::string::npos) << r.reason;
  EXPECT_TRUE(m.Assess(Frame(TrackOutcome::kAccepted, true)).alert);
  EXPECT_TRUE(m.Assess(Frame(TrackOutcome::kRejected, false)).alert);  // the count starts again
  EXPECT_TRUE(m.Assess(Frame(TrackOutcome::kAccepted, true)).alert);
  EXPECT_TRUE(m.Assess(Frame(TrackOutcome::kAccepted, true)).alert);
  r = m.Assess(Frame(TrackOutcome::kAccepted, true));
  EXPECT_FALSE(r.alert) << r.reason;
  EXPECT_EQ(r.reason, "");
  EXPECT_FALSE(m.Assess(Frame(TrackOutcome::kRejected, false)).alert);
  // A new track starts unconfirmed again.
  EXPECT_TRUE(m.Assess(Frame(TrackOutcome::kStarted, true)).alert);

  o.confirm_frames = 0;  // off: a start is trusted at once
  IntegrityMonitor trusting(o);
  EXPECT_FALSE(trusting.Assess(Frame(TrackOutcome::kStarted, true)).alert);
}

// An unconfirmed track publishes the covariance an acquisition can be off by, and levels from it;
// a confirmed one its own.
TEST(Integrity, AnUnconfirmedTrackCarriesTheAcquisitionsCovariance) {
  IntegrityOptions o;
  o.confirm_frames = 1;
  o.overbound_factor = 1.0;
  IntegrityMonitor m(o);
  IntegrityInput start = Frame(TrackOutcome::kStarted, true);
  start.acquisition_covariance.diagonal() << 4.0, 4.0, 4.0, 0.0025, 0.0025, 0.0025;
  const IntegrityResult unconfirmed = m.Assess(start);
  EXPECT_NEAR(unconfirmed.covariance(0, 0), 4.0 + 1e-4, 1e-12);
  EXPECT_NEAR(unconfirmed.levels.position_m, ProtectionFactor(1e-5) * std::sqrt(4.0001), 1e-9);
  IntegrityInput next = Frame(TrackOutcome::kAccepted, true);
  next.acquisition_covariance = start.acquisition_covariance;
  const IntegrityResult confirmed = m.Assess(next);
  EXPECT_FALSE(confirmed.alert) << confirmed.reason;
  EXPECT_TRUE(confirmed.covariance.isApprox(next.covariance));
}

TEST(Integrity, ALevelBeyondThePhasesLimitIsAnAlertThatSaysSo) {
  IntegrityOptions o;
  o.confirm_frames = 0;
  o.overbound_factor = 1.0;
  IntegrityMonitor m(o);
  // sigma 0.2 m: K(1e-5) 5.09 x 0.2 = 1.02 m > region C's 0.5 m.
  const IntegrityResult r = m.Assess(Frame(TrackOutcome::kAccepted, true, 0.2));
  EXPECT_TRUE(r.alert);
  EXPECT_NE(r.reason.find("position protection level 1.01"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("> alert limit 0.5 m"), std::string::npos) << r.reason;
  EXPECT_EQ(r.limits.position_m, 0.5);
  IntegrityInput none;
  const IntegrityResult missing = m.Assess(none);
  EXPECT_TRUE(missing.alert);
  EXPECT_EQ(missing.reason, "no pose");
}

// A pose turned further from the formation's nominal attitude than the envelope is an alert that
// gives the angle, whatever its covariance says; inside the envelope, or with it off, none.
TEST(Integrity, AnAttitudeOutsideTheFormationsEnvelopeIsAnAlert) {
  IntegrityOptions o;
  o.confirm_frames = 0;
  o.attitude_envelope_deg = 15.0;
  IntegrityMonitor m(o);
  IntegrityInput in = Frame(TrackOutcome::kAccepted, true);
  in.R_tanker_receiver_nominal = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).matrix();
  in.T_tanker_receiver.linear() =
      Eigen::AngleAxisd(0.05 + 28.0 * kDeg, Eigen::Vector3d::UnitY()).matrix();  // nose down
  IntegrityResult r = m.Assess(in);
  EXPECT_TRUE(r.alert);
  EXPECT_NE(r.reason.find("attitude 28 deg from the formation's nominal > envelope 15 deg"),
            std::string::npos)
      << r.reason;
  in.T_tanker_receiver.linear() =
      Eigen::AngleAxisd(0.05 - 14.0 * kDeg, Eigen::Vector3d::UnitY()).matrix();
  r = m.Assess(in);
  EXPECT_FALSE(r.alert) << r.reason;
  EXPECT_EQ(
      OutsideAttitudeEnvelope(Eigen::Matrix3d::Identity(),
                              Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).matrix(), 0.0),
      "");  // off
}

// A band's own overbound factor sets the levels of the poses in it; a band without one takes the
// options'. The same covariance at 36 m (C: 1.65) and at 100 m (A: 5.75, B none: 1.5).
TEST(Integrity, EachPhaseOverboundsWithItsOwnFactor) {
  IntegrityOptions o;
  o.confirm_frames = 0;
  o.overbound_factor = 1.5;
  o.bands[0].overbound_factor = 1.65;
  o.bands[2].overbound_factor = 5.75;
  IntegrityMonitor m(o);
  const double k = ProtectionFactor(1e-5);
  IntegrityInput in = Frame(TrackOutcome::kAccepted, true, 0.01);  // 36.5 m
  EXPECT_NEAR(m.Assess(in).levels.position_m, 1.65 * k * 0.01, 1e-12);
  in.T_tanker_receiver.translation() << -50.0, 0.0, -10.0;  // B
  EXPECT_NEAR(m.Assess(in).levels.position_m, 1.5 * k * 0.01, 1e-12);
  in.T_tanker_receiver.translation() << -100.0, 0.0, -10.0;  // A
  const IntegrityResult far = m.Assess(in);
  EXPECT_NEAR(far.levels.position_m, 5.75 * k * 0.01, 1e-12);
  EXPECT_NEAR(far.levels.attitude_deg, 5.75 * k * 0.01, 1e-9);
  EXPECT_NEAR(ComputeProtectionLevels(in.covariance, o, o.bands[2]).position_m,
              far.levels.position_m, 1e-15);
  o.bands[1].overbound_factor = 0.5;  // below 1 and not 0
  EXPECT_THROW(IntegrityMonitor{o}, std::invalid_argument);
}

TEST(Integrity, BadOptionsAreNamed) {
  IntegrityOptions o;
  o.integrity_risk = 0.0;
  EXPECT_THROW(IntegrityMonitor{o}, std::invalid_argument);
  o = {};
  o.bands = {{70.0, 2.0, 5.0}, {38.0, 0.5, 2.0}};
  try {
    IntegrityMonitor m(o);
    FAIL() << "bands that fall in range were taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("alert bands must rise in range"), std::string::npos);
  }
  o = {};
  o.overbound_factor = 0.5;
  EXPECT_THROW(IntegrityMonitor{o}, std::invalid_argument);
  o = {};
  o.attitude_envelope_deg = -1.0;
  EXPECT_THROW(IntegrityMonitor{o}, std::invalid_argument);
}

}  // namespace
}  // namespace aar_registration
