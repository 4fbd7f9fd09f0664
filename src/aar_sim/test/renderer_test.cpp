#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <aar_geometry/primitives.h>
#include <aar_geometry/weld.h>

#include <aar_description/boom_model.h>
#include <ros/package.h>

#include "aar_sim/world.h"

namespace aar_sim {

using aar_description::DefaultBoomPose;
namespace {

WorldOptions TestWorld(bool boom_visible, double noise = 0.0) {
  WorldOptions o = DefaultWorldOptions(ros::package::getPath("aar_description") + "/models");
  o.rig = MakeStereoRig(CameraIntrinsics::FromHorizontalFov(640, 480, 60.0), 0.5);
  o.sensor.noise_stddev = noise;
  o.boom_visible = boom_visible;
  return o;
}

FlightPathRow Receiver(double x, double y, double z, double yaw_deg) {
  FlightPathRow row;
  row.position_m = {x, y, z};
  row.rpy = {0.0, aar_geometry::DegToRad(-2.0), aar_geometry::DegToRad(yaw_deg)};
  return row;
}

// The receiver's vertices projected with the camera model land on receiver pixels of the label
// image, and the label's extent matches their extent within 2 px. Vertices are checked where the
// geometry is resolvable: a vertex of a triangle whose projection is at least 1 px thick (a tail
// seen edge-on at 150 m is thinner than a pixel and covers no pixel centre, as GL specifies).
// Two renders of the same inputs: the same images, left label and left depth, bit for bit.
void ExpectSameFrame(const StereoFrame& a, const StereoFrame& b) {
  EXPECT_EQ(a.left.image.data, b.left.image.data);
  EXPECT_EQ(a.right.image.data, b.right.image.data);
  EXPECT_EQ(a.left.label.data, b.left.label.data);
  EXPECT_EQ(a.left.depth.data, b.left.depth.data);
}

void CheckProjection(World& world, const FlightPathRow& row, int min_checked) {
  const StereoFrame frame = world.Render(row, DefaultBoomPose(), 0, true, true);
  const StereoRig& rig = world.options().rig;
  const CameraIntrinsics& k = rig.intrinsics;
  const aar_geometry::TriangleMesh& mesh = world.receiver_mesh();
  for (int camera = 0; camera < 2; ++camera) {
    SCOPED_TRACE(camera == 0 ? "left" : "right");
    const RenderedView& view = camera == 0 ? frame.left : frame.right;
    const Eigen::Isometry3d T_optical_receiver =
        (camera == 0 ? rig.T_tanker_left_optical : rig.T_tanker_right_optical()).inverse() *
        frame.T_tanker_receiver;
    std::vector<Eigen::Vector2d> px(mesh.vertices.size());
    double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      px[i] = k.Project(T_optical_receiver * mesh.vertices[i]);
      umin = std::min(umin, px[i].x()), umax = std::max(umax, px[i].x());
      vmin = std::min(vmin, px[i].y()), vmax = std::max(vmax, px[i].y());
    }
    std::vector<bool> resolvable(mesh.vertices.size(), false);
    for (const auto& t : mesh.triangles) {
      const Eigen::Vector2d a = px[t[1]] - px[t[0]], b = px[t[2]] - px[t[0]],
                            c = px[t[2]] - px[t[1]];
      const double longest = std::max({a.norm(), b.norm(), c.norm()});
      const double thickness =
          std::abs(a.x() * b.y() - a.y() * b.x()) / longest;  // smallest altitude
      if (thickness >= 1.0) resolvable[t[0]] = resolvable[t[1]] = resolvable[t[2]] = true;
    }
    int checked = 0, off_receiver = 0;
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      const int u = static_cast<int>(std::lround(px[i].x())),
                w = static_cast<int>(std::lround(px[i].y()));
      if (!resolvable[i] || u < 1 || w < 1 || u >= k.width - 1 || w >= k.height - 1) continue;
      ++checked;
      bool hit = false;  // a vertex on a silhouette may fall half a pixel outside the raster
      for (int du = -1; du <= 1; ++du)
        for (int dv = -1; dv <= 1; ++dv)
          hit |= view.label.at(u + du, w + dv) == static_cast<uint8_t>(Label::kReceiver);
      off_receiver += !hit;
    }
    EXPECT_GE(checked, min_checked);
    EXPECT_EQ(off_receiver, 0) << "of " << checked << " vertices";
    std::printf("[ projection ] range %.0f m, %s camera: %d resolvable vertices checked\n",
                row.position_m.norm(), camera == 0 ? "left" : "right", checked);
    int lumin = k.width, lumax = -1, lvmin = k.height, lvmax = -1;
    for (int w = 0; w < k.height; ++w)
      for (int u = 0; u < k.width; ++u)
        if (view.label.at(u, w) == static_cast<uint8_t>(Label::kReceiver)) {
          lumin = std::min(lumin, u), lumax = std::max(lumax, u);
          lvmin = std::min(lvmin, w), lvmax = std::max(lvmax, w);
          EXPECT_GT(view.depth.at(u, w), 0.0f);
        }
    EXPECT_NEAR(lumin, umin, 2.0);
    EXPECT_NEAR(lumax, umax, 2.0);
    EXPECT_NEAR(lvmin, vmin, 2.0);
    EXPECT_NEAR(lvmax, vmax, 2.0);
  }
}

