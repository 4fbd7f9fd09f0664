#pragma once

#include <string>
#include <vector>

#include <aar_geometry/receiver_check.h>
#include <aar_geometry/triangle_mesh.h>
#include <Eigen/Geometry>

namespace aar_description {

// A receiver model and its datum, as its description file (YAML, e.g. models/c12.yaml) gives
// them. Every key is checked: unknown or mistyped keys are refused.
//
//   name: c12
//   mesh: receiver.obj        # relative to the description; any format assimp reads
//   scale: 1.0                # mesh units to metres (0.001 for a mesh in millimetres)
//   mesh_to_body:             # maps mesh coordinates into the receiver body frame (REP-103:
//     translation: [0, 0, 0]  #   x tail to nose, y right to left wing, z up) [m]
//     rpy_deg: [0, 0, 0]      #   intrinsic z-y'-x'' [deg], applied after scale
//   receptacle: [-0.3, 0, 0.93]               # [m] body frame
//   static_parts: [left_wing, right_wing, nose]  # the static "wings and nose" reference
//   max_open_length: 0.05     # [m] open boundary allowed outside the rest of the model
//   contact:                  # T_tanker_receiver with the nozzle in the receptacle: the
//     position: [-35.0, 0, -10.19]  # nominal pose of the static (shelled) references [m]
//     rpy_deg: [0, -2, 0]
//   canopy:                   # optional: windscreen glass for the simulator's sun (issue 16):
//     min: [4.15, -0.8, 0.45] #   the surface inside this box [m, body frame] where it faces
//     max: [4.95, 0.8, 1.0]   #   up (normal z > 0.2)
//   propellers:               # optional: spinning propellers the simulator draws (issue 16);
//     - hub: [3.3, 2.6, -0.18]  # not part of the mesh, so not of any reference model
//       axis: [1, 0, 0]
//       radius: 1.25
//       hub_radius: 0.17
//       chord: 0.18
//       blades: 4
//       rpm: 1700
//       phase_deg: 0
//
// A propeller of the description: a disc of blades turning about its axis.
struct PropellerDescription {
  Eigen::Vector3d hub = Eigen::Vector3d::Zero();    // [m] body frame: the disc's centre
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // body frame, unit: the thrust axis
  double radius = 1.25;                             // [m] blade tip
  double hub_radius = 0.17;                         // [m] spinner: no blade inside it
  double chord = 0.18;                              // [m] blade width
  int blades = 4;
  double rpm = 1700.0;     // [rev/min] about +axis (clockwise seen from behind a tractor)
  double phase_deg = 0.0;  // [deg] blade 0's angle at path time 0
};

struct ReceiverDescription {
  std::string name;
  std::string path;  // the description file (a bare mesh: the mesh)
  std::string mesh;  // the mesh file, absolute
  double scale = 1.0;
  Eigen::Isometry3d T_body_mesh = Eigen::Isometry3d::Identity();  // after scaling
  bool has_receptacle = false;
  Eigen::Vector3d receptacle = Eigen::Vector3d::Zero();  // [m] body frame
  std::vector<std::string> static_parts;
  // [m] open boundary (edges of one triangle) allowed outside every other part of the model.
  double max_open_length = 0.05;
  bool has_contact = false;
  Eigen::Isometry3d T_tanker_receiver_contact = Eigen::Isometry3d::Identity();
  Eigen::Vector3d contact_rpy_deg = Eigen::Vector3d::Zero();  // its attitude as written [deg]
  bool has_canopy = false;
  Eigen::AlignedBox3d canopy;  // [m] body frame: windscreen glass where the surface faces up
  std::vector<PropellerDescription> propellers;
};

// A description file (.yaml or .yml), or a bare mesh file: the mesh in the body frame, in
// metres, with the C-12's part names as static parts and no receptacle or contact pose. Throws
// aar_geometry::LoadError naming the file and the key for anything wrong.
ReceiverDescription LoadReceiverDescription(const std::string& path);

// The mesh in the body frame [m]: loaded (any format assimp reads), scaled, mapped through
// T_body_mesh and checked (aar_geometry::CheckReceiverMesh: faces, size, closed up to the
// description's max_open_length). Throws aar_geometry::LoadError naming the mesh file.
aar_geometry::TriangleMesh LoadReceiverMesh(const ReceiverDescription& description,
                                            aar_geometry::ReceiverCheckOptions check = {});

// A description as YAML (what LoadReceiverDescription reads), with `comment` as its header and
// the mesh path written as given (relative to the description).
std::string ReceiverDescriptionYaml(const ReceiverDescription& description,
                                    const std::string& comment);

}  // namespace aar_description
