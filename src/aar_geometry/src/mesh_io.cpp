#include "aar_geometry/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <optional>
#include <sstream>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "aar_geometry/load_error.h"

namespace aar_geometry {

namespace {

std::string Lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The value of attribute `name` in an XML start tag ("<tag a=\"1\" b='2'"), if it has one.
std::optional<std::string> XmlAttribute(const std::string& start_tag, const std::string& name) {
  for (size_t at = start_tag.find(name); at != std::string::npos;
       at = start_tag.find(name, at + 1)) {
    if (at == 0 || !std::isspace(static_cast<unsigned char>(start_tag[at - 1]))) continue;
    size_t eq = start_tag.find_first_not_of(" \t\r\n", at + name.size());
    if (eq == std::string::npos || start_tag[eq] != '=') continue;
    const size_t quote = start_tag.find_first_not_of(" \t\r\n", eq + 1);
    if (quote == std::string::npos || (start_tag[quote] != '"' && start_tag[quote] != '\''))
      continue;
    const size_t end = start_tag.find(start_tag[quote], quote + 1);
    if (end == std::string::npos) return std::nullopt;
    return start_tag.substr(quote + 1, end - quote - 1);
  }
  return std::nullopt;
}

// An ASCII STL as the standard writes it: solids of facets, each "facet normal n n n / outer
// loop / vertex x y z (three times) / endloop / endfacet", and "endsolid" (or the file's end).
// Debian's assimp 5.2 leaks a mesh and a node on a solid whose vertex count is not a multiple of
// three or whose facets lack normals ("normal" not on the facet's line, a vertex outside a facet)
// and on a name of 1024 characters or more (found by the mesh fuzz target). Words after the
// name on the solid's line are skipped, as assimp skips them. Throws LoadError naming the line.
void CheckAsciiStl(const std::string& path, const std::string& text) {
  if (text.find('\0') != std::string::npos) throw LoadError(path, "ASCII STL holds a NUL byte");
  size_t pos = 0;
  int line = 1;
  // The next whitespace-separated token ("" at the end), counting lines.
  const auto next = [&]() {
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) {
      line += text[pos] == '\n';
      ++pos;
    }
    const size_t start = pos;
    while (pos < text.size() && !std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
    return text.substr(start, pos - start);
  };
  const auto fail = [&](const std::string& what) {
    throw LoadError(path, "ASCII STL line " + std::to_string(line) + ": " + what);
  };
  const auto expect = [&](const char* keyword) {
    const std::string token = next();
    if (token != keyword) fail(std::string("expected '") + keyword + "', found '" + token + "'");
  };
  const auto numbers = [&](const char* what) {
    for (int k = 0; k < 3; ++k) {
      const std::string token = next();
      char* end = nullptr;
      std::strtod(token.c_str(), &end);
      if (token.empty() || end != token.c_str() + token.size())
        fail(std::string(what) + " needs three numbers, found '" + token + "'");
    }
  };
  std::string token = next();
  while (!token.empty()) {
    if (token != "solid") fail("expected 'solid', found '" + token + "'");
    const int solid_line = line;
    token = next();
    if (!token.empty() && line == solid_line) {  // the name: any first word
      if (token.size() >= 1024) fail("solid name of 1024 characters or more");
      token = next();
      while (!token.empty() && line == solid_line && token != "facet" && token != "vertex" &&
             token != "endsolid")
        token = next();
    }
    for (; token == "facet"; token = next()) {
      const size_t after_facet = pos;
      expect("normal");
      if (text.find_first_not_of(" \t", after_facet) != pos - 6)
        fail("'normal' must follow 'facet' on its line");
      numbers("facet normal");
      expect("outer");
      expect("loop");
      for (int v = 0; v < 3; ++v) {
        expect("vertex");
        numbers("vertex");
      }
      expect("endloop");
      expect("endfacet");
    }
    if (token.empty()) break;  // assimp takes the file's end for "endsolid"
    if (token != "endsolid") fail("expected 'facet' or 'endsolid', found '" + token + "'");
    while (pos < text.size() && text[pos] != '\n') ++pos;  // the rest of its line
    token = next();
  }
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

// A PLY file whose body holds what its header declares: each element's instances with every
// property (list lengths read from the body), as ASCII lines of numbers or as binary values.
// Debian's assimp 5.2 loops forever on a header without end_header, reads out of bounds (SIGSEGV)
// on a binary body it misplaces or that is too short, and leaks on an ASCII line it cannot
// parse (the last two found by the mesh fuzz target). Throws LoadError saying what is wrong.
void CheckPly(const std::string& path, const std::string& text) {
  if (text.rfind("ply", 0) != 0) throw LoadError(path, "not a PLY file (no 'ply' magic)");
  // The first line that is "end_header" (a property named "x:end_header" does not end the
  // header for assimp, which then read the body as header and out of bounds: found by the mesh
  // fuzz target).
  size_t end = text.find("end_header");
  while (end != std::string::npos && end <= 65536 &&
         text.find_last_not_of(" \t", end - 1) != text.rfind('\n', end - 1))
    end = text.find("end_header", end + 1);
  if (end == std::string::npos || end > 65536)
    throw LoadError(path, "PLY header is incomplete (no end_header line)");
  const size_t body_start = text.find('\n', end);
  if (body_start == std::string::npos || text.find_first_not_of(" \t\r", end + 10) != body_start)
    throw LoadError(path, "PLY end_header must end its line");
  // Printable text, each line one of the header's forms with its number of words: assimp's
  // header parser reads garbage differently (a NUL ends its line) and crashed on a header that
  // declared nothing here (found by the mesh fuzz target).
  for (size_t i = 0; i < end; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 && c != '\n' && c != '\r' && c != '\t')
      throw LoadError(path,
                      "PLY header holds a control character (byte " + std::to_string(i) + ")");
  }

  struct Property {
    bool list = false;
    int count_size = 0, value_size = 0;  // bytes; the count only for lists
    bool value_integer = false, count_signed = false;
  };
  struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
  };
  static const std::map<std::string, std::pair<int, bool>> kTypes = {
      // bytes, integer
      {"char", {1, true}},    {"int8", {1, true}},     {"uchar", {1, true}},
      {"uint8", {1, true}},   {"short", {2, true}},    {"int16", {2, true}},
      {"ushort", {2, true}},  {"uint16", {2, true}},   {"int", {4, true}},
      {"int32", {4, true}},   {"uint", {4, true}},     {"uint32", {4, true}},
      {"float", {4, false}},  {"float32", {4, false}}, {"double", {8, false}},
      {"float64", {8, false}}};
  std::string format;
  std::vector<Element> elements;
  std::istringstream header(text.substr(0, end));
  int line_number = 0;
  for (std::string line; std::getline(header, line);) {
    ++line_number;
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    const auto fail = [&](const std::string& what) {
      throw LoadError(path, "PLY header line " + std::to_string(line_number) + ": " + what);
    };
    std::vector<std::string> all = {keyword};
    for (std::string word; words >> word;) all.push_back(word);
    const auto expect_words = [&](size_t n) {
      if (all.size() != n) {
        fail("'" + keyword + "' needs " + std::to_string(n - 1) + " words after it, not " +
             std::to_string(all.size() - 1));
      }
    };
    if (line_number == 1) {
      if (line != "ply" && line != "ply\r") fail("the first line must be 'ply'");
    } else if (keyword.empty() || keyword == "comment" || keyword == "obj_info") {
      continue;
    } else if (keyword == "format") {
      expect_words(3);
      if (!format.empty() || !elements.empty()) fail("'format' must come once, before elements");
      format = all[1];
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        fail("unknown format '" + format + "'");
    } else if (keyword == "element") {
      expect_words(3);
      Element e;
      e.name = all[1];
      const std::string& count = all[2];
      if (count.empty() || count.size() > 10 ||
          count.find_first_not_of("0123456789") != std::string::npos)
        fail("element '" + e.name + "' needs a count, not '" + count + "'");
      e.count = std::stoull(count);
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) fail("a property before any element");
      Property p;
      std::string type = all.size() > 1 ? all[1] : "";
      expect_words(type == "list" ? 5 : 3);
      if (type == "list") {
        p.list = true;
        type = all[2];
        const auto count_type = kTypes.find(type);
        if (count_type == kTypes.end() || !count_type->second.second)
          fail("a list needs an integer count type, not '" + type + "'");
        p.count_size = count_type->second.first;
        p.count_signed = type[0] != 'u';
        type = all[3];
      }
      const auto value_type = kTypes.find(type);
      if (value_type == kTypes.end()) fail("unknown property type '" + type + "'");
      p.value_size = value_type->second.first;
      p.value_integer = value_type->second.second;
      elements.back().properties.push_back(p);
    } else {
      fail("unknown keyword '" + keyword + "'");
    }
  }
  if (format.empty()) throw LoadError(path, "PLY header has no format line");
  if (elements.empty()) throw LoadError(path, "PLY header declares no element");
  for (const auto& e : elements) {
    if (e.properties.empty() && e.count > 0)
      throw LoadError(path, "PLY element '" + e.name + "' has no properties");
  }

