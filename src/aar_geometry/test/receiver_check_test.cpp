#include <gtest/gtest.h>

#include <string>

#include "aar_geometry/load_error.h"
#include "aar_geometry/primitives.h"
#include "aar_geometry/receiver_check.h"

namespace aar_geometry {
namespace {

// The message of the LoadError that CheckReceiverMesh throws, or "" when it accepts the mesh.
std::string Refusal(const TriangleMesh& mesh) {
  try {
    CheckReceiverMesh(mesh, "/models/plane.obj");
  } catch (const LoadError& e) {
    return e.what();
  }
  return "";
}

// A 13 m long, 16 m wide, 4 m tall box: aircraft sized.
TriangleMesh Aircraft() { return MakeBox({13.0, 16.0, 4.0}, "fuselage"); }

TEST(CheckReceiverMesh, AcceptsAClosedAircraftSizedModel) {
  const ReceiverCheckResult r = CheckReceiverMesh(Aircraft(), "plane.obj");
  EXPECT_NEAR(r.size.y(), 16.0, 1e-12);
  EXPECT_EQ(r.open_edges, 0u);
}

TEST(CheckReceiverMesh, RefusesNoFaces) {
  TriangleMesh mesh = Aircraft();
  mesh.triangles.clear();
  mesh.triangle_parts.clear();
  EXPECT_EQ(Refusal(mesh), "/models/plane.obj: the receiver model has no faces");
}

TEST(CheckReceiverMesh, RefusesMillimetresAndKilometresNamingTheSize) {
  const std::string huge = Refusal(Scaled(Aircraft(), Eigen::Vector3d::Constant(1000.0)));
  EXPECT_NE(huge.find("/models/plane.obj: the receiver model is 16000 m across (x 13000 m, y "
                      "16000 m, z 4000 m)"),
            std::string::npos)
      << huge;
  EXPECT_NE(huge.find("millimetres needs scale: 0.001"), std::string::npos) << huge;
  const std::string tiny = Refusal(Scaled(Aircraft(), Eigen::Vector3d::Constant(0.001)));
  EXPECT_NE(tiny.find("is 0.02 m across"), std::string::npos) << tiny;
  EXPECT_NE(tiny.find("smaller than any aircraft"), std::string::npos) << tiny;
}

TEST(CheckReceiverMesh, RefusesAnOpenModelNamingWhere) {
  TriangleMesh mesh = Aircraft();
  mesh.triangles.pop_back();  // a hole: one face of the box half gone
  mesh.triangle_parts.pop_back();
  const std::string why = Refusal(mesh);
  EXPECT_NE(why.find("/models/plane.obj: the receiver model is open: 3 of 3 edges used by one "
                     "triangle"),
            std::string::npos)
      << why;
}

// A wing whose open root lies inside the fuselage (as the C-12's do) is not open; the same wing
// pulled out of the fuselage is.
TEST(CheckReceiverMesh, AcceptsOpenEdgesInsideAnotherPart) {
  TriangleMesh wing = MakeBox({2.0, 8.0, 0.3}, "left_wing");
  std::vector<Eigen::Vector3i> kept;
  std::vector<int> parts;
  for (size_t t = 0; t < wing.triangles.size(); ++t) {
    bool root = true;  // both triangles of the face at y = -4 (the root)
    for (int k = 0; k < 3; ++k) root = root && wing.vertices[wing.triangles[t][k]].y() < -3.9;
    if (!root) {
      kept.push_back(wing.triangles[t]);
      parts.push_back(wing.triangle_parts[t]);
    }
  }
  ASSERT_EQ(kept.size(), wing.triangles.size() - 2);
  wing.triangles = kept;
  wing.triangle_parts = parts;
  TriangleMesh plane = MakeBox({13.0, 1.6, 1.6}, "fuselage");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.0, 4.5, 0.0);  // root at y = 0.5, inside the 0.8 half-width
  plane.Append(wing, T);
  const ReceiverCheckResult r = CheckReceiverMesh(plane, "plane.obj");
  EXPECT_EQ(r.open_edges, 4u);  // the root rectangle
  EXPECT_EQ(r.exposed_open_edges, 0u);

  TriangleMesh detached = MakeBox({13.0, 1.6, 1.6}, "fuselage");
  T.translation() = Eigen::Vector3d(0.0, 6.0, 0.0);  // root at y = 2: outside
  detached.Append(wing, T);
  EXPECT_NE(Refusal(detached).find("is open: 4 of 4 edges"), std::string::npos)
      << Refusal(detached);
}

}  // namespace
}  // namespace aar_geometry
