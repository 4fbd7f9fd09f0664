#pragma once

#include <map>
#include <string>

#include <aar_geometry/triangle_mesh.h>

#include <Eigen/Geometry>

namespace aar_description {

// Boom joint positions; a flight path's optional boom columns.
struct BoomPose {
  double pitch = 0.0;      // [rad] below horizontal (CSV: boom_pitch, deg)
  double roll = 0.0;       // [rad] lateral swing about the tanker's x axis (CSV: boom_roll, deg)
  double extension = 0.0;  // [m] telescope extension (CSV: boom_extension)
};

// KC-10 class refueling boom. Links: boom_pivot (fixed to the tanker under its tail) ->
// boom_gimbal (joint boom_roll, about the tanker's x axis, +/-15 deg) -> boom (joint boom_pitch,
// positive = down from horizontal, 20 to 40 deg) -> telescope (joint boom_extension, 0 to 6 m
// along the boom) -> nozzle_tip (fixed). At zero joint positions every link frame is aligned with
// the tanker frame and the boom points aft along -x. The fixed tube runs 8.5 m from the pivot
// (0.5 to 0.6 m across); the telescope and nozzle reach 10.85 m plus the extension.
struct BoomModelOptions {
  // [m] under the tanker's tail, 5.5 m behind the cameras: far enough that the boom's near end
  // does not hide a distant receiver.
  Eigen::Vector3d pivot_in_tanker{-25.5, 0.0, -3.6};
  int segments = 32;  // facets around the visual tubes
};

// Static boom pose when a flight path has no boom columns: 30 deg down, centred, 0.5 m out.
BoomPose DefaultBoomPose();

// The URDF text; visual meshes are referenced as `mesh_uri_prefix` + "boom_visual.obj" and
// "telescope_visual.obj" (e.g. "package://aar_description/models/").
std::string MakeBoomUrdf(const BoomModelOptions& options, const std::string& mesh_uri_prefix);

// Detailed visual geometry of link "boom" or "telescope" in that link's frame, parts named.
aar_geometry::TriangleMesh MakeBoomVisualMesh(const std::string& link,
                                              const BoomModelOptions& options);

// The left ruddevator's convex collision hull in the boom frame (models/ruddevator_collision.obj;
// the URDF mirrors it for the right one).
aar_geometry::TriangleMesh MakeRuddevatorCollisionMesh();

// Joint positions for aar_geometry::ComputeLinkPoses and joint_states.
std::map<std::string, double> BoomJointPositions(const BoomPose& pose);

}  // namespace aar_description
