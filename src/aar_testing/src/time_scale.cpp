#include "aar_testing/time_scale.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace aar_testing {

double TimeScale() {
  static const double scale = [] {
    const char* text = std::getenv("AAR_TIME_SCALE");
    if (text == nullptr || *text == '\0') return 1.0;
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    // A silent 1 here would make a sanitized run fail on time for no visible reason.
    if (end == text || *end != '\0' || !(value >= 1.0) || value > 100.0) {
      std::fprintf(stderr, "AAR_TIME_SCALE='%s' is not a number from 1 to 100\n", text);
      std::exit(2);
    }
    return value;
  }();
  return scale;
}

}  // namespace aar_testing
