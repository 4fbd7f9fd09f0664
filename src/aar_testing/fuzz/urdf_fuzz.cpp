// Fuzz target urdf: a URDF through aar_geometry::LoadRobotModel (urdfdom, meshes through
// LoadMesh), then what the simulator and the occlusion stage do with the model: link poses at
// rest and with each movable joint at its limits, the visual and collision meshes placed, and the
// boom's collision parts for culling (aar_occlusion::LoadBoomParts).
// Mesh references resolve against the shipped models: package://aar_description/..., and
// models/... relative to the URDF (the shipped models folder is linked beside it).
// LoadRobotModel may refuse a model with aar_geometry::LoadError, LoadBoomParts one that cannot
// be culled with std::invalid_argument.
#include <filesystem>
#include <stdexcept>

#include <aar_geometry/load_error.h>
#include <aar_geometry/robot_model.h>
#include <aar_occlusion/boom.h>

#include "fuzz_support.h"

namespace {

const aar_geometry::RobotModelOptions& ModelOptions() {
  static const aar_geometry::RobotModelOptions options = [] {
    aar_geometry::RobotModelOptions o;
    o.package_paths = {aar_fuzz::SourceDir() + "/aar_description"};
    std::error_code ec;
    std::filesystem::create_directory_symlink(aar_fuzz::SourceDir() + "/aar_description/models",
                                              aar_fuzz::ScratchDir() + "/models", ec);
    return o;
  }();
  return options;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const aar_geometry::RobotModelOptions& options = ModelOptions();
  const std::string file = aar_fuzz::WriteScratch("robot.urdf", data, size);
  aar_geometry::RobotModel model;
  try {
    model = aar_geometry::LoadRobotModel(file, options);
  } catch (const aar_geometry::LoadError&) {
    return 0;
  }
  FUZZ_CHECK(model.FindLink(model.root_link) != nullptr, "the root link is a link");
  // Link poses at rest (every joint at 0, as the simulator starts) and with each limited joint
  // at its lower, then its upper limit; every link placed, then the meshes.
  std::map<std::string, double> at_lower, at_upper;
  for (const auto& joint : model.joints) {
    if (!joint.limited()) continue;
    at_lower[joint.name] = joint.lower;
    at_upper[joint.name] = joint.upper;
  }
  for (const auto& positions : {std::map<std::string, double>{}, at_lower, at_upper}) {
    std::map<std::string, Eigen::Isometry3d> poses;
    try {
      aar_geometry::CheckJointLimits(model, positions);          // lower > upper: refused
      poses = aar_geometry::ComputeLinkPoses(model, positions);  // a limit not finite: refused
    } catch (const std::invalid_argument&) {
      continue;
    }
    for (const auto& link : model.links)
      FUZZ_CHECK(poses.count(link.name) == 1, "link '" + link.name + "' not reached from the root");
    for (const auto kind :
         {aar_geometry::GeometryKind::kVisual, aar_geometry::GeometryKind::kCollision}) {
      const aar_geometry::TriangleMesh mesh = aar_geometry::RobotMesh(model, poses, kind);
      FUZZ_CHECK(mesh.triangle_parts.size() == mesh.triangles.size(), "a part per triangle");
    }
  }
  try {
    aar_occlusion::LoadBoomParts(model);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