  size_t pos = body_start + 1;
  if (format == "ascii") {
    // One line per instance (blank lines skipped), each property a number, lists led by theirs.
    int line = line_number + 1;
    for (const auto& e : elements) {
      for (uint64_t i = 0; i < e.count; ++i) {
        std::string text_line;
        while (text_line.find_first_not_of(" \t\r") == std::string::npos) {
          if (pos >= text.size()) {
            throw LoadError(path, "PLY body ends before instance " + std::to_string(i) +
                                      " of element '" + e.name + "' (of " +
                                      std::to_string(e.count) + ")");
          }
          const size_t eol = std::min(text.find('\n', pos), text.size());
          text_line = text.substr(pos, eol - pos);
          pos = eol + 1;
          ++line;
        }
        std::istringstream values(text_line);
        const auto number = [&](bool integer) {
          std::string token;
          values >> token;
          if (token.empty()) {
            throw LoadError(path, "PLY line " + std::to_string(line) + ": too few values for " +
                                      "element '" + e.name + "'");
          }
          if (!IsDecimal(token, integer))
            throw LoadError(path, "PLY line " + std::to_string(line) + ": '" + token + "' is not " +
                                      (integer ? "an integer" : "a number"));
          return std::strtod(token.c_str(), nullptr);
        };
        for (const auto& p : e.properties) {
          const double n = p.list ? number(true) : 1.0;
          if (n < 0 || n > 1e6)
            throw LoadError(path, "PLY line " + std::to_string(line) + ": list length " +
                                      std::to_string(n) + " out of range");
          for (int k = 0; k < static_cast<int>(n); ++k) number(p.value_integer);
        }
        std::string extra;
        if (values >> extra)
          throw LoadError(path, "PLY line " + std::to_string(line) + ": more values than " +
                                    "element '" + e.name + "' has properties ('" + extra + "')");
      }
    }
    return;
  }
  // Binary: walk the values; every list's length comes from the body.
  const bool big_endian = format == "binary_big_endian";
  for (const auto& e : elements) {
    for (uint64_t i = 0; i < e.count; ++i) {
      for (const auto& p : e.properties) {
        uint64_t n = 1;
        if (p.list) {
          if (pos + p.count_size > text.size()) {
            throw LoadError(path, "PLY body ends inside instance " + std::to_string(i) +
                                      " of element '" + e.name + "'");
          }
          unsigned char bytes[4] = {0, 0, 0, 0};
          std::memcpy(bytes, text.data() + pos, p.count_size);
          uint32_t raw = 0;
          for (int b = 0; b < p.count_size; ++b)
            raw |= uint32_t{bytes[big_endian ? p.count_size - 1 - b : b]} << (8 * b);
          const bool negative = p.count_signed && (raw >> (8 * p.count_size - 1)) & 1u;
          if (negative) throw LoadError(path, "PLY element '" + e.name + "' has a negative list");
          n = raw;
          pos += p.count_size;
        }
        if (pos + n * p.value_size > text.size()) {
          throw LoadError(path, "PLY body ends inside instance " + std::to_string(i) +
                                    " of element '" + e.name + "' (of " + std::to_string(e.count) +
                                    ")");
        }
        pos += n * p.value_size;
      }
      if (pos > text.size()) throw LoadError(path, "PLY body ends inside element '" + e.name + "'");
    }
  }
}

