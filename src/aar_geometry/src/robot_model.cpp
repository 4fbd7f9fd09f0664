#include "aar_geometry/robot_model.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "aar_geometry/load_error.h"
#include "aar_geometry/mesh_io.h"
#include "aar_geometry/primitives.h"

namespace aar_geometry {
namespace fs = std::filesystem;

const Link* RobotModel::FindLink(const std::string& link_name) const {
  for (const auto& link : links) {
    if (link.name == link_name) return &link;
  }
  return nullptr;
}

const Joint* RobotModel::FindJoint(const std::string& joint_name) const {
  for (const auto& joint : joints) {
    if (joint.name == joint_name) return &joint;
  }
  return nullptr;
}

namespace {

// urdfdom reports problems only through console_bridge, and for some (a malformed geometry
// element) logs an error yet returns a model without that element. Collect its errors while
// parsing so that they fail the load and the exception can say why. Not thread-safe
// (console_bridge's handler is global); models are loaded at start-up.
class CapturedConsole : public console_bridge::OutputHandler {
 public:
  CapturedConsole() : previous_(console_bridge::getOutputHandler()) {
    console_bridge::useOutputHandler(this);
  }
  ~CapturedConsole() override { console_bridge::useOutputHandler(previous_); }
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) {
      if (!messages_.empty()) messages_ += "; ";
      messages_ += text;
    }
  }
  const std::string& messages() const { return messages_; }

 private:
  console_bridge::OutputHandler* previous_;
  std::string messages_;
};

Eigen::Isometry3d ToEigen(const urdf::Pose& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << pose.position.x, pose.position.y, pose.position.z;
  T.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
          .normalized()
          .toRotationMatrix();
  return T;
}

std::vector<std::string> PackageRoots(const RobotModelOptions& options) {
  if (!options.package_paths.empty()) return options.package_paths;
  std::vector<std::string> roots;
  if (const char* env = std::getenv("ROS_PACKAGE_PATH")) {
    std::stringstream ss(env);
    std::string root;
    while (std::getline(ss, root, ':')) {
      if (!root.empty()) roots.push_back(root);
    }
  }
  return roots;
}

// The <name> of a package.xml, or "" if it has none.
std::string PackageName(const fs::path& package_xml) {
  std::ifstream in(package_xml);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  const size_t open = s.find("<name>");
  const size_t close = open == std::string::npos ? std::string::npos : s.find("</name>", open);
  if (close == std::string::npos) return "";
  std::string name = s.substr(open + 6, close - open - 6);
  const size_t b = name.find_first_not_of(" \t\r\n"), e = name.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? "" : name.substr(b, e - b + 1);
}

std::string FindPackage(const std::string& package, const std::vector<std::string>& roots) {
  std::function<std::string(const fs::path&, int)> search = [&](const fs::path& dir, int depth) {
    std::error_code ec;
    if (fs::exists(dir / "package.xml", ec)) {
      // A package: its name decides; packages do not nest.
      return PackageName(dir / "package.xml") == package ? dir.string() : std::string();
    }
    if (depth == 0) return std::string();
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->is_directory(ec)) {
        const std::string found = search(it->path(), depth - 1);
        if (!found.empty()) return found;
      }
    }
    return std::string();
  };
  for (const auto& root : roots) {
    const std::string found = search(fs::path(root).lexically_normal(), 4);
    if (!found.empty()) return found;
  }
  return "";
}

std::string ResolveMeshPath(const std::string& uri, const fs::path& urdf_dir,
                            const RobotModelOptions& options) {
  static const std::string kPackage = "package://";
  static const std::string kFile = "file://";
  if (uri.rfind(kPackage, 0) == 0) {
    const std::string rest = uri.substr(kPackage.size());
    const size_t slash = rest.find('/');
    if (slash == std::string::npos) throw std::runtime_error("'" + uri + "' names no file");
    const std::string package = rest.substr(0, slash);
    const std::string root = options.find_package ? options.find_package(package)
                                                  : FindPackage(package, PackageRoots(options));
    if (root.empty()) {
      throw std::runtime_error(
          "package '" + package + "' of '" + uri + "' not found " +
          (options.find_package ? "(rospack)" : "in the package paths (ROS_PACKAGE_PATH)"));
    }
    return (fs::path(root) / rest.substr(slash + 1)).string();
  }
  if (uri.rfind(kFile, 0) == 0) return uri.substr(kFile.size());
  const fs::path p(uri);
  return p.is_absolute() ? p.string() : (urdf_dir / p).string();
}

