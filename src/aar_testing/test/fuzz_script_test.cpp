// scripts/fuzz refuses bad arguments with a message naming them and status 2, before it sets up
// or builds anything; scripts/setup names a package list it cannot use.
#include <gtest/gtest.h>

#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace {

aar_testing::CommandResult Script(const std::string& name, const std::string& args) {
  return aar_testing::RunCommand(aar_testing::WorkspaceRoot() + "/scripts/" + name + " " + args);
}

TEST(FuzzScript, BadArgumentsAreNamedAndRefused) {
  const struct {
    std::string args, needle;
  } cases[] = {
      {"--seconds 0", "--seconds takes a whole number of seconds >= 1, not '0'"},
      {"--seconds 1.5", "--seconds takes a whole number of seconds >= 1, not '1.5'"},
      {"--seconds", "--seconds needs a value"},
      {"--targets mesh,nope",
       "no fuzz target 'nope' (targets: flight_path, mesh, urdf, point_cloud, stereo_input, "
       "params)"},
      {"--jobs 999", "(this machine's cores), not '999'"},
      {"--jobs 0", "(this machine's cores), not '0'"},
      {"--bogus", "unknown argument '--bogus'"},
  };
  for (const auto& c : cases) {
    const auto r = Script("fuzz", c.args);
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << ": " << r.output;
    EXPECT_EQ(r.output.find("setup:"), std::string::npos) << c.args << ": set up anyway";
  }
}

TEST(SetupScript, APackageListItCannotUseIsNamed) {
  const auto missing = Script("setup", "/nonexistent/packages.txt");
  EXPECT_EQ(missing.status, 2) << missing.output;
  EXPECT_NE(missing.output.find("no package list '/nonexistent/packages.txt'"), std::string::npos)
      << missing.output;
  const auto two = Script("setup", "a.txt b.txt");
  EXPECT_EQ(two.status, 2) << two.output;
  EXPECT_NE(two.output.find("(one list, not 2 arguments)"), std::string::npos) << two.output;
}

}  // namespace
