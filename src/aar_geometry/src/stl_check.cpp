#include "mesh_check.h"

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "aar_geometry/load_error.h"

namespace aar_geometry {
namespace {

// The whitespace-separated tokens of an ASCII STL, counting lines; failures name the line.
class StlTokens {
 public:
  StlTokens(const std::string& path, const std::string& text) : path_(path), text_(text) {}

  // The next token ("" at the end).
  std::string Next() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      line_ += text_[pos_] == '\n';
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return text_.substr(start, pos_ - start);
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw LoadError(path_, "ASCII STL line " + std::to_string(line_) + ": " + what);
  }

  void Expect(const char* keyword) {
    const std::string token = Next();
    if (token != keyword) Fail(std::string("expected '") + keyword + "', found '" + token + "'");
  }

  // Three numbers, as `what` ("vertex", "facet normal") needs them.
  void ExpectNumbers(const char* what) {
    for (int k = 0; k < 3; ++k) {
      const std::string token = Next();
      char* end = nullptr;
      std::strtod(token.c_str(), &end);
      if (token.empty() || end != token.c_str() + token.size())
        Fail(std::string(what) + " needs three numbers, found '" + token + "'");
    }
  }

  void SkipRestOfLine() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }

  const std::string& text() const { return text_; }
  size_t pos() const { return pos_; }
  int line() const { return line_; }

 private:
  const std::string& path_;
  const std::string& text_;
  size_t pos_ = 0;
  int line_ = 1;
};

// After "solid": its name (any first word on the line) and the words after it on the line, which
// assimp skips too. Returns the token after them.
std::string SkipStlSolidName(StlTokens& stl) {
  const int solid_line = stl.line();
  std::string token = stl.Next();
  if (!token.empty() && stl.line() == solid_line) {
    if (token.size() >= 1024) stl.Fail("solid name of 1024 characters or more");
    token = stl.Next();
    while (!token.empty() && stl.line() == solid_line && token != "facet" && token != "vertex" &&
           token != "endsolid")
      token = stl.Next();
  }
  return token;
}

// After "facet": "normal n n n" on the facet's line, "outer loop", three "vertex x y z",
// "endloop", "endfacet".
void CheckStlFacet(StlTokens& stl) {
  const size_t after_facet = stl.pos();
  stl.Expect("normal");
  if (stl.text().find_first_not_of(" \t", after_facet) != stl.pos() - 6)
    stl.Fail("'normal' must follow 'facet' on its line");
  stl.ExpectNumbers("facet normal");
  stl.Expect("outer");
  stl.Expect("loop");
  for (int v = 0; v < 3; ++v) {
    stl.Expect("vertex");
    stl.ExpectNumbers("vertex");
  }
  stl.Expect("endloop");
  stl.Expect("endfacet");
}

// An ASCII STL as the standard writes it: solids of facets, each "facet normal n n n / outer
// loop / vertex x y z (three times) / endloop / endfacet", and "endsolid" (or the file's end).
// Debian's assimp 5.2 leaks a mesh and a node on a solid whose vertex count is not a multiple of
// three or whose facets lack normals ("normal" not on the facet's line, a vertex outside a facet)
// and on a name of 1024 characters or more (found by the mesh fuzz target). Throws LoadError
// naming the line.
void CheckAsciiStl(const std::string& path, const std::string& text) {
  if (text.find('\0') != std::string::npos) throw LoadError(path, "ASCII STL holds a NUL byte");
  StlTokens stl(path, text);
  std::string token = stl.Next();
  while (!token.empty()) {
    if (token != "solid") stl.Fail("expected 'solid', found '" + token + "'");
    for (token = SkipStlSolidName(stl); token == "facet"; token = stl.Next()) CheckStlFacet(stl);
    if (token.empty()) break;  // assimp takes the file's end for "endsolid"
    if (token != "endsolid") stl.Fail("expected 'facet' or 'endsolid', found '" + token + "'");
    stl.SkipRestOfLine();
    token = stl.Next();
  }
}

}  // namespace

// assimp's test: binary when the size is 84 bytes plus 50 per facet of the count at byte 80,
// else ASCII when "solid" comes first (after spaces and tabs). Only ASCII is checked.
void CheckStl(const std::string& path, const std::string& text) {
  if (text.size() >= 84) {
    uint32_t facets = 0;
    std::memcpy(&facets, text.data() + 80, sizeof(facets));
    if (84 + 50 * static_cast<uint64_t>(facets) == text.size()) return;
  }
  const size_t first = text.find_first_not_of(" \t");
  if (first != std::string::npos && text.compare(first, 5, "solid") == 0) CheckAsciiStl(path, text);
}

}  // namespace aar_geometry