GeometryElement MakeElement(const urdf::Geometry& geometry, const std::string& name,
                            const urdf::Pose& origin, const fs::path& urdf_dir,
                            const RobotModelOptions& options) {
  GeometryElement element;
  element.name = name;
  element.T_link_geometry = ToEigen(origin);
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      element.source = "box";
      element.mesh = MakeBox({box.dim.x, box.dim.y, box.dim.z}, name);
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      element.source = "cylinder";
      element.mesh =
          MakeCylinder(cylinder.radius, cylinder.length, options.cylinder_segments, name);
      break;
    }
    case urdf::Geometry::SPHERE: {
      const auto& sphere = static_cast<const urdf::Sphere&>(geometry);
      element.source = "sphere";
      element.mesh = MakeSphere(sphere.radius, options.sphere_subdivisions, name);
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      element.source = ResolveMeshPath(mesh.filename, urdf_dir, options);
      TriangleMesh loaded =
          Scaled(LoadMesh(element.source), {mesh.scale.x, mesh.scale.y, mesh.scale.z});
      // One part per element: the element is the unit that later stages select.
      element.mesh.vertices = std::move(loaded.vertices);
      element.mesh.triangles = std::move(loaded.triangles);
      element.mesh.AddPart(name);
      element.mesh.triangle_parts.assign(element.mesh.triangles.size(), 0);
      break;
    }
    default:
      throw std::runtime_error("unsupported geometry type");
  }
  return element;
}

template <typename ElementPtr>
std::vector<GeometryElement> MakeElements(const std::vector<ElementPtr>& elements,
                                          const std::string& link, const std::string& kind,
                                          const std::string& urdf_path, const fs::path& urdf_dir,
                                          const RobotModelOptions& options) {
  std::vector<GeometryElement> out;
  for (size_t i = 0; i < elements.size(); ++i) {
    const auto& element = *elements[i];
    const std::string name =
        element.name.empty() ? link + "/" + kind + std::to_string(i) : element.name;
    const std::string where =
        "link '" + link + "' " + kind + " " + std::to_string(i) + " ('" + name + "')";
    if (!element.geometry) throw LoadError(urdf_path, where + " has no geometry");
    try {
      out.push_back(MakeElement(*element.geometry, name, element.origin, urdf_dir, options));
    } catch (const std::exception& e) {
      throw LoadError(urdf_path, where + ": " + e.what());
    }
  }
  return out;
}

JointType ToJointType(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE:
      return JointType::kRevolute;
    case urdf::Joint::CONTINUOUS:
      return JointType::kContinuous;
    case urdf::Joint::PRISMATIC:
      return JointType::kPrismatic;
    case urdf::Joint::FLOATING:
      return JointType::kFloating;
    case urdf::Joint::PLANAR:
      return JointType::kPlanar;
    default:
      return JointType::kFixed;
  }
}

// urdfdom's model of `xml`, with a root link; its console errors fail the parse.
urdf::ModelInterfaceSharedPtr ParseUrdf(const std::string& xml, const std::string& path) {
  if (xml.find_first_not_of(" \t\r\n") == std::string::npos) throw LoadError(path, "URDF is empty");
  urdf::ModelInterfaceSharedPtr urdf;
  std::string parse_messages;
  {
    CapturedConsole console;
    try {
      urdf = urdf::parseURDF(xml);
    } catch (const std::exception& e) {
      throw LoadError(path, std::string("not a valid URDF: ") + e.what());
    }
    parse_messages = console.messages();
  }
  if (!urdf || !parse_messages.empty()) {
    throw LoadError(path, "not a valid URDF" +
                              (parse_messages.empty() ? std::string() : ": " + parse_messages));
  }
  if (!urdf->getRoot()) throw LoadError(path, "URDF has no root link");
  return urdf;
}

// urdfdom accepts joints that form a cycle apart from the root (each of its links has a
// parent, so the root is still the only link without one): no pose could place those links.
// Found by the urdf fuzz target.
void CheckConnected(const urdf::ModelInterface& urdf, const std::string& path) {
  std::set<std::string> reached = {urdf.getRoot()->name};
  for (std::vector<std::string> frontier = {urdf.getRoot()->name}; !frontier.empty();) {
    const std::string parent = frontier.back();
    frontier.pop_back();
    for (const auto& [name, joint] : urdf.joints_) {
      if (joint->parent_link_name == parent && reached.insert(joint->child_link_name).second)
        frontier.push_back(joint->child_link_name);
    }
  }
  for (const auto& [name, link] : urdf.links_) {
    if (!reached.count(name)) {
      throw LoadError(path, "link '" + name + "' is not connected to the root link '" +
                                urdf.getRoot()->name + "' (its joints form a cycle)");
    }
  }
}

Joint MakeJoint(const urdf::Joint& joint, const std::string& path) {
  Joint out;
  out.name = joint.name;
  out.type = ToJointType(joint.type);
  out.parent_link = joint.parent_link_name;
  out.child_link = joint.child_link_name;
  out.T_parent_joint = ToEigen(joint.parent_to_joint_origin_transform);
  const Eigen::Vector3d axis(joint.axis.x, joint.axis.y, joint.axis.z);
  if (out.movable() && !(axis.norm() > 0.0)) {
    throw LoadError(path, "joint '" + joint.name + "' has a zero axis");
  }
  out.axis = axis.norm() > 0.0 ? axis.normalized() : Eigen::Vector3d::UnitX();
  if (joint.limits) {
    out.lower = joint.limits->lower;
    out.upper = joint.limits->upper;
  }
  return out;
}

}  // namespace

