// model_info on the command line: bad option values are named, joint positions outside the URDF's
// limits are refused, and a mesh that welds down to nothing is not reported closed.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "test_files.h"

namespace aar_geometry {
namespace {

struct ToolRun {
  int status = -1;     // exit code
  std::string output;  // stdout and stderr
};

ToolRun ModelInfo(const std::string& args) {
  const std::string command = std::string(AAR_GEOMETRY_MODEL_INFO) + " " + args + " 2>&1";
  ToolRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
    run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

bool Contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(ModelInfo, SampleCountMustBeAPositiveInteger) {
  const std::string cube = test::DataPath("cube.stl");
  for (const std::string bad : {"-5", "0", "2.5", "abc", "99999999999999999999999"}) {
    const ToolRun run = ModelInfo(cube + " --samples " + bad);
    EXPECT_EQ(run.status, 2) << bad;
    EXPECT_TRUE(Contains(run.output, "--samples: '" + bad + "' is not an integer of at least 1"))
        << run.output;
    EXPECT_FALSE(Contains(run.output, "samples: 1")) << run.output;  // no wrapped count drawn
  }
  const ToolRun good = ModelInfo(cube + " --samples 5");
  EXPECT_EQ(good.status, 0) << good.output;
  EXPECT_TRUE(Contains(good.output, "samples: 5 (seed 1)")) << good.output;
  const ToolRun seed = ModelInfo(cube + " --samples 5 --seed -1");
  EXPECT_EQ(seed.status, 2);
  EXPECT_TRUE(Contains(seed.output, "--seed: '-1' is not an integer of at least 0")) << seed.output;
}

TEST(ModelInfo, JointValueThatIsNotANumberIsNamed) {
  const std::string urdf = test::DataPath("boom_primitives.urdf");
  for (const std::string bad : {"abc", "", "0.5x", "nan"}) {
    const ToolRun run = ModelInfo(urdf + " --joint boom_pitch=" + bad);
    EXPECT_EQ(run.status, 2) << bad;
    EXPECT_TRUE(Contains(run.output, "--joint boom_pitch: '" + bad + "' is not a number"))
        << run.output;
  }
  const ToolRun weld = ModelInfo(urdf + " --weld 1e-4m");
  EXPECT_EQ(weld.status, 2);
  EXPECT_TRUE(Contains(weld.output, "--weld: '1e-4m' is not a number")) << weld.output;
}

TEST(ModelInfo, JointOutsideItsLimitsIsRefused) {
  const std::string urdf = test::DataPath("boom_primitives.urdf");
  const ToolRun pitch = ModelInfo(urdf + " --joint boom_pitch=100");
  EXPECT_EQ(pitch.status, 1);
  EXPECT_TRUE(Contains(
      pitch.output, "joint 'boom_pitch' position 100 rad is outside its limits 0.349 to 0.698 rad"))
      << pitch.output;
  EXPECT_FALSE(Contains(pitch.output, "triangles:")) << pitch.output;
  const ToolRun telescope = ModelInfo(urdf + " --joint telescope=-50");
  EXPECT_EQ(telescope.status, 1);
  EXPECT_TRUE(
      Contains(telescope.output, "joint 'telescope' position -50 m is outside its limits 0 to 6 m"))
      << telescope.output;
  const ToolRun within = ModelInfo(urdf + " --joint boom_pitch=0.5 --joint telescope=2");
  EXPECT_EQ(within.status, 0) << within.output;
  EXPECT_TRUE(Contains(within.output, "triangles:")) << within.output;
}

TEST(ModelInfo, MeshWithOnlyADegenerateTriangleIsNotClosed) {
  test::TempDir dir;
  const std::string obj = dir.Write("one.obj",
                                    "o one\n"
                                    "v 0 0 0\nv 1 0 0\nv 1 0 0\n"
                                    "f 1 2 3\n");
  const ToolRun run = ModelInfo(obj);
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "(not closed: 0 triangles, fewer than a tetrahedron's 4)"))
      << run.output;
  EXPECT_FALSE(Contains(run.output, ", closed\n")) << run.output;  // nor its part
  const ToolRun cube = ModelInfo(test::DataPath("cube.stl"));
  EXPECT_TRUE(Contains(cube.output, "(closed)")) << cube.output;
}

}  // namespace
}  // namespace aar_geometry
