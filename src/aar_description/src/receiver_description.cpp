#include "aar_description/receiver_description.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>

#include <aar_geometry/load_error.h>
#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <yaml-cpp/yaml.h>

namespace aar_description {
namespace {

using aar_geometry::LoadError;

// Strict reading of one YAML map: each key read is remembered, and Finish refuses the rest.
class StrictMap {
 public:
  StrictMap(const YAML::Node& node, const std::string& path, const std::string& where)
      : node_(node), path_(path), where_(where) {
    if (!node.IsMap()) throw LoadError(path, Name("") + " must be a map");
  }
  bool Has(const std::string& key) {
    known_.insert(key);
    return static_cast<bool>(node_[key]);
  }
  YAML::Node Get(const std::string& key) {
    known_.insert(key);
    return node_[key];
  }
  std::string String(const std::string& key) {
    const YAML::Node n = Get(key);
    if (!n || !n.IsScalar() || n.Scalar().empty())
      throw LoadError(path_, Name(key) + " must be a non-empty string");
    return n.Scalar();
  }
  double Number(const std::string& key) { return ToNumber(Get(key), key); }
  Eigen::Vector3d Vector(const std::string& key) {
    const YAML::Node n = Get(key);
    if (!n || !n.IsSequence() || n.size() != 3)
      throw LoadError(path_, Name(key) + " must be a list of three numbers");
    return {ToNumber(n[0], key), ToNumber(n[1], key), ToNumber(n[2], key)};
  }
  std::vector<std::string> Strings(const std::string& key) {
    const YAML::Node n = Get(key);
    if (!n || !n.IsSequence()) throw LoadError(path_, Name(key) + " must be a list of names");
    std::vector<std::string> out;
    for (const auto& item : n) {
      if (!item.IsScalar() || item.Scalar().empty())
        throw LoadError(path_, Name(key) + " must be a list of names");
      out.push_back(item.Scalar());
    }
    return out;
  }
  Eigen::Isometry3d Pose(const std::string& key, const std::string& translation_key,
                         Eigen::Vector3d* rpy_deg = nullptr) {
    StrictMap pose(Get(key), path_, where_.empty() ? key : where_ + "/" + key);
    const Eigen::Vector3d t =
        pose.Has(translation_key) ? pose.Vector(translation_key) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d rpy =
        pose.Has("rpy_deg") ? pose.Vector("rpy_deg") : Eigen::Vector3d::Zero();
    pose.Finish();
    if (rpy_deg) *rpy_deg = rpy;
    using aar_geometry::DegToRad;
    return aar_geometry::MakeTransform(t,
                                       {DegToRad(rpy.x()), DegToRad(rpy.y()), DegToRad(rpy.z())});
  }
  void Finish() const {
    std::string known;
    for (const auto& k : known_) known += (known.empty() ? "" : ", ") + k;
    for (const auto& item : node_) {
      const std::string key = item.first.IsScalar() ? item.first.Scalar() : "(a non-scalar key)";
      if (!known_.count(key))
        throw LoadError(path_, "unknown key " + Name(key) + " (known: " + known + ")");
    }
  }