TEST(Renderer, LabelMatchesProjectedVerticesNearAndFar) {
  WorldOptions options = DefaultWorldOptions(ros::package::getPath("aar_description") + "/models");
  options.boom_visible = false;
  World world(options);
  CheckProjection(world, Receiver(-36.0, 0.0, -10.5, 0.0), 5000);
  CheckProjection(world, Receiver(-60.0, 3.0, -18.0, 8.0), 1000);
  CheckProjection(world, Receiver(-150.0, -4.0, -40.0, -5.0), 10);
}

TEST(Renderer, DepthIsOpticalZ) {
  World world(TestWorld(false));
  const FlightPathRow row = Receiver(-40.0, 0.0, -12.0, 0.0);
  const StereoFrame frame = world.Render(row, DefaultBoomPose(), 0, true, true);
  // The nose tip is the receiver's point nearest to the camera along its line of sight: the
  // depth at its pixel is within 5 cm of its optical z.
  const Eigen::Vector3d nose = world.options().rig.T_tanker_left_optical.inverse() *
                               frame.T_tanker_receiver * Eigen::Vector3d(5.98, 0.0, -0.1);
  const Eigen::Vector2d px = world.options().rig.intrinsics.Project(nose);
  EXPECT_NEAR(frame.left.depth.at(std::lround(px.x()), std::lround(px.y())), nose.z(), 0.05);
  EXPECT_EQ(frame.left.depth.at(0, world.options().rig.intrinsics.height - 1), 0.0f);  // sky
}

// Raw cameras: the world renders a view grown by the lenses' margins; the rectified views it
// returns are the pinhole world's (same size, same pixels within the renderer's rounding), and
// rectifying its raw images as image_proc does (cv::initUndistortRectifyMap) gives them back.
TEST(Renderer, RawCamerasSeeTheRectifiedViewThroughTheirLenses) {
  WorldOptions raw_options = TestWorld(true);
  raw_options.raw = DefaultRawCameraOptions();
  raw_options.raw.enabled = true;
  World pinhole(TestWorld(true)), raw(raw_options);
  ASSERT_NE(raw.raw_left(), nullptr);
  EXPECT_EQ(pinhole.raw_left(), nullptr);
  EXPECT_GT(raw.raw_left()->margin_x(), 40);  // [px] measured 60 at 640x480
  const FlightPathRow row = Receiver(-45.0, 1.0, -13.0, 3.0);
  const StereoFrame a = pinhole.Render(row, DefaultBoomPose(), 3, true, false);
  const StereoFrame b = raw.Render(row, DefaultBoomPose(), 3, true, false);
  ASSERT_EQ(b.left.image.width, 640);
  ASSERT_EQ(b.left.image.height, 480);
  ASSERT_EQ(b.left_raw.width, 640);
  ASSERT_EQ(b.left.label.width, 640);
  EXPECT_TRUE(a.left_raw.data.empty());
  for (int camera = 0; camera < 2; ++camera) {
    SCOPED_TRACE(camera == 0 ? "left" : "right");
    const Image<uint8_t>& ideal = camera == 0 ? a.left.image : a.right.image;
    const Image<uint8_t>& grown = camera == 0 ? b.left.image : b.right.image;
    const Image<uint8_t>& raw_image = camera == 0 ? b.left_raw : b.right_raw;
    const RawCamera& cam = camera == 0 ? *raw.raw_left() : *raw.raw_right();
    double same = 0.0, back = 0.0;
    int n = 0;
    cv::Matx33d K(cam.K().fx, 0, cam.K().cx, 0, cam.K().fy, cam.K().cy, 0, 0, 1), R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R(i, j) = cam.R_rect_raw()(i, j);
    cv::Mat D(1, 5, CV_64F, const_cast<double*>(cam.D().data())), m1, m2, rect;
    cv::initUndistortRectifyMap(K, D, R, K, cv::Size(640, 480), CV_16SC2, m1, m2);
    cv::remap(cv::Mat(480, 640, CV_8UC1, const_cast<uint8_t*>(raw_image.data.data())), rect, m1, m2,
              cv::INTER_LINEAR);
    for (int v = 10; v < 470; ++v) {
      for (int u = 10; u < 630; ++u, ++n) {
        same += std::abs(grown.at(u, v) - ideal.at(u, v));
        back += std::abs(rect.at<uint8_t>(v, u) - ideal.at(u, v));
      }
    }
    EXPECT_LT(same / n, 0.01);  // [grey levels] measured 2.8e-5 (left), 1.4e-5 (right)
    EXPECT_LT(back / n, 0.6);   // [grey levels] two interpolations at edges; measured 0.38
  }
  // A lens no calibration would give is refused before rendering, naming the camera's keys.
  WorldOptions folding = raw_options;
  folding.raw.right.distortion = {-3.0, 0.0, 0.0, 0.0, 0.0};
  try {
    World bad(folding);
    ADD_FAILURE() << "a folding lens was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("right camera (right_distortion, right_rotation_deg): "
                                         "lens distortion folds"),
              std::string::npos)
        << e.what();
  }
}

