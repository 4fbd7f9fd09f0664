#pragma once

namespace aar_testing {

// How many times slower than a plain Release build the graph runs: AAR_TIME_SCALE, 1 when unset.
// scripts/test --sanitize sets it (AddressSanitizer and -O1 make the graph several times slower),
// and the tests that bound time or rate divide their rates and multiply their timeouts and time
// bounds by it, so a sanitized run checks the same behaviour at a slower pace. A value that is
// not a number of at least 1 ends the test program, naming it.
double TimeScale();

}  // namespace aar_testing
