// mount_visibility: what each candidate camera mount would see of the receiver over a suite's
// approaches, to choose a second rig's mount (docs/AVAILABILITY.md). Only the simulator's own
// visibility is rendered (World::MeasureVisibility: the receiver's silhouette drawn alone against
// the scene with the boom), one label pair a mount and frame; nothing flies.
//   mount_visibility [--receiver DESCRIPTION] [--csv FILE] [--every N] SEED COUNT
//                    NAME=X,Y,Z[,YAW,PITCH]...
// Approach i (1..COUNT) is aar_sim::VariedApproach(SEED * 1000 + i) at its 10 Hz rows: the frames
// of `scripts/run --suite COUNT --seed SEED --rate 10` in the ideal world (--every N: every Nth
// of them, N times quicker; about 23 ms a mount and frame on 2 cores). A mount is the rig's
// centre in the tanker frame [m], looking aft (YAW 180) and PITCH deg down (25), with the default
// rig's cameras (1280x960, 60 deg, 0.5 m baseline). The first mount is the one flown today: each
// other mount is also counted together with it (a frame seen by either rig: the better rig's
// weaker camera, since stereo needs both cameras of one rig). Prints, over region A's frames (70
// to 175 m), how many have the weaker camera at 25, 50 and 75 % or more; --csv writes every
// frame's fractions (approach, t, range, then left and right for each mount).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <aar_description/boom_model.h>
#include <aar_description/receiver_description.h>
#include <aar_geometry/pose_error.h>
#include <ros/package.h>

#include "aar_sim/approach.h"
#include "aar_sim/world.h"

namespace {

const double kBands[] = {0.25, 0.50, 0.75};

struct Mount {
  std::string name;
  aar_sim::StereoRig rig;
  std::string where;            // as given
  int seen[3] = {0, 0, 0};      // region A frames with the weaker camera >= each band
  int together[3] = {0, 0, 0};  // ... of the better of this rig and the first
};

struct Arguments {
  std::string receiver;  // a receiver description; empty: the C-12
  std::string csv;
  int every = 1;  // every Nth region A row
  uint64_t seed = 1;
  int count = 0;
  std::vector<Mount> mounts;
};

std::vector<double> Numbers(const std::string& text) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    size_t used = 0;
    v.push_back(std::stod(item, &used));
    if (used != item.size()) throw std::invalid_argument(item);
  }
  return v;
}

// NAME=X,Y,Z[,YAW,PITCH] with the default rig's cameras.
Mount ParseMount(const std::string& text, const aar_sim::StereoRig& cameras) {
  const size_t eq = text.find('=');
  std::vector<double> v;
  try {
    if (eq != std::string::npos && eq > 0) v = Numbers(text.substr(eq + 1));
  } catch (const std::exception&) {
    v.clear();
  }
  if (v.size() != 3 && v.size() != 5) {
    throw std::runtime_error("mount_visibility: a mount is NAME=X,Y,Z[,YAW,PITCH], not '" + text +
                             "'");
  }
  Mount m;
  m.name = text.substr(0, eq);
  m.where = text.substr(eq + 1);
  m.rig = aar_sim::MakeStereoRig(cameras.intrinsics, cameras.baseline, {v[0], v[1], v[2]},
                                 v.size() == 5 ? v[3] : 180.0, v.size() == 5 ? v[4] : 25.0);
  return m;
}

Arguments ParseArguments(int argc, char** argv, const aar_sim::StereoRig& cameras) {
  Arguments args;
  int i = 1;
  for (; i + 1 < argc && std::string(argv[i]).rfind("--", 0) == 0; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--receiver") {
      args.receiver = value;
    } else if (flag == "--csv") {
      args.csv = value;
    } else if (flag == "--every" && !value.empty() &&
               value.find_first_not_of("0123456789") == std::string::npos && std::stoi(value) > 0) {
      args.every = std::stoi(value);
    } else {
      throw std::runtime_error("mount_visibility: unknown option or bad value: " + flag + " " +
                               value);
    }
  }
  if (argc - i < 3) {
    throw std::runtime_error(
        "usage: mount_visibility [--receiver DESCRIPTION] [--csv FILE] [--every N] SEED COUNT "
        "NAME=X,Y,Z[,YAW,PITCH]...");
  }
  const std::string seed = argv[i], count = argv[i + 1];
  if (seed.find_first_not_of("0123456789") != std::string::npos || seed.empty() ||
      count.find_first_not_of("0123456789") != std::string::npos || count.empty() ||
      std::stoi(count) < 1) {
    throw std::runtime_error("mount_visibility: SEED and COUNT are whole numbers (COUNT >= 1)");
  }
  args.seed = std::stoull(seed);
  args.count = std::stoi(count);
  for (i += 2; i < argc; ++i) args.mounts.push_back(ParseMount(argv[i], cameras));
  return args;
}

