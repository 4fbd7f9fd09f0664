// bench_icp: ICP time per frame, iterations and pose error against range, aar_registration's
// point-to-point ICP side by side with PCL's IterativeClosestPoint, on the same sensed clouds:
// simulated frames of the default approach (boom hidden) through aar_stereo's thesis settings,
// registered against the shelled reference model from the thesis's centroid seed.
//   bench_icp [FRAMES] [REPEATS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include <pcl/point_types.h>
#include <pcl/registration/icp.h>

#include <aar_description/boom_model.h>
#include <aar_geometry/pose_error.h>
#include <aar_geometry/receiver_reference.h>
#include <aar_registration/icp.h>
#include <aar_testing/sim_stereo.h>
#include <aar_testing/timing.h>

namespace {

using Clock = std::chrono::steady_clock;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// PCL keeps its iteration count protected.
struct PclIcp : pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> {
  int iterations() const { return nr_iterations_; }
};

Cloud::Ptr ToPcl(const std::vector<Eigen::Vector3d>& points) {
  Cloud::Ptr cloud(new Cloud);
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  return cloud;
}

void PrintError(const Eigen::Isometry3d& truth, const Eigen::Isometry3d& estimate) {
  const aar_geometry::PoseError e = aar_geometry::ComputePoseError(truth, estimate);
  const Eigen::Vector3d deg(e.orientation_rad.roll, e.orientation_rad.pitch, e.orientation_rad.yaw);
  std::printf(" %7.3f %7.2f", e.position_m.norm(), deg.cwiseAbs().maxCoeff() * 180.0 / M_PI);
}

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::stoi(argv[1]) : 10;
  const int repeats = argc > 2 ? std::stoi(argv[2]) : 3;
  try {
    aar_sim::WorldOptions w = aar_testing::SimStereo::DefaultWorld();
    w.boom_visible = false;
    aar_testing::SimStereo sim(w);
    aar_sim::World& world = sim.world();
    const auto path = aar_sim::FlightPath::Load(aar_testing::DefaultApproachPath());

    // Shelled static reference: seen from both cameras at the contact pose (last path row).
    const Eigen::Isometry3d T_receiver_tanker = path.rows().back().T_tanker_receiver().inverse();
    const aar_geometry::ReferenceCloud dense =
        aar_geometry::SampleReceiver(world.receiver_mesh(), aar_geometry::ReferenceModelOptions{});
    const aar_geometry::VisibilityTester tester(world.receiver_mesh());
    const auto reference =
        aar_geometry::Shell(dense, tester,
                            {T_receiver_tanker * w.rig.T_tanker_left_optical.translation(),
                             T_receiver_tanker * w.rig.T_tanker_right_optical().translation()},
                            0.01);

    aar_registration::Icp ours{aar_registration::IcpOptions{}};
    const auto t_tree = Clock::now();
    ours.SetTarget(reference.points);
    const double tree_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_tree).count();
    PclIcp pcl_icp;
    pcl_icp.setMaximumIterations(30);
    pcl_icp.setMaxCorrespondenceDistance(1.0);
    pcl_icp.setTransformationEpsilon(1e-10);
    pcl_icp.setEuclideanFitnessEpsilon(
        1e-10);  // [m^2] MSE change: stop when the error stops falling
    pcl_icp.setInputTarget(ToPcl(reference.points));

    std::printf(
        "shelled reference: %zu points (KD-tree %.1f ms, built once); 30 iterations at most\n",
        reference.size(), tree_ms);
    std::printf("%6s %8s %7s | %9s %5s %7s %7s | %9s %5s %7s %7s\n", "t[s]", "range[m]", "points",
                "ours[ms]", "iter", "pos[m]", "ang[deg]", "pcl[ms]", "iter", "pos[m]", "ang[deg]");
    for (int i = 0; i < frames; ++i) {
      const double t =
          path.start_time() + (path.end_time() - path.start_time()) * i / std::max(1, frames - 1);
      const auto row = path.At(t);
      const std::vector<Eigen::Vector3d> sensed =
          sim.Run(row, aar_description::DefaultBoomPose(), i).points_in_tanker;
      std::printf("%6.1f %8.1f %7zu |", t, row.position_m.norm(), sensed.size());
      if (sensed.size() < 10) {
        std::printf(" too few points\n");
        continue;
      }
      const Eigen::Isometry3d seed =
          aar_geometry::CentroidSeed(sensed, reference.points);  // T_tanker_receiver

      aar_registration::RegistrationResult r;
      const double ours_ms =
          aar_testing::MedianMs(repeats, [&] { r = ours.Align(sensed, seed.inverse()); });
      std::printf(" %9.2f %5d", ours_ms, r.iterations);
      PrintError(row.T_tanker_receiver(), r.T_target_source.inverse());

      Cloud aligned;
      const Cloud::Ptr source = ToPcl(sensed);
      const double pcl_ms = aar_testing::MedianMs(repeats, [&] {
        pcl_icp.setInputSource(source);
        pcl_icp.align(aligned, seed.inverse().matrix().cast<float>());
      });
      const Eigen::Matrix4d M = pcl_icp.getFinalTransformation().cast<double>();
      Eigen::Isometry3d pcl_T = Eigen::Isometry3d::Identity();  // float: re-orthonormalised
      pcl_T.linear() = Eigen::Quaterniond(Eigen::Matrix3d(M.topLeftCorner<3, 3>()))
                           .normalized()
                           .toRotationMatrix();
      pcl_T.translation() = M.topRightCorner<3, 1>();
      std::printf(" | %9.2f %5d", pcl_ms, pcl_icp.iterations());
      PrintError(row.T_tanker_receiver(), pcl_T.inverse());
      std::printf("\n");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_icp: %s\n", e.what());
    return 1;
  }
  return 0;
}