TEST(Renderer, SameFrameTwiceIsBitIdentical) {
  World world(TestWorld(true, 2.0));
  const FlightPathRow row = Receiver(-45.0, 1.0, -13.0, 3.0);
  const StereoFrame a = world.Render(row, DefaultBoomPose(), 17, true, true);
  const StereoFrame b = world.Render(row, DefaultBoomPose(), 17, true, true);
  ExpectSameFrame(a, b);
  // A second world (a fresh context) renders the same bits too.
  World other(TestWorld(true, 2.0));
  EXPECT_EQ(other.Render(row, DefaultBoomPose(), 17).left.image.data, a.left.image.data);
  // Another frame index draws other noise; the noise has the configured spread.
  const StereoFrame c = world.Render(row, DefaultBoomPose(), 18);
  ASSERT_NE(c.left.image.data, a.left.image.data);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (size_t i = 0; i < a.left.image.data.size(); ++i) {
    if (a.left.label.data[i] != static_cast<uint8_t>(Label::kBackground)) continue;  // flat sky
    const double d = static_cast<double>(a.left.image.data[i]) - c.left.image.data[i];
    sum += d, sum2 += d * d, ++n;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n - (sum / n) * (sum / n)), 2.0 * std::sqrt(2.0), 0.1);
}

TEST(Renderer, BoomOccludesAndIsLabelled) {
  World with(TestWorld(true)), without(TestWorld(false));
  const FlightPathRow row = Receiver(-35.0, 0.0, -10.3, 0.0);
  const StereoFrame a = with.Render(row, DefaultBoomPose(), 0, true);
  const StereoFrame b = without.Render(row, DefaultBoomPose(), 0, true);
  auto count = [](const Image<uint8_t>& label, Label l) {
    return std::count(label.data.begin(), label.data.end(), static_cast<uint8_t>(l));
  };
  EXPECT_GT(count(a.left.label, Label::kBoom), 1000);
  EXPECT_EQ(count(b.left.label, Label::kBoom), 0);
  EXPECT_LT(count(a.left.label, Label::kReceiver), count(b.left.label, Label::kReceiver));
}

// Visibility: the receiver drawn alone is the boomless scene's receiver, and what the boom
// leaves of it is the receiver's pixels in the scene with the boom. Raw cameras count in the
// rectified view as the pinhole world does.
TEST(Renderer, VisibilityCountsWhatTheBoomLeavesOfTheReceiver) {
  WorldOptions raw_options = TestWorld(true);
  raw_options.raw = DefaultRawCameraOptions();
  raw_options.raw.enabled = true;
  World with(TestWorld(true)), without(TestWorld(false)), raw(raw_options);
  const FlightPathRow row = Receiver(-35.0, 0.0, -10.3, 0.0);
  const StereoFrame a = with.Render(row, DefaultBoomPose(), 0, true);
  const StereoFrame b = without.Render(row, DefaultBoomPose(), 0, true);
  auto count = [](const Image<uint8_t>& label, Label l) {
    return static_cast<int>(std::count(label.data.begin(), label.data.end(), uint8_t(l)));
  };
  const std::array<ViewVisibility, 2> seen = with.MeasureVisibility(a);
  EXPECT_EQ(seen[0].silhouette_px, count(b.left.label, Label::kReceiver));
  EXPECT_EQ(seen[1].silhouette_px, count(b.right.label, Label::kReceiver));
  EXPECT_EQ(seen[0].visible_px, count(a.left.label, Label::kReceiver));
  EXPECT_EQ(seen[1].visible_px, count(a.right.label, Label::kReceiver));
  // Near contact the boom's tube covers the fuselage's nose: measured 0.963 of it left.
  EXPECT_LT(seen[0].fraction(), 0.97);
  EXPECT_GT(seen[0].fraction(), 0.955);
  const std::array<ViewVisibility, 2> bare = without.MeasureVisibility(b);
  EXPECT_EQ(bare[0].fraction(), 1.0);
  EXPECT_EQ(bare[1].visible_px, bare[1].silhouette_px);
  const std::array<ViewVisibility, 2> through_lenses =
      raw.MeasureVisibility(raw.Render(row, DefaultBoomPose(), 0, true));
  EXPECT_NEAR(through_lenses[0].silhouette_px, seen[0].silhouette_px, 0.01 * seen[0].silhouette_px);
  // Out of view: no silhouette, no fraction. Without the label: named.
  const StereoFrame behind =
      with.Render(Receiver(35.0, 0.0, -10.0, 0.0), DefaultBoomPose(), 0, true);
  EXPECT_EQ(with.MeasureVisibility(behind)[0].silhouette_px, 0);
  EXPECT_TRUE(std::isnan(with.MeasureVisibility(behind)[0].fraction()));
  try {
    with.MeasureVisibility(with.Render(row, DefaultBoomPose(), 0));
    ADD_FAILURE() << "a frame without its label was measured";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("want_label"), std::string::npos) << e.what();
  }
}

