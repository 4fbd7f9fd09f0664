#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry {

// One <visual> or <collision> element, its geometry already turned into a mesh.
struct GeometryElement {
  std::string name;    // the element's name attribute, else "<link>/<kind><index>"
  std::string source;  // "box", "cylinder", "sphere", or the resolved mesh path
  Eigen::Isometry3d T_link_geometry = Eigen::Isometry3d::Identity();  // the element's <origin>
  TriangleMesh mesh;  // in the geometry frame, URDF mesh scale applied
};

struct Link {
  std::string name;
  std::vector<GeometryElement> visuals;
  std::vector<GeometryElement> collisions;
};

enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic, kFloating, kPlanar };

struct Joint {
  std::string name;
  JointType type = JointType::kFixed;
  std::string parent_link;
  std::string child_link;
  Eigen::Isometry3d T_parent_joint = Eigen::Isometry3d::Identity();  // the joint's <origin>
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();                   // unit, in the joint frame
  double lower = 0.0;  // [rad] or [m]; 0 when the URDF gives no limits
  double upper = 0.0;  // [rad] or [m]

  bool movable() const {
    return type == JointType::kRevolute || type == JointType::kContinuous ||
           type == JointType::kPrismatic;
  }
  // Revolute and prismatic joints have <limit> (urdfdom requires it); continuous ones do not.
  bool limited() const { return type == JointType::kRevolute || type == JointType::kPrismatic; }
  // True for an unlimited joint or a finite `position` [rad or m] within [lower, upper] up to
  // kJointLimitTolerance.
  bool WithinLimits(double position) const;
};

// [rad] or [m]: URDF limits are written rounded (aar_description's to six significant digits,
// 20 deg as 0.349066), so a position at a limit given in other units may land just outside it.
constexpr double kJointLimitTolerance = 1e-6;

struct RobotModel {
  std::string name;
  std::string root_link;
  std::vector<Link> links;
  std::vector<Joint> joints;

  const Link* FindLink(const std::string& name) const;    // nullptr if absent
  const Joint* FindJoint(const std::string& name) const;  // nullptr if absent
};

struct RobotModelOptions {
  int cylinder_segments = 32;   // facets around URDF cylinders
  int sphere_subdivisions = 2;  // icosphere level of URDF spheres (320 triangles)
  // Where package://NAME/... is: find_package(NAME), the package's folder ("" if unknown); ROS
  // nodes set rospack's (aar_ros_common::LoadRobotDescription). Unset: package_paths are
  // searched for a folder whose package.xml says <name>NAME</name>, the root itself or up to four
  // folders below it; empty, the folders of ROS_PACKAGE_PATH (tools and tests without ROS).
  std::function<std::string(const std::string&)> find_package;
  std::vector<std::string> package_paths;
};

// Parses a URDF through urdfdom and loads every visual and collision geometry: meshes through
// LoadMesh (package://, file:// and paths relative to the URDF resolved), primitives through
// MakeBox/MakeCylinder/MakeSphere. Throws LoadError naming the URDF, and the link and mesh where
// one is at fault, for a missing, empty or malformed file, an invalid model or a mesh that does
// not load.
RobotModel LoadRobotModel(const std::string& path, const RobotModelOptions& options = {});

// The same from URDF text, e.g. the robot_description parameter. `source` names it in errors;
// relative mesh paths resolve against `base_dir`.
RobotModel ParseRobotModel(const std::string& xml, const std::string& source,
                           const std::string& base_dir, const RobotModelOptions& options = {});

// T_root_link for every link at the given joint positions ([rad] or [m]); joints not listed stay
// at 0, even where 0 is outside their limits (floating and planar joints are held at their
// origin; <mimic> is not followed). Positions are not clamped to the limits. Throws
// std::invalid_argument for a name that is not a movable joint of the model, or a value that is not
// finite.
std::map<std::string, Eigen::Isometry3d> ComputeLinkPoses(
    const RobotModel& model, const std::map<std::string, double>& joint_positions = {});

// Throws std::invalid_argument naming the joint, the position and the joint's limits for a
// position outside a limited joint's limits (Joint::WithinLimits). Names that are not joints of
// the model are left to ComputeLinkPoses.
void CheckJointLimits(const RobotModel& model, const std::map<std::string, double>& positions);

enum class GeometryKind { kVisual, kCollision };

// Every element of the kind placed in the root frame at the given link poses, one part per
// element, named as GeometryElement::name, or "<link>/<name>" where two links use one name.
TriangleMesh RobotMesh(const RobotModel& model,
                       const std::map<std::string, Eigen::Isometry3d>& T_root_links,
                       GeometryKind kind);

}  // namespace aar_geometry