double Weaker(const std::array<aar_sim::ViewVisibility, 2>& v) {
  const double l = v[0].fraction(), r = v[1].fraction();
  return std::isnan(l) || std::isnan(r) ? 0.0 : std::min(l, r);  // out of a view: nothing
}

void Count(double fraction, int* counts) {
  for (int b = 0; b < 3; ++b) counts[b] += fraction >= kBands[b];
}

// Every region A row of the suite's approaches through every mount; the region A frame count.
int Measure(aar_sim::World& world, Arguments& args, std::ostream* csv) {
  const auto links = aar_geometry::ComputeLinkPoses(
      world.boom_model(), aar_description::BoomJointPositions(aar_description::DefaultBoomPose()));
  const Eigen::Vector3d tip = links.at("nozzle_tip").translation();
  int frames = 0, rows = 0;
  for (int a = 1; a <= args.count; ++a) {
    aar_sim::ApproachOptions o = aar_sim::VariedApproach(args.seed * 1000 + a);
    o.receptacle = world.options().receiver.receptacle;
    for (const aar_sim::FlightPathRow& row : aar_sim::GenerateApproach(o, tip)) {
      const double range = row.position_m.norm();
      if (aar_geometry::RegionOfRange(range) != aar_geometry::Region::kA) continue;
      if (rows++ % args.every != 0) continue;
      ++frames;
      const aar_sim::BoomPose boom = row.boom.value_or(aar_description::DefaultBoomPose());
      if (csv) *csv << o.seed << ',' << row.t << ',' << range;
      double first = 0.0;
      for (size_t m = 0; m < args.mounts.size(); ++m) {
        const auto v = world.MeasureVisibility(row, boom, args.mounts[m].rig);
        if (csv) *csv << ',' << v[0].fraction() << ',' << v[1].fraction();
        const double weaker = Weaker(v);
        if (m == 0) first = weaker;
        Count(weaker, args.mounts[m].seen);
        Count(std::max(first, weaker), args.mounts[m].together);
      }
      if (csv) *csv << '\n';
    }
    std::cerr << "mount_visibility: approach " << o.seed << " done\n";
  }
  return frames;
}

void Print(const Arguments& args, int frames) {
  std::cout << "Region A frames: " << frames << " (suite seed " << args.seed << ", " << args.count
            << " approaches"
            << (args.every > 1 ? ", every " + std::to_string(args.every) + "th" : "")
            << "). Frames whose weaker camera sees at least 25 / 50 / 75 % of the "
               "receiver; with "
            << args.mounts[0].name << ": either rig.\n\n"
            << "| mount | centre, yaw, pitch | >= 25 % | >= 50 % | >= 75 % | with "
            << args.mounts[0].name << ": >= 25 % | >= 50 % | >= 75 % |\n"
            << "|---|---|---:|---:|---:|---:|---:|---:|\n";
  auto pct = [frames](int n) {
    std::ostringstream s;
    s << n << " (" << std::fixed << std::setprecision(1) << 100.0 * n / std::max(frames, 1)
      << " %)";
    return s.str();
  };
  for (const Mount& m : args.mounts) {
    std::cout << "| " << m.name << " | " << m.where << " | " << pct(m.seen[0]) << " | "
              << pct(m.seen[1]) << " | " << pct(m.seen[2]) << " | " << pct(m.together[0]) << " | "
              << pct(m.together[1]) << " | " << pct(m.together[2]) << " |\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    aar_sim::WorldOptions options =
        aar_sim::DefaultWorldOptions(ros::package::getPath("aar_description") + "/models");
    Arguments args = ParseArguments(argc, argv, options.rig);
    if (args.mounts.empty()) throw std::runtime_error("mount_visibility: name at least one mount");
    if (!args.receiver.empty()) {
      options.receiver = aar_description::LoadReceiverDescription(args.receiver);
      if (!options.receiver.has_receptacle) {
        throw std::runtime_error("mount_visibility: " + args.receiver + ": no receptacle");
      }
    }
    aar_sim::World world(options);
    std::ofstream csv;
    if (!args.csv.empty()) {
      csv.open(args.csv);
      if (!csv) throw std::runtime_error("mount_visibility: cannot write " + args.csv);
      csv << "approach,t,range";
      for (const Mount& m : args.mounts) csv << ',' << m.name << "_left," << m.name << "_right";
      csv << '\n';
    }
    const int frames = Measure(world, args, args.csv.empty() ? nullptr : &csv);
    Print(args, frames);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
}