// Debian's assimp 5.2 loops forever on a PLY cut off inside its header, exhausts memory on a
// COLLADA list with a non-numeric entry and leaks on a malformed ASCII STL. Checked here first,
// so such files raise LoadError.
void CheckStructure(const std::string& path) {
  const std::string ext = Lowercase(std::filesystem::path(path).extension().string());
  if (ext != ".ply" && ext != ".dae" && ext != ".stl") return;
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (ext == ".stl") {
    // assimp's test: binary when the size is 84 bytes plus 50 per facet of the count at byte 80,
    // else ASCII when "solid" comes first (after spaces and tabs).
    if (text.size() >= 84) {
      uint32_t facets = 0;
      std::memcpy(&facets, text.data() + 80, sizeof(facets));
      if (84 + 50 * static_cast<uint64_t>(facets) == text.size()) return;
    }
    const size_t first = text.find_first_not_of(" \t");
    if (first != std::string::npos && text.compare(first, 5, "solid") == 0)
      CheckAsciiStl(path, text);
    return;
  }
  if (ext == ".ply") {
    CheckPly(path, text);
    return;
  }
  // COLLADA number lists: <p>, <v>, <vcount>, <h>, <int_array>, <float_array>. (A plain scan:
  // std::regex recurses per character and overflows the stack on large arrays.) An array must
  // say how many values it holds and hold that many, and an accessor must stay inside its array:
  // assimp dereferences a null pointer on an array without a count (SIGSEGV, found by the mesh
  // fuzz target) and reads past an array that is shorter than its count or its accessors.
  static const std::vector<std::string> kLists = {"p", "v",         "vcount",
                                                  "h", "int_array", "float_array"};
  const auto line_of = [&](size_t at) {
    return std::to_string(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n') + 1);
  };
  std::map<std::string, uint64_t> array_counts;  // by id
  struct Accessor {
    std::string source;
    uint64_t count, stride, offset;
    size_t at;
  };
  std::vector<Accessor> accessors;
  for (size_t open = text.find('<'); open != std::string::npos; open = text.find('<', open + 1)) {
    const size_t name_end = text.find_first_of(" \t\r\n/>", open + 1);
    if (name_end == std::string::npos) break;
    const std::string tag = text.substr(open + 1, name_end - open - 1);
    const bool array = tag == "float_array" || tag == "int_array";
    if (tag != "accessor" && std::find(kLists.begin(), kLists.end(), tag) == kLists.end()) continue;
    const size_t body = text.find('>', name_end);
    if (body == std::string::npos) throw LoadError(path, "COLLADA <" + tag + "> is not closed");
    const std::string start_tag = text.substr(open, body - open);
    // A whole number attribute of the start tag (`fallback` when absent and allowed).
    const auto number = [&](const std::string& name, std::optional<uint64_t> fallback) {
      const auto value = XmlAttribute(start_tag, name);
      if (!value && fallback) return *fallback;
      if (!value || value->empty() || value->size() > 12 ||
          value->find_first_not_of("0123456789") != std::string::npos) {
        throw LoadError(path, "COLLADA <" + tag + "> (line " + line_of(open) + ") needs a " + name +
                                  " that is a whole number" +
                                  (value ? ", not '" + *value + "'" : ""));
      }
      return static_cast<uint64_t>(std::stoull(*value));
    };
    if (tag == "accessor") {
      const auto source = XmlAttribute(start_tag, "source");
      accessors.push_back({source ? *source : "", number("count", std::nullopt),
                           number("stride", 1), number("offset", 0), open});
      continue;
    }
    const bool empty = text[body - 1] == '/';
    const size_t close = empty ? body : text.find('<', body + 1);
    if (close == std::string::npos) throw LoadError(path, "COLLADA <" + tag + "> is not closed");
    const bool floats = tag == "float_array";
    const size_t bad =
        text.find_first_not_of(floats ? "0123456789+-.eE \t\r\n" : "0123456789- \t\r\n", body + 1);
    if (!empty && bad < close) {
      throw LoadError(path, "COLLADA <" + tag + "> list holds a non-numeric character '" +
                                text.substr(bad, 1) + "' (line " + line_of(bad) + ")");
    }
    if (array) {
      uint64_t values = 0;
      std::istringstream list(empty ? std::string() : text.substr(body + 1, close - body - 1));
      for (std::string value; list >> value;) ++values;
      const uint64_t count = number("count", std::nullopt);
      if (count != values) {
        throw LoadError(path, "COLLADA <" + tag + "> (line " + line_of(open) + ") says count " +
                                  std::to_string(count) + " but holds " + std::to_string(values) +
                                  " values");
      }
      if (const auto id = XmlAttribute(start_tag, "id")) array_counts[*id] = count;
    }
    open = close;
  }
  for (const auto& a : accessors) {
    const auto array = array_counts.find(a.source.substr(a.source.rfind('#', 0) == 0));
    if (array == array_counts.end()) continue;  // another kind of array: assimp checks it
    if (a.offset + a.count * a.stride > array->second) {
      throw LoadError(path, "COLLADA <accessor> (line " + line_of(a.at) + ") reads " +
                                std::to_string(a.count) + " elements of stride " +
                                std::to_string(a.stride) + " from '" + array->first +
                                "', which holds " + std::to_string(array->second) + " values");
    }
  }
}

Eigen::Matrix4d ToEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d out;
  out << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return out;
}

