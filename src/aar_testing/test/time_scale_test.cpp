// AAR_TIME_SCALE (aar_testing/time_scale.h): 1 when unset, the number when given, and a value a
// sanitized run could not mean ends the test program naming it rather than quietly becoming 1.
// Each case runs in a child process (a death test): TimeScale() reads the variable once.
#include <gtest/gtest.h>

#include <cstdlib>

#include "aar_testing/time_scale.h"

namespace {

void ExitWithScaleTimesTen(const char* value) {
  if (value == nullptr) {
    ::unsetenv("AAR_TIME_SCALE");
  } else {
    ::setenv("AAR_TIME_SCALE", value, 1);
  }
  std::exit(static_cast<int>(aar_testing::TimeScale() * 10.0 + 0.5));
}

TEST(TimeScale, UnsetIsOneAndANumberIsTaken) {
  EXPECT_EXIT(ExitWithScaleTimesTen(nullptr), ::testing::ExitedWithCode(10), "");
  EXPECT_EXIT(ExitWithScaleTimesTen(""), ::testing::ExitedWithCode(10), "");
  EXPECT_EXIT(ExitWithScaleTimesTen("2.5"), ::testing::ExitedWithCode(25), "");
}

TEST(TimeScale, ValuesThatMeanNothingEndTheProgramNamingThem) {
  for (const char* bad : {"abc", "3x", "0.5", "0", "-2", "nan", "1000"}) {
    EXPECT_EXIT(ExitWithScaleTimesTen(bad), ::testing::ExitedWithCode(2),
                std::string("AAR_TIME_SCALE='") + bad + "' is not a number from 1 to 100")
        << bad;
  }
}

}  // namespace
