#include "markdown.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace aar_eval {

void WriteMarkdownRow(std::ostream& out, const std::vector<std::string>& cells) {
  out << "|";
  for (const auto& cell : cells) out << ' ' << cell << " |";
  out << "\n";
}

void WriteMarkdownRule(std::ostream& out, const std::vector<Align>& aligns) {
  out << "|";
  for (Align align : aligns) out << (align == Align::kRight ? "---:|" : "---|");
  out << "\n";
}

std::string RegionColumnHeader(const std::string& key) {
  return key == "all" ? "whole approach" : "region " + key;
}

std::string Fixed(double value, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << value;
  return s.str();
}

void WriteRunSection(std::ostream& out, const std::string& dir) {
  std::ifstream run(dir + "/run.txt");
  if (run && run.peek() != std::ifstream::traits_type::eof())
    out << "## Run\n\n```\n" << run.rdbuf() << "```\n\n";
}

std::string OutsideRegionsNote(const std::string& experiment,
                               const std::vector<const std::vector<FrameRecord>*>& runs) {
  size_t outside = 0, frames = 0;
  for (const std::vector<FrameRecord>* run : runs) {
    frames += run->size();
    outside += std::count_if(run->begin(), run->end(), [](const FrameRecord& f) {
      return f.region == aar_geometry::Region::kOutside;
    });
  }
  if (outside == 0) return "";
  return experiment + ": " + std::to_string(outside) + " of " + std::to_string(frames) +
         " frames outside the regions (a range under 32 m or over 175 m, or not finite), in no "
         "table";
}

}  // namespace aar_eval