// A mount measured before it flies (tools/mount_visibility): from the world's own rig it is the
// rendered frame's visibility, from another rig that of a world built with that rig. Far out on
// the boom's other side (y < 0), the boom hides more of the receiver from the default mount (1 m
// left of the boom's plane) than from its mirror image (1 m right).
TEST(Renderer, VisibilityFromAnotherRigIsThatOfAWorldWithIt) {
  World world(TestWorld(true));
  const FlightPathRow row = Receiver(-140.0, -10.0, -35.0, 0.0);
  auto expect_same = [](const std::array<ViewVisibility, 2>& a,
                        const std::array<ViewVisibility, 2>& b) {
    for (int camera = 0; camera < 2; ++camera) {
      EXPECT_EQ(a[camera].silhouette_px, b[camera].silhouette_px) << camera;
      EXPECT_EQ(a[camera].visible_px, b[camera].visible_px) << camera;
    }
  };
  const auto own = world.MeasureVisibility(world.Render(row, DefaultBoomPose(), 0, true));
  expect_same(world.MeasureVisibility(row, DefaultBoomPose(), world.options().rig), own);
  WorldOptions mirrored = TestWorld(true);
  mirrored.rig = MakeStereoRig(mirrored.rig.intrinsics, 0.5, {-20.0, -1.0, -3.0});
  World there(mirrored);
  const auto theirs = there.MeasureVisibility(there.Render(row, DefaultBoomPose(), 0, true));
  const auto measured = world.MeasureVisibility(row, DefaultBoomPose(), mirrored.rig);
  expect_same(measured, theirs);
  std::printf("[ visibility ] default %.3f %.3f, mirrored %.3f %.3f\n", own[0].fraction(),
              own[1].fraction(), measured[0].fraction(), measured[1].fraction());
  // The weaker camera: measured 0.193 from the default mount, 0.768 from its mirror image.
  EXPECT_LT(std::min(own[0].fraction(), own[1].fraction()), 0.21);
  EXPECT_GT(std::min(measured[0].fraction(), measured[1].fraction()), 0.75);
  StereoRig other_lens = mirrored.rig;
  other_lens.intrinsics = CameraIntrinsics::FromHorizontalFov(640, 480, 50.0);
  EXPECT_THROW(world.MeasureVisibility(row, DefaultBoomPose(), other_lens), std::invalid_argument);
}

// A second rig (World::RenderRig) renders what a world built with that rig renders, on a noise
// stream of its own: with stream 0 (the world's own rig's) its images are that world's bit for
// bit, with stream 1 the same labels and other noise.
TEST(Renderer, ASecondRigRendersWhatAWorldWithItDoes) {
  const WorldOptions o = TestWorld(true, 2.0);
  WorldOptions mirrored = o;
  mirrored.rig = MakeStereoRig(o.rig.intrinsics, 0.5, {-15.0, -1.0, -4.0});
  World world(o), there(mirrored);
  const FlightPathRow row = Receiver(-60.0, -3.0, -18.0, 0.0);
  const StereoFrame theirs = there.Render(row, DefaultBoomPose(), 3, true);
  ExpectSameFrame(world.RenderRig(mirrored.rig, 0, row, DefaultBoomPose(), 3, true), theirs);
  const StereoFrame own = world.RenderRig(mirrored.rig, 1, row, DefaultBoomPose(), 3, true);
  EXPECT_EQ(own.left.label.data, theirs.left.label.data);
  EXPECT_NE(own.left.image.data, theirs.left.image.data);
  ExpectSameFrame(world.Render(row, DefaultBoomPose(), 3, true),
                  world.RenderRig(o.rig, 0, row, DefaultBoomPose(), 3, true));
  StereoRig other_lens = mirrored.rig;
  other_lens.intrinsics = CameraIntrinsics::FromHorizontalFov(640, 480, 50.0);
  EXPECT_THROW(world.RenderRig(other_lens, 1, row, DefaultBoomPose(), 3), std::invalid_argument);
}

