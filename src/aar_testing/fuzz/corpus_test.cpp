// Runs one fuzz target (its LLVMFuzzerTestOneInput, linked beside this file) on every file of its
// seed corpus and of its regression inputs, so that the regular suite replays them all. A crash,
// a failed FUZZ_CHECK or an escaping exception fails the test; the file is named first.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

namespace fs = std::filesystem;

// The files of `dir` (none when it does not exist), in name order.
std::vector<fs::path> Inputs(const std::string& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

size_t RunAll(const std::string& dir) {
  const std::vector<fs::path> files = Inputs(dir);
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    std::cerr << "input " << file.string() << " (" << bytes.size() << " bytes)" << std::endl;
    SCOPED_TRACE(file.string());
    EXPECT_EQ(LLVMFuzzerTestOneInput(bytes.data(), bytes.size()), 0);
  }
  return files.size();
}

TEST(FuzzCorpus, EverySeedAndRegressionInputRuns) {
  const size_t seeds = RunAll(AAR_FUZZ_CORPUS);
  const size_t regressions = RunAll(AAR_FUZZ_REGRESSIONS);
  EXPECT_GT(seeds, 0u) << "no seed corpus in " << AAR_FUZZ_CORPUS;
  std::cout << seeds << " seeds, " << regressions << " regression inputs" << std::endl;
}

}  // namespace