std::string PartName(const aiScene& scene, const aiNode& node, unsigned mesh_index) {
  const aiMesh& mesh = *scene.mMeshes[mesh_index];
  std::string name = node.mName.length > 0 ? node.mName.C_Str() : "";
  if (name.empty() || &node == scene.mRootNode) {
    name = mesh.mName.length > 0 ? mesh.mName.C_Str() : "mesh" + std::to_string(mesh_index);
  }
  return name;
}

void AddNode(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent_transform,
             TriangleMesh& out) {
  const Eigen::Matrix4d transform = parent_transform * ToEigen(node.mTransformation);
  const Eigen::Matrix3d linear = transform.topLeftCorner<3, 3>();
  const bool mirrored = linear.determinant() < 0.0;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[i]];
    if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const int part = out.AddPart(PartName(scene, node, node.mMeshes[i]));
    const int offset = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      out.vertices.push_back((transform * Eigen::Vector4d(p.x, p.y, p.z, 1.0)).head<3>());
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left over from triangulation
      Eigen::Vector3i tri(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
      if (mirrored) std::swap(tri[1], tri[2]);
      out.triangles.push_back(tri.array() + offset);
      out.triangle_parts.push_back(part);
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    AddNode(scene, *node.mChildren[c], transform, out);
  }
}

}  // namespace