// The label-only render leaves nothing behind: in a world with the sun's shadows, a background
// and propellers, the frame rendered after a visibility measure is the frame before, bit for bit.
// The propellers' discs are the receiver's: visible, not hidden.
TEST(Renderer, VisibilityLeavesTheNextFrameAlone) {
  WorldOptions o = TestWorld(true);
  o.renderer.sun.enabled = true;
  o.renderer.scene.background = Background::kSea;
  o.propellers = PropellerMode::kDisc;
  World world(o);
  const FlightPathRow row = Receiver(-35.0, 0.0, -10.3, 0.0);
  const StereoFrame a = world.Render(row, DefaultBoomPose(), 0, true, true);
  const std::array<ViewVisibility, 2> seen = world.MeasureVisibility(a);
  ExpectSameFrame(a, world.Render(row, DefaultBoomPose(), 0, true, true));
  const auto propeller = std::count(a.left.label.data.begin(), a.left.label.data.end(),
                                    static_cast<uint8_t>(Label::kPropeller));
  ASSERT_GT(propeller, 0);
  EXPECT_GE(seen[0].visible_px, std::count(a.left.label.data.begin(), a.left.label.data.end(),
                                           static_cast<uint8_t>(Label::kReceiver)));
}

TEST(Renderer, BoomPoseFromThePathMovesTheBoom) {
  World world(TestWorld(true));
  const FlightPathRow row = Receiver(-60.0, 0.0, -18.0, 0.0);
  BoomPose swung = DefaultBoomPose();
  swung.roll = aar_geometry::DegToRad(10.0);
  swung.pitch = aar_geometry::DegToRad(36.0);
  swung.extension = 4.0;
  const StereoFrame a = world.Render(row, DefaultBoomPose(), 0, true);
  const StereoFrame b = world.Render(row, swung, 0, true);
  EXPECT_GT((b.T_tanker_links.at("nozzle_tip").translation() -
             a.T_tanker_links.at("nozzle_tip").translation())
                .norm(),
            3.0);
  // The boom's pixels follow: the nozzle's new projection is a boom pixel, the old one is not.
  const StereoRig& rig = world.options().rig;
  for (const auto* frame : {&a, &b}) {
    const Eigen::Vector3d tip = rig.T_tanker_left_optical.inverse() *
                                frame->T_tanker_links.at("nozzle_tip") * Eigen::Vector3d(0.1, 0, 0);
    const Eigen::Vector2d px = rig.intrinsics.Project(tip);
    const uint8_t label_here = frame->left.label.at(std::lround(px.x()), std::lround(px.y()));
    const uint8_t label_other =
        (frame == &a ? b : a).left.label.at(std::lround(px.x()), std::lround(px.y()));
    EXPECT_EQ(label_here, static_cast<uint8_t>(Label::kBoom));
    EXPECT_NE(label_other, static_cast<uint8_t>(Label::kBoom));
  }
}

TEST(Renderer, RightCameraSeesTheSceneShiftedByTheDisparity) {
  World world(TestWorld(false));
  const FlightPathRow row = Receiver(-40.0, 0.0, -12.0, 0.0);
  const StereoFrame frame = world.Render(row, DefaultBoomPose(), 0, true, true);
  // Rectified pair: a point at depth z appears f * b / z pixels further left in the right image,
  // on the same row.
  const StereoRig& rig = world.options().rig;
  const Eigen::Vector3d p =
      rig.T_tanker_left_optical.inverse() * frame.T_tanker_receiver * Eigen::Vector3d(0, 0, 0.9);
  const Eigen::Vector2d left = rig.intrinsics.Project(p);
  const Eigen::Vector2d right = rig.intrinsics.Project(rig.T_tanker_right_optical().inverse() *
                                                       rig.T_tanker_left_optical * p);
  EXPECT_NEAR(left.y(), right.y(), 1e-9);
  EXPECT_NEAR(left.x() - right.x(), rig.intrinsics.fx * rig.baseline / p.z(), 1e-9);
}

