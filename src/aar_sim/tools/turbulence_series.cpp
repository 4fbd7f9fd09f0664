// turbulence_series: writes N steps of the Dryden gusts (aar_sim::DrydenGusts at the default
// airspeed, altitude and 100 Hz step) as raw little-endian float64 triples u, v, w [m/s], after a
// warm-up of 16384 steps from rest; prints sigma [m/s], the scale length [m], the airspeed [m/s]
// and the step [s] on one line. For scripts/plot_turbulence_psd.py.
//   turbulence_series light|moderate|severe SEED STEPS OUT.bin
#include <cstdint>
#include <fstream>
#include <iostream>
#include <string>

#include "aar_sim/turbulence.h"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: turbulence_series light|moderate|severe SEED STEPS OUT.bin\n";
    return 2;
  }
  aar_sim::TurbulenceOptions o;
  try {
    o.intensity = aar_sim::ParseTurbulenceIntensity(argv[1]);
    o.seed = std::stoull(argv[2]);
  } catch (const std::exception& e) {
    std::cerr << "turbulence_series: bad intensity or SEED: " << e.what() << "\n";
    return 2;
  }
  size_t steps = 0;
  try {
    steps = std::stoull(argv[3]);
  } catch (const std::exception&) {
  }
  if (steps < 2 || steps > (size_t(1) << 24)) {
    std::cerr << "turbulence_series: STEPS must be from 2 to 2^24, not '" << argv[3] << "'\n";
    return 2;
  }
  const size_t warmup = 16384;
  const auto gusts = aar_sim::DrydenGusts(o, warmup + steps);
  std::ofstream out(argv[4], std::ios::binary);
  for (size_t i = warmup; i < gusts.size(); ++i)
    out.write(reinterpret_cast<const char*>(gusts[i].velocity.data()), 3 * sizeof(double));
  if (!out) {
    std::cerr << "turbulence_series: cannot write " << argv[4] << "\n";
    return 1;
  }
  std::cout << aar_sim::HighAltitudeSigma(o.intensity, o.altitude) << " "
            << aar_sim::kDrydenScaleLength << " " << o.airspeed << " " << o.step << "\n";
  return 0;
}