 private:
  std::string Name(const std::string& key) const {
    const std::string full = where_.empty() ? key : key.empty() ? where_ : where_ + "/" + key;
    return "'" + full + "'";
  }
  double ToNumber(const YAML::Node& n, const std::string& key) const {
    double v = 0.0;
    if (!n || !n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v))
      throw LoadError(path_, Name(key) + " must be a finite number");
    return v;
  }
  YAML::Node node_;
  std::string path_, where_;
  std::set<std::string> known_;
};

bool IsYaml(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".yaml" || ext == ".yml";
}

std::string Numbers(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s << std::setprecision(10) << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

std::string PoseYaml(const Eigen::Isometry3d& T, const std::string& translation_key) {
  const aar_geometry::RollPitchYaw rpy = aar_geometry::RollPitchYawFromRotation(T.linear());
  Eigen::Vector3d deg(rpy.roll, rpy.pitch, rpy.yaw);
  deg *= 180.0 / M_PI;
  for (int i = 0; i < 3; ++i) deg[i] = std::round(deg[i] * 1e9) / 1e9 + 0.0;  // no -0
  return "  " + translation_key + ": " + Numbers(T.translation()) + "\n  rpy_deg: " + Numbers(deg) +
         "\n";
}

}  // namespace

ReceiverDescription LoadReceiverDescription(const std::string& path) {
  ReceiverDescription d;
  d.path = path;
  if (!IsYaml(path)) {  // a bare mesh in the body frame
    aar_geometry::CheckReadableFile(path);
    d.name = std::filesystem::path(path).stem().string();
    d.mesh = std::filesystem::absolute(path).string();
    d.static_parts = {"left_wing", "right_wing", "nose"};
    return d;
  }
  aar_geometry::CheckReadableFile(path);
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw LoadError(path, std::string("not valid YAML: ") + e.what());
  }
  if (!root.IsMap()) throw LoadError(path, "a receiver description must be a YAML map");
  StrictMap keys(root, path, "");
  d.name = keys.String("name");
  const std::filesystem::path mesh(keys.String("mesh"));
  d.mesh = (mesh.is_absolute() ? mesh : std::filesystem::absolute(path).parent_path() / mesh)
               .lexically_normal()
               .string();
  if (keys.Has("scale")) d.scale = keys.Number("scale");
  if (!(d.scale > 0.0)) throw LoadError(path, "'scale' must be positive");
  if (keys.Has("mesh_to_body")) d.T_body_mesh = keys.Pose("mesh_to_body", "translation");
  if ((d.has_receptacle = keys.Has("receptacle"))) d.receptacle = keys.Vector("receptacle");
  if (keys.Has("static_parts")) d.static_parts = keys.Strings("static_parts");
  if (keys.Has("max_open_length")) d.max_open_length = keys.Number("max_open_length");
  if (!(d.max_open_length >= 0.0)) throw LoadError(path, "'max_open_length' must be >= 0");
  if ((d.has_contact = keys.Has("contact")))
    d.T_tanker_receiver_contact = keys.Pose("contact", "position", &d.contact_rpy_deg);
  if ((d.has_canopy = keys.Has("canopy"))) {
    StrictMap box(keys.Get("canopy"), path, "canopy");
    d.canopy = Eigen::AlignedBox3d(box.Vector("min"), box.Vector("max"));
    box.Finish();
    if (d.canopy.isEmpty()) throw LoadError(path, "'canopy': min must not exceed max");
  }
  if (keys.Has("propellers")) {
    const YAML::Node list = keys.Get("propellers");
    if (!list.IsSequence()) throw LoadError(path, "'propellers' must be a list of maps");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string where = "propellers[" + std::to_string(i) + "]";
      StrictMap item(list[i], path, where);
      PropellerDescription prop;
      prop.hub = item.Vector("hub");
      if (item.Has("axis")) prop.axis = item.Vector("axis");
      if (item.Has("radius")) prop.radius = item.Number("radius");
      if (item.Has("hub_radius")) prop.hub_radius = item.Number("hub_radius");
      if (item.Has("chord")) prop.chord = item.Number("chord");
      if (item.Has("blades")) {
        const double blades = item.Number("blades");
        if (blades != std::round(blades) || blades < 1 || blades > 16)
          throw LoadError(path, "'" + where + "/blades' must be a whole number from 1 to 16");
        prop.blades = static_cast<int>(blades);
      }
      if (item.Has("rpm")) prop.rpm = item.Number("rpm");
      if (item.Has("phase_deg")) prop.phase_deg = item.Number("phase_deg");
      item.Finish();
      if (!(prop.axis.norm() > 1e-9))
        throw LoadError(path, "'" + where + "/axis' must not be zero");
      prop.axis.normalize();
      if (!(prop.radius > 0.0 && prop.hub_radius >= 0.0 && prop.hub_radius < prop.radius))
        throw LoadError(path, "'" + where + "': radius must be positive and above hub_radius >= 0");
      if (!(prop.chord > 0.0)) throw LoadError(path, "'" + where + "/chord' must be positive");
      d.propellers.push_back(prop);
    }
  }
  keys.Finish();
  return d;
}

aar_geometry::TriangleMesh LoadReceiverMesh(const ReceiverDescription& d,
                                            aar_geometry::ReceiverCheckOptions check) {
  check.max_exposed_open_length = d.max_open_length;
  aar_geometry::TriangleMesh mesh = aar_geometry::LoadMesh(d.mesh);
  if (d.scale != 1.0) mesh = aar_geometry::Scaled(mesh, Eigen::Vector3d::Constant(d.scale));
  if (!d.T_body_mesh.matrix().isIdentity(0.0))
    mesh = aar_geometry::Transformed(mesh, d.T_body_mesh);
  aar_geometry::CheckReceiverMesh(mesh, d.mesh, check);
  for (const auto& part : d.static_parts) {
    if (mesh.FindPart(part) < 0) {
      std::string parts;
      for (const auto& p : mesh.part_names) parts += (parts.empty() ? "" : ", ") + p;
      throw aar_geometry::LoadError(d.path, "static part '" + part + "' is not a part of " +
                                                d.mesh + " (its parts: " + parts + ")");
    }
  }
  return mesh;
}

std::string ReceiverDescriptionYaml(const ReceiverDescription& d, const std::string& comment) {
  std::ostringstream s;
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) s << "# " << line << "\n";
  s << "name: " << d.name << "\n";
  s << "mesh: " << d.mesh << "\n";
  s << "scale: " << d.scale << "\n";
  s << "mesh_to_body:\n" << PoseYaml(d.T_body_mesh, "translation");
  if (d.has_receptacle) s << "receptacle: " << Numbers(d.receptacle) << "\n";
  if (!d.static_parts.empty()) {
    s << "static_parts: [";
    for (size_t i = 0; i < d.static_parts.size(); ++i) s << (i ? ", " : "") << d.static_parts[i];
    s << "]\n";
  }
  if (d.max_open_length != ReceiverDescription().max_open_length)
    s << "max_open_length: " << d.max_open_length << "\n";
  if (d.has_contact) {
    s << "contact:\n  position: " << Numbers(d.T_tanker_receiver_contact.translation())
      << "\n  rpy_deg: " << Numbers(d.contact_rpy_deg) << "\n";
  }
  if (d.has_canopy) {
    s << "canopy:\n  min: " << Numbers(d.canopy.min()) << "\n  max: " << Numbers(d.canopy.max())
      << "\n";
  }
  if (!d.propellers.empty()) s << "propellers:\n";
  for (const PropellerDescription& p : d.propellers) {
    s << "  - hub: " << Numbers(p.hub) << "\n    axis: " << Numbers(p.axis)
      << "\n    radius: " << p.radius << "\n    hub_radius: " << p.hub_radius
      << "\n    chord: " << p.chord << "\n    blades: " << p.blades << "\n    rpm: " << p.rpm
      << "\n    phase_deg: " << p.phase_deg << "\n";
  }
  return s.str();
}

}  // namespace aar_description
