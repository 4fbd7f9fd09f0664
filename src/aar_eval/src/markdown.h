// Markdown the report writers (report.cpp, suite.cpp, worlds.cpp) share: tables described once
// by their columns, and the run section; not installed.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "aar_eval/tables.h"

namespace aar_eval {

enum class Align { kLeft, kRight };

// One column of a table whose rows are of type Row: its header, its alignment, its cell.
template <class Row>
struct Column {
  std::string header;
  Align align;
  std::function<std::string(const Row&)> cell;
};

template <class Row>
using Columns = std::vector<Column<Row>>;

// "| a | b |" and a line end.
void WriteMarkdownRow(std::ostream& out, const std::vector<std::string>& cells);

// The rule under a table's header: "|---|---:|" and a line end.
void WriteMarkdownRule(std::ostream& out, const std::vector<Align>& aligns);

// The header line and the rule under it.
template <class Row>
void WriteTableHead(std::ostream& out, const Columns<Row>& columns) {
  std::vector<std::string> headers;
  std::vector<Align> aligns;
  for (const auto& c : columns) {
    headers.push_back(c.header);
    aligns.push_back(c.align);
  }
  WriteMarkdownRow(out, headers);
  WriteMarkdownRule(out, aligns);
}

template <class Row>
void WriteTableRow(std::ostream& out, const Columns<Row>& columns, const Row& row) {
  std::vector<std::string> cells;
  for (const auto& c : columns) cells.push_back(c.cell(row));
  WriteMarkdownRow(out, cells);
}

// The column header of region `key` of RegionTitles(): "region A", ..., "whole approach".
std::string RegionColumnHeader(const std::string& key);

// `value` with `digits` decimals.
std::string Fixed(double value, int digits);

// "## Run" and DIR/run.txt in a code block, if DIR has a run.txt that is not empty.
void WriteRunSection(std::ostream& out, const std::string& dir);

// "E: N of M frames outside the regions (...), in no table" over `runs` (one run's frames, or
// every approach's), or "" when N is 0.
std::string OutsideRegionsNote(const std::string& experiment,
                               const std::vector<const std::vector<FrameRecord>*>& runs);

}  // namespace aar_eval