TriangleMesh LoadMesh(const std::string& path) {
  CheckReadableFile(path);
  CheckStructure(path);

  Assimp::Importer importer;
  // Keep the file's axes: ROS models are authored z-up and must not be turned to y-up.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (scene == nullptr) {
    throw LoadError(path, std::string("not a readable mesh: ") + importer.GetErrorString());
  }
  if (scene->mRootNode == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    throw LoadError(path, "mesh file is incomplete");
  }
  // Debian's assimp is built with assertions on, and its triangulation aborts the process on a
  // mesh whose primitive-type flags disagree with its faces (a truncated PLY makes one). Set the
  // flags from the faces themselves before triangulating.
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    aiMesh& mesh = *scene->mMeshes[m];
    unsigned types = 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const unsigned n = mesh.mFaces[f].mNumIndices;
      if (n == 0)
        throw LoadError(path, "mesh " + std::to_string(m) + " has a face with no vertices");
      types |= n == 1   ? aiPrimitiveType_POINT
               : n == 2 ? aiPrimitiveType_LINE
               : n == 3 ? aiPrimitiveType_TRIANGLE
                        : aiPrimitiveType_POLYGON;
    }
    mesh.mPrimitiveTypes = types;
  }
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (scene == nullptr) {
    throw LoadError(path, std::string("cannot triangulate: ") + importer.GetErrorString());
  }

  TriangleMesh mesh;
  AddNode(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), mesh);
  if (mesh.triangles.empty()) throw LoadError(path, "contains no triangles");
  try {
    mesh.Validate();
  } catch (const std::invalid_argument& e) {
    throw LoadError(path, e.what());
  }
  return mesh;
}

void WriteObj(const std::string& path, const TriangleMesh& mesh, const std::string& comment) {
  mesh.Validate();
  std::ofstream out(path);
  if (!out) throw LoadError(path, "cannot be written");
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  for (const auto& name : mesh.part_names) {
    if (name.empty() || name.find_first_of("\r\n") != std::string::npos) {
      throw LoadError(path, "part name '" + name + "' cannot be written as an OBJ object name");
    }
  }
  out << std::fixed << std::setprecision(6);
  for (const auto& v : mesh.vertices) out << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << "\n";
  // Faces grouped by part, parts in their order, so each part is one OBJ object.
  for (size_t p = 0; p < mesh.part_names.size(); ++p) {
    out << "o " << mesh.part_names[p] << "\n";
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.triangle_parts[t] != static_cast<int>(p)) continue;
      const auto& f = mesh.triangles[t];
      out << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << "\n";
    }
  }
  if (!out) throw LoadError(path, "write failed");
}

}  // namespace aar_geometry