TEST(Renderer, TwoRenderersLiveSideBySide) {
  // Destroying one must not break the other (they share the process's EGL display).
  RendererOptions o;
  o.intrinsics = CameraIntrinsics::FromHorizontalFov(64, 48, 60.0);
  auto first = std::make_unique<Renderer>(o);
  Renderer second(o);
  const int box =
      second.AddMesh(aar_geometry::MakeBox({1, 1, 1}), Label::kReceiver, Surface::kAircraftPaint);
  first.reset();
  Eigen::Isometry3d T_object = Eigen::Isometry3d::Identity();
  T_object.translation() << 0, 0, 5;  // in front of a camera at the origin looking along z
  const RenderedView view =
      second.Render(Eigen::Isometry3d::Identity(), {{box, T_object}}, true, false);
  EXPECT_EQ(view.label.at(32, 24), static_cast<uint8_t>(Label::kReceiver));
}

TEST(Renderer, MissingModelsAndBadIntrinsicsFailClearly) {
  WorldOptions o = TestWorld(true);
  o.receiver.mesh = "/nonexistent/receiver.obj";
  try {
    World world(o);
    ADD_FAILURE();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/receiver.obj"), std::string::npos)
        << e.what();
  }
  RendererOptions bad;
  bad.intrinsics.width = 0;
  EXPECT_THROW(Renderer{bad}, RenderError);
}

// The GLSL is read from files at construction: a missing one is named in the error.
TEST(Renderer, MissingShaderFileIsNamed) {
  const char* previous = std::getenv("AAR_SIM_SHADER_DIR");
  const std::string saved = previous ? previous : "";
  setenv("AAR_SIM_SHADER_DIR", "/nonexistent/shaders", 1);
  RendererOptions o;
  o.intrinsics = CameraIntrinsics::FromHorizontalFov(64, 48, 60.0);
  try {
    Renderer renderer(o);
    ADD_FAILURE() << "no error without shader files";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/shaders/mesh_vertex.glsl"),
              std::string::npos)
        << e.what();
  }
  if (previous) {
    setenv("AAR_SIM_SHADER_DIR", saved.c_str(), 1);
  } else {
    unsetenv("AAR_SIM_SHADER_DIR");
  }
}

// Issue 16 background: the lower part of the view (the camera looks 25 deg down) is ground or
// cloud, labelled and with the optical z of the plane it hits; the same inputs give the same bits;
// the sky above the horizon stays the plain sky; no cloud nearer than cloud_min_range.
TEST(Renderer, BackgroundIsLabelledDeterministicAndAtItsDepth) {
  WorldOptions o = TestWorld(true);
  o.renderer.scene.background = Background::kTerrain;
  o.renderer.scene.cloud_coverage = 0.5;
  o.renderer.scene.cloud_min_range_m = 0.0;
  World world(o);
  const FlightPathRow row = Receiver(-45.0, 1.0, -13.0, 3.0);
  const StereoFrame a = world.Render(row, DefaultBoomPose(), 3, true, true);
  const StereoFrame b = world.Render(row, DefaultBoomPose(), 3, true, true);
  ExpectSameFrame(a, b);

  const StereoRig& rig = world.options().rig;
  const CameraIntrinsics& k = rig.intrinsics;
  const SceneOptions& sc = o.renderer.scene;
  int ground = 0, cloud = 0, sky = 0, checked = 0;
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const auto label = static_cast<Label>(a.left.label.at(u, v));
      const Eigen::Vector3d d = rig.T_tanker_left_optical.linear() *
                                Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const Eigen::Vector3d c = rig.T_tanker_left_optical.translation();
      if (label == Label::kBackground) {
        ++sky;
        EXPECT_GE(d.z(), -1e-5) << u << "," << v;  // empty sky only above the horizon
        EXPECT_EQ(a.left.image.at(u, v), 200);
        continue;
      }
      if (label != Label::kGround && label != Label::kCloud) continue;
      ASSERT_LT(d.z(), 0.0) << u << "," << v;
      const double plane =
          label == Label::kGround ? -sc.background_altitude_m : -sc.cloud_altitude_m;
      const double z = (plane - c.z()) / d.z();
      EXPECT_NEAR(a.left.depth.at(u, v), z, 1e-3 * z) << u << "," << v;
      ++checked;
      (label == Label::kGround ? ground : cloud)++;
    }
  }
  // Bottom row: all background classes or the aircraft, never empty sky.
  for (int u = 0; u < k.width; ++u) EXPECT_NE(a.left.label.at(u, k.height - 1), 0) << u;
  EXPECT_GT(ground, 10000) << cloud << " " << sky;
  EXPECT_GT(cloud, 10000) << ground << " " << sky;

  // Clouds only beyond their minimum range: a range beyond the view leaves none.
  o.renderer.scene.cloud_min_range_m = 1e6;
  World far(o);
  const StereoFrame f = far.Render(row, DefaultBoomPose(), 3, true, false);
  EXPECT_EQ(std::count(f.left.label.data.begin(), f.left.label.data.end(),
                       static_cast<uint8_t>(Label::kCloud)),
            0);
}

