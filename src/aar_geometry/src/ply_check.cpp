#include "mesh_check.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "aar_geometry/load_error.h"

namespace aar_geometry {
namespace {

struct PlyProperty {
  bool list = false;
  int count_size = 0, value_size = 0;  // bytes; the count only for lists
  bool value_integer = false, count_signed = false;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  int lines = 0;  // before the end_header line
};

// Where a PLY file's parts begin: the "end_header" that ends its header, and its body.
struct PlyLayout {
  size_t end_header = 0;
  size_t body = 0;
};

// PLY's value types: bytes, integer.
const std::map<std::string, std::pair<int, bool>>& PlyTypes() {
  static const std::map<std::string, std::pair<int, bool>> types = {
      {"char", {1, true}},    {"int8", {1, true}},     {"uchar", {1, true}},
      {"uint8", {1, true}},   {"short", {2, true}},    {"int16", {2, true}},
      {"ushort", {2, true}},  {"uint16", {2, true}},   {"int", {4, true}},
      {"int32", {4, true}},   {"uint", {4, true}},     {"uint32", {4, true}},
      {"float", {4, false}},  {"float32", {4, false}}, {"double", {8, false}},
      {"float64", {8, false}}};
  return types;
}

// A number as PLY writes it (assimp's parsers take no hex, inf or nan): [+-]digits for an
// integer, else digits with an optional fraction and exponent.
bool IsDecimal(const std::string& token, bool integer) {
  size_t i = token[0] == '+' || token[0] == '-';
  const auto digits = [&]() {
    const size_t start = i;
    while (i < token.size() && std::isdigit(static_cast<unsigned char>(token[i]))) ++i;
    return i - start;
  };
  size_t count = digits();
  if (integer) return count > 0 && i == token.size();
  if (i < token.size() && token[i] == '.') {
    ++i;
    count += digits();
  }
  if (count == 0) return false;
  if (i < token.size() && (token[i] == 'e' || token[i] == 'E')) {
    ++i;
    i += i < token.size() && (token[i] == '+' || token[i] == '-');
    if (digits() == 0) return false;
  }
  return i == token.size();
}

// The "ply" magic; "end_header" a line of its own within the first 64 KiB (a property named
// "x:end_header" does not end the header for assimp, which then read the body as header and out
// of bounds: found by the mesh fuzz target); a header of printable text (assimp's header parser
// reads garbage differently: a NUL ends its line).
PlyLayout FindPlyHeader(const std::string& path, const std::string& text) {
  if (text.rfind("ply", 0) != 0) throw LoadError(path, "not a PLY file (no 'ply' magic)");
  size_t end = text.find("end_header");
  while (end != std::string::npos && end <= 65536 &&
         text.find_last_not_of(" \t", end - 1) != text.rfind('\n', end - 1))
    end = text.find("end_header", end + 1);
  if (end == std::string::npos || end > 65536)
    throw LoadError(path, "PLY header is incomplete (no end_header line)");
  const size_t line_end = text.find('\n', end);
  if (line_end == std::string::npos || text.find_first_not_of(" \t\r", end + 10) != line_end)
    throw LoadError(path, "PLY end_header must end its line");
  for (size_t i = 0; i < end; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 && c != '\n' && c != '\r' && c != '\t')
      throw LoadError(path,
                      "PLY header holds a control character (byte " + std::to_string(i) + ")");
  }
  return {end, line_end + 1};
}

// One line of a PLY header as words, its keyword first ("" on a blank line).
struct PlyHeaderLine {
  const std::string& path;
  int number = 0;
  std::vector<std::string> words;

  const std::string& keyword() const { return words[0]; }

  [[noreturn]] void Fail(const std::string& what) const {
    throw LoadError(path, "PLY header line " + std::to_string(number) + ": " + what);
  }

