#include "scene_graph_tracker/geometry/mesh_header.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "scene_graph_tracker/geometry/mesh_io.hpp"

namespace fs = std::filesystem;

namespace sgt {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw MeshError("mesh '" + path + "': " + problem);
}

// The vertex and face counts an OFF header declares, summed: the first two numbers after the
// keyword, which may be glued to the first ("OFF3"; '#' starts a comment).
double offDeclared(const std::string& glued, std::istringstream& text) {
  double declared = 0.0;
  int counts = 0;
  if (!glued.empty()) declared += std::fabs(std::strtod(glued.c_str(), nullptr)), ++counts;
  for (std::string token; counts < 2 && text >> token;) {
    if (token[0] == '#') {
      std::getline(text, token);
      continue;
    }
    declared += std::fabs(std::strtod(token.c_str(), nullptr)), ++counts;
  }
  return declared;
}

bool plyScalarType(const std::string& t) {
  static const char* const kTypes[] = {"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                       "float", "double", "int8",    "uint8",  "int16", "uint16",
                                       "int32", "uint32", "float32", "float64"};
  return std::find(std::begin(kTypes), std::end(kTypes), t) != std::end(kTypes);
}

// Whether one line of a PLY header after "format" is well formed ("comment", "obj_info",
// "element NAME COUNT", "property TYPE NAME", "property list TYPE TYPE NAME"); adds an element's
// count to `declared`.
bool plyHeaderLine(const std::string& line, bool& in_element, double& declared) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string t; in >> t;) w.push_back(t);
  if (w.empty()) return false;
  if (w[0] == "comment" || w[0] == "obj_info") return true;
  if (w[0] == "element") {
    if (w.size() != 3 || w[2].find_first_not_of("0123456789") != std::string::npos) return false;
    declared += std::strtod(w[2].c_str(), nullptr);
    return in_element = true;
  }
  if (w[0] != "property" || !in_element) return false;
  if (w.size() == 3) return plyScalarType(w[1]);
  return w.size() == 5 && w[1] == "list" && plyScalarType(w[2]) && plyScalarType(w[3]);
}

// A PLY header checked against the format's grammar (assimp's parser reads past its buffer on some
// broken ones); returns the element counts it declares, summed.
double plyDeclared(std::istringstream& text, const std::string& path) {
  std::string line;
  std::getline(text, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "ply") fail(path, "PLY header: the first line is not 'ply'");
  std::getline(text, line);
  std::istringstream format(line);
  std::string keyword, kind, version, extra;
  format >> keyword >> kind >> version;
  if (keyword != "format" || version != "1.0" || format >> extra ||
      (kind != "ascii" && kind != "binary_little_endian" && kind != "binary_big_endian"))
    fail(path, "PLY header: '" + line + "' is not a format line");
  bool in_element = false;
  double declared = 0.0;
  while (std::getline(text, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line == "end_header") return declared;
    if (!plyHeaderLine(line, in_element, declared))
      fail(path, "PLY header: '" + line.substr(0, 80) + "' is not a header line");
  }
  fail(path, "PLY header: no end_header in the first 64 kB");
}

}  // namespace

void checkMeshHeader(const std::string& path, std::uintmax_t bytes) {
  std::ifstream in(path, std::ios::binary);
  std::string head(static_cast<std::size_t>(std::min<std::uintmax_t>(bytes, 1 << 16)), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::istringstream text(head);
  double declared = 0.0;
  // assimp picks the reader by the extension first, by the content otherwise.
  if (ext == ".ply" || head.rfind("ply", 0) == 0) {
    declared = plyDeclared(text, path);
  } else {
    std::string first;
    text >> first;
    const std::size_t off = first.find("OFF");  // OFF, COFF, NOFF, STOFF, 4OFF, ...
    if (ext == ".off" || (off != std::string::npos && off <= 4))
      declared = offDeclared(off == std::string::npos ? first : first.substr(off + 3), text);
  }
  if (!(declared <= static_cast<double>(bytes))) {
    std::ostringstream msg;
    msg << "its header declares " << declared << " vertices and faces, more than a file of "
        << bytes << " bytes can hold";
    fail(path, msg.str());
  }
}

}  // namespace sgt