// With the background off (the default), nothing of it is drawn: only sky, receiver and boom.
TEST(Renderer, BackgroundOffDrawsOnlyThePlainSky) {
  WorldOptions o = TestWorld(true);
  o.renderer.scene.cloud_coverage = 0.7;  // ignored without a background
  World world(o), plain(TestWorld(true));
  const FlightPathRow row = Receiver(-45.0, 1.0, -13.0, 3.0);
  const StereoFrame a = world.Render(row, DefaultBoomPose(), 3, true, true);
  const StereoFrame b = plain.Render(row, DefaultBoomPose(), 3, true, true);
  EXPECT_EQ(a.left.image.data, b.left.image.data);
  for (uint8_t l : a.left.label.data) ASSERT_LE(l, static_cast<uint8_t>(Label::kBoom));
}

TEST(Renderer, BadBackgroundOptionsAreRefused) {
  WorldOptions o = TestWorld(true);
  o.renderer.scene.background = Background::kSea;
  o.renderer.scene.cloud_altitude_m = 4000.0;  // below the sea
  try {
    World world(o);
    FAIL() << "cloud layer below the ground accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("cloud_altitude"), std::string::npos) << e.what();
  }
}

// Issue 16 sun: the boom's cast shadow on the receiver near contact. Pixels that show the
// receiver with and without the boom drawn, and that the boom's presence darkens to below 60 %, can
// only be in its shadow; there are many with shadows on and none with them off.
int PixelsShadowedByTheBoom(bool shadows, double* darkest = nullptr) {
  WorldOptions o = TestWorld(true);
  o.renderer.sun.enabled = true;
  o.renderer.sun.shadows = shadows;
  WorldOptions no_boom = o;
  no_boom.boom_visible = false;
  World with(o), without(no_boom);
  const FlightPathRow row = Receiver(-35.0, 0.0, -10.3, 0.0);
  const StereoFrame a = with.Render(row, DefaultBoomPose(), 0, true, false);
  const StereoFrame b = without.Render(row, DefaultBoomPose(), 0, true, false);
  int shadowed = 0;
  double ratio_min = 1.0;
  for (size_t i = 0; i < a.left.radiance.data.size(); ++i) {
    const auto receiver = static_cast<uint8_t>(Label::kReceiver);
    if (a.left.label.data[i] != receiver || b.left.label.data[i] != receiver) continue;
    const double ratio = a.left.radiance.data[i] / std::max(b.left.radiance.data[i], 1e-6f);
    ratio_min = std::min(ratio_min, ratio);
    shadowed += ratio < 0.6;
  }
  if (darkest) *darkest = ratio_min;
  return shadowed;
}

TEST(Sun, TheBoomCastsItsShadowOnTheReceiver) {
  double darkest = 1.0;
  const int shadowed = PixelsShadowedByTheBoom(true, &darkest);
  std::printf("[ sun ] receiver pixels in the boom's shadow: %d (darkest at %.2f of sunlit)\n",
              shadowed, darkest);
  EXPECT_GT(shadowed, 1200);  // measured 1332 (640x480)
  EXPECT_LT(darkest, 0.3);    // measured 0.26: skylight only, ambient / (ambient + direct cos)
  EXPECT_EQ(PixelsShadowedByTheBoom(false), 0);
}

// Glare: with the sun behind the tanker and 60 deg high the windscreen mirrors it towards the
// cameras: its facets saturate (radiance above 1, clipped white by the sensor); without the
// glass's specular they do not. (No boom: near contact its shadow lies on the windscreen then.)
TEST(Sun, TheWindscreenGlaresAndTheSunIsBitIdentical) {
  WorldOptions o = TestWorld(false);
  o.renderer.sun.enabled = true;
  o.renderer.sun.azimuth_deg = 180.0;
  o.renderer.sun.elevation_deg = 60.0;
  auto saturated = [](const StereoFrame& f) {
    int n = 0;
    for (size_t i = 0; i < f.left.radiance.data.size(); ++i)
      n += f.left.label.data[i] == static_cast<uint8_t>(Label::kReceiver) &&
           f.left.radiance.data[i] > 1.0f;
    return n;
  };
  const FlightPathRow row = Receiver(-35.0, 0.0, -10.3, 0.0);
  World world(o);
  const StereoFrame a = world.Render(row, DefaultBoomPose(), 0, true, true);
  o.renderer.sun.glass_specular = 0.0;
  World matte(o);
  const StereoFrame m = matte.Render(row, DefaultBoomPose(), 0, true, true);
  std::printf("[ sun ] saturated receiver pixels: %d with glass glare, %d without\n", saturated(a),
              saturated(m));
  EXPECT_GT(saturated(a), saturated(m) + 130);  // measured 154 and 0
  ExpectSameFrame(a, world.Render(row, DefaultBoomPose(), 0, true, true));
  // The sun changes the image; below the horizon it is refused, naming the key.
  EXPECT_NE(a.left.image.data,
            World(TestWorld(false)).Render(row, DefaultBoomPose(), 0).left.image.data);
  o.renderer.sun.elevation_deg = -10.0;
  try {
    World below(o);
    ADD_FAILURE() << "a sun below the horizon was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sun_elevation_deg"), std::string::npos) << e.what();
  }
}