RobotModel LoadRobotModel(const std::string& path, const RobotModelOptions& options) {
  CheckReadableFile(path);
  std::ifstream file(path);
  std::stringstream xml;
  xml << file.rdbuf();
  return ParseRobotModel(xml.str(), path, fs::absolute(fs::path(path)).parent_path().string(),
                         options);
}

RobotModel ParseRobotModel(const std::string& xml, const std::string& path,
                           const std::string& base_dir, const RobotModelOptions& options) {
  const urdf::ModelInterfaceSharedPtr urdf = ParseUrdf(xml, path);
  // urdfdom's links hold their children by shared_ptr, so a cycle of joints would never be
  // freed: cut every link's ties when done, however this function ends.
  const struct CycleBreaker {
    urdf::ModelInterfaceSharedPtr model;
    ~CycleBreaker() {
      for (auto& [name, link] : model->links_) {
        link->child_links.clear();
        link->child_joints.clear();
        link->parent_joint.reset();
      }
    }
  } cycle_breaker{urdf};
  CheckConnected(*urdf, path);
  RobotModel model;
  model.name = urdf->getName();
  model.root_link = urdf->getRoot()->name;
  const fs::path urdf_dir(base_dir);
  for (const auto& [name, link] : urdf->links_) {
    Link out;
    out.name = name;
    out.visuals = MakeElements(link->visual_array, name, "visual", path, urdf_dir, options);
    out.collisions =
        MakeElements(link->collision_array, name, "collision", path, urdf_dir, options);
    model.links.push_back(std::move(out));
  }
  for (const auto& [name, joint] : urdf->joints_) model.joints.push_back(MakeJoint(*joint, path));
  return model;
}

bool Joint::WithinLimits(double position) const {
  if (!limited()) return true;
  return position >= lower - kJointLimitTolerance && position <= upper + kJointLimitTolerance;
}

void CheckJointLimits(const RobotModel& model, const std::map<std::string, double>& positions) {
  for (const auto& [name, value] : positions) {
    const Joint* joint = model.FindJoint(name);
    if (joint == nullptr || joint->WithinLimits(value)) continue;
    std::ostringstream msg;
    const char* unit = joint->type == JointType::kPrismatic ? " m" : " rad";
    msg << "joint '" << name << "' position " << value << unit << " is outside its limits "
        << joint->lower << " to " << joint->upper << unit << " (robot '" << model.name << "')";
    throw std::invalid_argument(msg.str());
  }
}

std::map<std::string, Eigen::Isometry3d> ComputeLinkPoses(
    const RobotModel& model, const std::map<std::string, double>& joint_positions) {
  for (const auto& [name, value] : joint_positions) {
    const Joint* joint = model.FindJoint(name);
    if (joint == nullptr || !joint->movable()) {
      throw std::invalid_argument("'" + name + "' is not a movable joint of robot '" + model.name +
                                  "'");
    }
    if (!std::isfinite(value)) {
      throw std::invalid_argument("joint '" + name + "' position is not finite");
    }
  }
  std::map<std::string, std::vector<const Joint*>> children;
  for (const auto& joint : model.joints) children[joint.parent_link].push_back(&joint);

  std::map<std::string, Eigen::Isometry3d> poses;
  std::vector<std::string> stack = {model.root_link};
  poses[model.root_link] = Eigen::Isometry3d::Identity();
  while (!stack.empty()) {
    const std::string parent = stack.back();
    stack.pop_back();
    for (const Joint* joint : children[parent]) {
      const auto it = joint_positions.find(joint->name);
      const double q = it == joint_positions.end() ? 0.0 : it->second;
      Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
      if (joint->type == JointType::kRevolute || joint->type == JointType::kContinuous) {
        motion.linear() = Eigen::AngleAxisd(q, joint->axis).toRotationMatrix();
      } else if (joint->type == JointType::kPrismatic) {
        motion.translation() = q * joint->axis;
      }
      poses[joint->child_link] = poses[parent] * joint->T_parent_joint * motion;
      stack.push_back(joint->child_link);
    }
  }
  return poses;
}

TriangleMesh RobotMesh(const RobotModel& model,
                       const std::map<std::string, Eigen::Isometry3d>& T_root_links,
                       GeometryKind kind) {
  TriangleMesh out;
  std::map<std::string, std::string> owner;  // element name -> link that used it first
  for (const auto& link : model.links) {
    const auto pose = T_root_links.find(link.name);
    if (pose == T_root_links.end()) {
      throw std::invalid_argument("no pose given for link '" + link.name + "'");
    }
    const auto& elements = kind == GeometryKind::kVisual ? link.visuals : link.collisions;
    for (const auto& element : elements) {
      const auto [it, first] = owner.emplace(element.name, link.name);
      if (first || it->second == link.name) {
        out.Append(element.mesh, pose->second * element.T_link_geometry);
      } else {  // another link's element has this name: keep the parts apart
        TriangleMesh renamed = element.mesh;
        for (auto& name : renamed.part_names) name = link.name + "/" + name;
        out.Append(renamed, pose->second * element.T_link_geometry);
      }
    }
  }
  return out;
}

}  // namespace aar_geometry