  // Fails unless the line has `n` words, the keyword included.
  void ExpectWords(size_t n) const {
    if (words.size() != n) {
      Fail("'" + keyword() + "' needs " + std::to_string(n - 1) + " words after it, not " +
           std::to_string(words.size() - 1));
    }
  }
};

// "format ascii|binary_little_endian|binary_big_endian VERSION", once, before the elements.
void ParsePlyFormat(const PlyHeaderLine& line, PlyHeader& header) {
  line.ExpectWords(3);
  if (!header.format.empty() || !header.elements.empty())
    line.Fail("'format' must come once, before elements");
  header.format = line.words[1];
  if (header.format != "ascii" && header.format != "binary_little_endian" &&
      header.format != "binary_big_endian")
    line.Fail("unknown format '" + header.format + "'");
}

// "element NAME COUNT", the count a whole number of at most 10 digits.
PlyElement ParsePlyElement(const PlyHeaderLine& line) {
  line.ExpectWords(3);
  PlyElement e;
  e.name = line.words[1];
  const std::string& count = line.words[2];
  if (count.empty() || count.size() > 10 ||
      count.find_first_not_of("0123456789") != std::string::npos)
    line.Fail("element '" + e.name + "' needs a count, not '" + count + "'");
  e.count = std::stoull(count);
  return e;
}

// "property TYPE NAME" or "property list COUNT_TYPE TYPE NAME", the count type an integer.
PlyProperty ParsePlyProperty(const PlyHeaderLine& line) {
  const auto& types = PlyTypes();
  PlyProperty p;
  std::string type = line.words.size() > 1 ? line.words[1] : "";
  line.ExpectWords(type == "list" ? 5 : 3);
  if (type == "list") {
    p.list = true;
    type = line.words[2];
    const auto count_type = types.find(type);
    if (count_type == types.end() || !count_type->second.second)
      line.Fail("a list needs an integer count type, not '" + type + "'");
    p.count_size = count_type->second.first;
    p.count_signed = type[0] != 'u';
    type = line.words[3];
  }
  const auto value_type = types.find(type);
  if (value_type == types.end()) line.Fail("unknown property type '" + type + "'");
  p.value_size = value_type->second.first;
  p.value_integer = value_type->second.second;
  return p;
}

// The header before end_header, each line one of the header's forms with its number of words
// (assimp crashed on a header that declared nothing here: found by the mesh fuzz target).
PlyHeader ParsePlyHeader(const std::string& path, const std::string& header_text) {
  PlyHeader header;
  std::istringstream lines(header_text);
  for (std::string text_line; std::getline(lines, text_line);) {
    PlyHeaderLine line{path, ++header.lines, {}};
    std::istringstream words(text_line);
    std::string keyword;
    words >> keyword;
    line.words.push_back(keyword);
    for (std::string word; words >> word;) line.words.push_back(word);
    if (line.number == 1) {
      if (text_line != "ply" && text_line != "ply\r") line.Fail("the first line must be 'ply'");
    } else if (keyword.empty() || keyword == "comment" || keyword == "obj_info") {
      continue;
    } else if (keyword == "format") {
      ParsePlyFormat(line, header);
    } else if (keyword == "element") {
      header.elements.push_back(ParsePlyElement(line));
    } else if (keyword == "property") {
      if (header.elements.empty()) line.Fail("a property before any element");
      header.elements.back().properties.push_back(ParsePlyProperty(line));
    } else {
      line.Fail("unknown keyword '" + keyword + "'");
    }
  }
  return header;
}

// A format, an element, and properties for each element that has instances.
void CheckPlyDeclarations(const std::string& path, const PlyHeader& header) {
  if (header.format.empty()) throw LoadError(path, "PLY header has no format line");
  if (header.elements.empty()) throw LoadError(path, "PLY header declares no element");
  for (const auto& e : header.elements) {
    if (e.properties.empty() && e.count > 0)
      throw LoadError(path, "PLY element '" + e.name + "' has no properties");
  }
}

// The next line of an ASCII body that is not blank, for instance i of element e; advances `pos`
// and `line` past it.
std::string NextAsciiPlyLine(const std::string& path, const std::string& text, const PlyElement& e,
                             uint64_t i, size_t& pos, int& line) {
  std::string text_line;
  while (text_line.find_first_not_of(" \t\r") == std::string::npos) {
    if (pos >= text.size()) {
      throw LoadError(path, "PLY body ends before instance " + std::to_string(i) + " of element '" +
                                e.name + "' (of " + std::to_string(e.count) + ")");
    }
    const size_t eol = std::min(text.find('\n', pos), text.size());
    text_line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line;
  }
  return text_line;
}

// One instance of element e on ASCII line `line`: each property a number, a list's values led by
// its length, and nothing more.
void CheckAsciiPlyInstance(const std::string& path, const PlyElement& e,
                           const std::string& text_line, int line) {
  const auto fail = [&](const std::string& what) {
    throw LoadError(path, "PLY line " + std::to_string(line) + ": " + what);
  };
  std::istringstream values(text_line);
  const auto number = [&](bool integer) {
    std::string token;
    values >> token;
    if (token.empty()) fail("too few values for element '" + e.name + "'");
    if (!IsDecimal(token, integer))
      fail("'" + token + "' is not " + (integer ? "an integer" : "a number"));
    return std::strtod(token.c_str(), nullptr);
  };
  for (const auto& p : e.properties) {
    const double n = p.list ? number(true) : 1.0;
    if (n < 0 || n > 1e6) fail("list length " + std::to_string(n) + " out of range");
    for (int k = 0; k < static_cast<int>(n); ++k) number(p.value_integer);
  }
  std::string extra;
  if (values >> extra)
    fail("more values than element '" + e.name + "' has properties ('" + extra + "')");
}

// An ASCII body from `pos`: one line per instance (blank lines skipped).
void CheckAsciiPlyBody(const std::string& path, const std::string& text, size_t pos,
                       const PlyHeader& header) {
  int line = header.lines + 1;
  for (const auto& e : header.elements) {
    for (uint64_t i = 0; i < e.count; ++i) {
      const std::string values = NextAsciiPlyLine(path, text, e, i, pos, line);
      CheckAsciiPlyInstance(path, e, values, line);
    }
  }
}

// The length of element e's list p at `at`, in the body's byte order.
uint64_t BinaryPlyListLength(const std::string& path, const char* at, const PlyElement& e,
                             const PlyProperty& p, bool big_endian) {
  unsigned char bytes[4] = {0, 0, 0, 0};
  std::memcpy(bytes, at, p.count_size);
  uint32_t raw = 0;
  for (int b = 0; b < p.count_size; ++b)
    raw |= uint32_t{bytes[big_endian ? p.count_size - 1 - b : b]} << (8 * b);
  const bool negative = p.count_signed && (raw >> (8 * p.count_size - 1)) & 1u;
  if (negative) throw LoadError(path, "PLY element '" + e.name + "' has a negative list");
  return raw;
}

// A binary body from `pos`: walks the values; every list's length comes from the body.
void CheckBinaryPlyBody(const std::string& path, const std::string& text, size_t pos,
                        const PlyHeader& header) {
  const bool big_endian = header.format == "binary_big_endian";
  for (const auto& e : header.elements) {
    for (uint64_t i = 0; i < e.count; ++i) {
      const auto ends_inside = [&]() {
        return "PLY body ends inside instance " + std::to_string(i) + " of element '" + e.name +
               "'";
      };
      for (const auto& p : e.properties) {
        uint64_t n = 1;
        if (p.list) {
          if (pos + p.count_size > text.size()) throw LoadError(path, ends_inside());
          n = BinaryPlyListLength(path, text.data() + pos, e, p, big_endian);
          pos += p.count_size;
        }
        if (pos + n * p.value_size > text.size())
          throw LoadError(path, ends_inside() + " (of " + std::to_string(e.count) + ")");
        pos += n * p.value_size;
      }
      if (pos > text.size()) throw LoadError(path, "PLY body ends inside element '" + e.name + "'");
    }
  }
}

}  // namespace

// A PLY file whose body holds what its header declares: each element's instances with every
// property (list lengths read from the body), as ASCII lines of numbers or as binary values.
// Debian's assimp 5.2 loops forever on a header without end_header, reads out of bounds (SIGSEGV)
// on a binary body it misplaces or that is too short, and leaks on an ASCII line it cannot
// parse (the last two found by the mesh fuzz target). Throws LoadError saying what is wrong.
void CheckPly(const std::string& path, const std::string& text) {
  const PlyLayout layout = FindPlyHeader(path, text);
  const PlyHeader header = ParsePlyHeader(path, text.substr(0, layout.end_header));
  CheckPlyDeclarations(path, header);
  if (header.format == "ascii")
    CheckAsciiPlyBody(path, text, layout.body, header);
  else
    CheckBinaryPlyBody(path, text, layout.body, header);
}

}  // namespace aar_geometry
