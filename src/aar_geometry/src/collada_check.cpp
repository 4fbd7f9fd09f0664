#include "mesh_check.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "aar_geometry/load_error.h"

namespace aar_geometry {
namespace {

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

// The line (from 1) that byte `at` of `text` is on, as text.
std::string LineOf(const std::string& text, size_t at) {
  return std::to_string(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n') + 1);
}

// The start tag of a COLLADA element that the check reads.
struct ColladaTag {
  const std::string& path;
  const std::string& text;  // the whole file
  std::string name;
  size_t open = 0;  // its '<'
  size_t body = 0;  // its '>'
  std::string start_tag;

  // A whole number attribute (`fallback` when absent and allowed).
  uint64_t WholeNumber(const std::string& attribute, std::optional<uint64_t> fallback) const {
    const auto value = XmlAttribute(start_tag, attribute);
    if (!value && fallback) return *fallback;
    if (!value || value->empty() || value->size() > 12 ||
        value->find_first_not_of("0123456789") != std::string::npos) {
      throw LoadError(path, "COLLADA <" + name + "> (line " + LineOf(text, open) + ") needs a " +
                                attribute + " that is a whole number" +
                                (value ? ", not '" + *value + "'" : ""));
    }
    return static_cast<uint64_t>(std::stoull(*value));
  }
};

struct ColladaAccessor {
  std::string source;
  uint64_t count, stride, offset;
  size_t at;
};

ColladaAccessor ReadColladaAccessor(const ColladaTag& tag) {
  const auto source = XmlAttribute(tag.start_tag, "source");
  return {source ? *source : "", tag.WholeNumber("count", std::nullopt),
          tag.WholeNumber("stride", 1), tag.WholeNumber("offset", 0), tag.open};
}

// A number list: numeric characters only; an array (<int_array>, <float_array>) holds as many
// values as its count says, which is recorded in `array_counts` by its id. Returns where the
// list ends.
size_t CheckColladaList(const ColladaTag& tag, std::map<std::string, uint64_t>& array_counts) {
  const std::string& text = tag.text;
  const bool empty = text[tag.body - 1] == '/';
  const size_t close = empty ? tag.body : text.find('<', tag.body + 1);
  if (close == std::string::npos)
    throw LoadError(tag.path, "COLLADA <" + tag.name + "> is not closed");
  const bool floats = tag.name == "float_array";
  const size_t bad = text.find_first_not_of(
      floats ? "0123456789+-.eE \t\r\n" : "0123456789- \t\r\n", tag.body + 1);
  if (!empty && bad < close) {
    throw LoadError(tag.path, "COLLADA <" + tag.name + "> list holds a non-numeric character '" +
                                  text.substr(bad, 1) + "' (line " + LineOf(text, bad) + ")");
  }
  if (tag.name != "float_array" && tag.name != "int_array") return close;
  uint64_t values = 0;
  std::istringstream list(empty ? std::string() : text.substr(tag.body + 1, close - tag.body - 1));
  for (std::string value; list >> value;) ++values;
  const uint64_t count = tag.WholeNumber("count", std::nullopt);
  if (count != values) {
    throw LoadError(tag.path, "COLLADA <" + tag.name + "> (line " + LineOf(text, tag.open) +
                                  ") says count " + std::to_string(count) + " but holds " +
                                  std::to_string(values) + " values");
  }
  if (const auto id = XmlAttribute(tag.start_tag, "id")) array_counts[*id] = count;
  return close;
}

// Each accessor of an array checked here stays inside it.
void CheckColladaAccessors(const std::string& path, const std::string& text,
                           const std::vector<ColladaAccessor>& accessors,
                           const std::map<std::string, uint64_t>& array_counts) {
  for (const auto& a : accessors) {
    const auto array = array_counts.find(a.source.substr(a.source.rfind('#', 0) == 0));
    if (array == array_counts.end()) continue;  // another kind of array: assimp checks it
    if (a.offset + a.count * a.stride > array->second) {
      throw LoadError(path, "COLLADA <accessor> (line " + LineOf(text, a.at) + ") reads " +
                                std::to_string(a.count) + " elements of stride " +
                                std::to_string(a.stride) + " from '" + array->first +
                                "', which holds " + std::to_string(array->second) + " values");
    }
  }
}

}  // namespace

// COLLADA number lists: <p>, <v>, <vcount>, <h>, <int_array>, <float_array>. (A plain scan:
// std::regex recurses per character and overflows the stack on large arrays.) An array must
// say how many values it holds and hold that many, and an accessor must stay inside its array:
// assimp dereferences a null pointer on an array without a count (SIGSEGV, found by the mesh
// fuzz target) and reads past an array that is shorter than its count or its accessors.
void CheckCollada(const std::string& path, const std::string& text) {
  static const std::vector<std::string> kLists = {"p", "v",         "vcount",
                                                  "h", "int_array", "float_array"};
  std::map<std::string, uint64_t> array_counts;  // by id
  std::vector<ColladaAccessor> accessors;
  for (size_t open = text.find('<'); open != std::string::npos; open = text.find('<', open + 1)) {
    const size_t name_end = text.find_first_of(" \t\r\n/>", open + 1);
    if (name_end == std::string::npos) break;
    const std::string name = text.substr(open + 1, name_end - open - 1);
    if (name != "accessor" && std::find(kLists.begin(), kLists.end(), name) == kLists.end())
      continue;
    const size_t body = text.find('>', name_end);
    if (body == std::string::npos) throw LoadError(path, "COLLADA <" + name + "> is not closed");
    const ColladaTag tag{path, text, name, open, body, text.substr(open, body - open)};
    if (name == "accessor")
      accessors.push_back(ReadColladaAccessor(tag));
    else
      open = CheckColladaList(tag, array_counts);
  }
  CheckColladaAccessors(path, text, accessors, array_counts);
}

}  // namespace aar_geometry