// Issue 16 propellers: labelled, turning with path time, smeared over the exposure.
TEST(Propellers, LabelledTurningAndSmearedOverTheExposure) {
  WorldOptions o = TestWorld(true);
  const FlightPathRow row = Receiver(-40.0, 0.0, -11.0, 0.0);
  auto count = [](const StereoFrame& f) {
    return std::count(f.left.label.data.begin(), f.left.label.data.end(),
                      static_cast<uint8_t>(Label::kPropeller));
  };
  World none(o);
  const StereoFrame bare = none.Render(row, DefaultBoomPose(), 0, true, false);
  EXPECT_EQ(count(bare), 0);
  o.propellers = PropellerMode::kBlades;
  World sharp(o);
  const StereoFrame a = sharp.Render(row, DefaultBoomPose(), 0, true, false);
  FlightPathRow later = row;
  later.t += 0.004;  // 41 deg of turn at 1700 rpm
  const StereoFrame b = sharp.Render(later, DefaultBoomPose(), 0, true, false);
  ExpectSameFrame(a, sharp.Render(row, DefaultBoomPose(), 0, true, false));
  EXPECT_GT(count(a), 1100);  // measured 1270
  EXPECT_NE(a.left.label.data, b.left.label.data);
  // Pixels the propellers change: a blade's width frozen, its sweep over a 2 ms exposure
  // smeared, the whole disc fully blurred.
  auto touched = [&](const StereoFrame& f) {
    int n = 0;
    for (size_t i = 0; i < f.left.radiance.data.size(); ++i)
      n += f.left.radiance.data[i] != bare.left.radiance.data[i];
    return n;
  };
  o.sensor.motion_blur = true;
  o.sensor.exposure_time = 0.002;
  World smeared(o);
  o.propellers = PropellerMode::kDisc;
  World disc(o);
  const StereoFrame s = smeared.Render(row, DefaultBoomPose(), 0, true, false);
  const StereoFrame d = disc.Render(row, DefaultBoomPose(), 0, true, false);
  std::printf(
      "[ propellers ] pixels labelled %ld sharp, %ld smeared, %ld disc; changed %d, %d, %d\n",
      static_cast<long>(count(a)), static_cast<long>(count(s)), static_cast<long>(count(d)),
      touched(a), touched(s), touched(d));
  EXPECT_GT(touched(s), 2.2 * touched(a));  // measured 3048 against 1270 (x2.40)
  EXPECT_GT(touched(d), 2.4 * touched(s));  // measured 7880 (x2.59)
  EXPECT_LT(count(s), count(a));  // smeared thin: fewer pixels covered half the exposure (977)
}

// Every issue-16 effect at once (config/realism/realistic.yaml's values): the same inputs and
// seed give the same bits, in this world and in a fresh one; another seed gives other noise.
TEST(Realism, EveryEffectOnIsBitIdenticalForTheSameSeed) {
  WorldOptions o = TestWorld(true, 2.0);
  o.renderer.scene.background = Background::kTerrain;
  o.renderer.scene.cloud_coverage = 0.4;
  o.renderer.sun.enabled = true;
  o.propellers = PropellerMode::kBlades;
  SensorOptions& s = o.sensor;
  s.full_well = 10000.0;
  s.motion_blur = true;
  s.gain_mismatch = 0.03;
  s.auto_exposure = true;
  World world(o);
  const FlightPathRow row = Receiver(-45.0, 1.0, -13.0, 3.0);
  FlightPathRow end = row;
  end.t += s.exposure_time;
  end.position_m.x() += 0.01;
  const SceneState exposure_end{end, DefaultBoomPose()};
  const StereoFrame a = world.Render(row, DefaultBoomPose(), 5, true, true, &exposure_end);
  ExpectSameFrame(a, world.Render(row, DefaultBoomPose(), 5, true, true, &exposure_end));
  World fresh(o);
  ExpectSameFrame(a, fresh.Render(row, DefaultBoomPose(), 5, true, true, &exposure_end));
  o.sensor.noise_seed = 2;
  World other(o);
  EXPECT_NE(a.left.image.data,
            other.Render(row, DefaultBoomPose(), 5, true, true, &exposure_end).left.image.data);
}

}  // namespace
}  // namespace aar_sim
