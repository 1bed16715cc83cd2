// The files generated from the parameter schema: config/tracker.yaml, config/detector.yaml,
// cfg/Tracker.cfg and the README's parameter tables (tools/print_parameters.cpp writes them,
// test_parameter_schema compares them with the committed copies).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "scene_graph_tracker/pipeline/parameter_schema.hpp"

namespace sgt::params {
namespace {

bool isNumber(const std::string& s) {
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size();
}

// A string as a YAML scalar: plain when YAML 1.1 reads it back as that string, else quoted.
std::string yamlString(const std::string& s) {
  static const char* const kWords[] = {"y",     "n",  "yes", "no",   "true",
                                       "false", "on", "off", "null", "~"};
  std::string lower = s;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  bool plain = !s.empty() && !isNumber(s) && std::all_of(s.begin(), s.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '.' || c == '/' || c == '-';
  });
  for (const char* w : kWords) plain = plain && lower != w;
  if (plain) return s;
  std::string q = "\"";
  for (char c : s) q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return q + "\"";
}

// A default as the README shows it.
std::string shownString(const std::string& s) {
  if (s.empty()) return "`\"\"`";
  return "`" + s + "`";
}

template <class O>
std::string comment(const Param<O>& p) {
  return "# " + (p.unit.empty() ? "" : p.unit + ": ") + p.doc;
}

// One YAML file: the parameters that belong in a file, group by group, nested by their '/'.
template <class O>
std::string yaml(const Schema<O>& schema, const std::string& header) {
  const O defaults{};
  std::vector<std::pair<std::string, std::string>> lines;  // text, comment
  std::vector<std::string> closed;  // nested blocks already written: they must not open again
  for (const Group& g : groups()) {
    bool any = false;
    std::string block;
    for (const Param<O>& p : schema) {
      if (p.group != g.name || !p.in_file) continue;
      if (!any)
        lines.push_back({"", ""}), lines.push_back({std::string("# ") + g.name + ": " + g.doc, ""}),
            any = true;
      if (std::count(p.name.begin(), p.name.end(), '/') > 1)
        throw std::logic_error(p.name + ": one level of nesting at most");
      const std::size_t slash = p.name.find('/');
      const std::string prefix = slash == std::string::npos ? "" : p.name.substr(0, slash);
      if (prefix != block) {
        if (!block.empty()) closed.push_back(block);
        if (std::find(closed.begin(), closed.end(), prefix) != closed.end())
          throw std::logic_error(p.name + ": the parameters under " + prefix +
                                 "/ must follow each other");
        if (!prefix.empty()) lines.push_back({prefix + ":", ""});
        block = prefix;
      }
      const Value v = p.get(defaults);
      const std::string value =
          p.type == Type::kString ? yamlString(std::get<std::string>(v)) : format(p, v);
      lines.push_back({(prefix.empty() ? "" : "  ") +
                           p.name.substr(prefix.empty() ? 0 : slash + 1) + ": " + value,
                       comment(p)});
    }
    if (!block.empty()) closed.push_back(block);
  }
  std::size_t width = 0;
  for (const auto& [text, note] : lines)
    if (!note.empty()) width = std::max(width, text.size());
  std::string out = header;
  for (const auto& [text, note] : lines) {
    std::string line = text;
    if (!note.empty()) line += std::string(width + 1 - text.size(), ' ') + note;
    out += line + "\n";
  }
  return out;
}

std::string cell(std::string s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

// The README tables: one per group.
template <class O>
std::string tables(const Schema<O>& schema) {
  const O defaults{};
  std::ostringstream out;
  bool first = true;
  for (const Group& g : groups()) {
    bool any = false;
    for (const Param<O>& p : schema) {
      if (p.group != g.name) continue;
      if (!any) {
        out << (first ? "" : "\n") << "**" << g.name << "**: " << g.doc << "\n\n"
            << "| name | type | default | range | unit | runtime | description |\n"
            << "|---|---|---|---|---|---|---|\n";
        any = true, first = false;
      }
      const Value v = p.get(defaults);
      const std::string shown =
          p.type == Type::kString ? shownString(std::get<std::string>(v)) : format(p, v);
      out << "| `" << p.name << "` | " << toString(p.type) << " | " << cell(shown) << " | "
          << range(p) << " | " << cell(p.unit) << " | " << (p.runtime ? "yes" : "no") << " | "
          << cell(p.doc) << " |\n";
    }
  }
  return out.str();
}

// The README's index: per group, the names of its parameters (the tables are in doc/parameters.md).
template <class O>
std::string index(const Schema<O>& schema) {
  std::ostringstream out;
  out << "| group | parameters |\n|---|---|\n";
  for (const Group& g : groups()) {
    std::string names;
    for (const Param<O>& p : schema)
      if (p.group == g.name) names += (names.empty() ? "`" : ", `") + p.name + "`";
    if (!names.empty()) out << "| " << g.name << " | " << names << " |\n";
  }
  return out.str();
}

std::string python(const Param<TrackerParameters>& p, const Value& v) {
  if (p.type == Type::kBool) return std::get<bool>(v) ? "True" : "False";
  return format(p, v);
}

std::string markerLine(const std::string& which, const std::string& what) {
  return "<!-- " + which + " GENERATED: " + what + " -->\n";
}

// Where the text between the marker lines starts and ends.
std::pair<std::size_t, std::size_t> section(const std::string& text, const std::string& what) {
  const std::string begin = markerLine("BEGIN", what), end = markerLine("END", what);
  const std::size_t b = text.find(begin);
  const std::size_t e = b == std::string::npos ? b : text.find(end, b + begin.size());
  if (b == std::string::npos || e == std::string::npos || (b > 0 && text[b - 1] != '\n') ||
      text[e - 1] != '\n')
    throw std::runtime_error("no lines '" + begin.substr(0, begin.size() - 1) + "' ... '" +
                             end.substr(0, end.size() - 1) + "'");
  return {b + begin.size(), e};
}

}  // namespace

std::string formatNumber(double v, bool single) {
  char buf[64];
  const auto r = single ? std::to_chars(buf, buf + sizeof buf, static_cast<float>(v))
                        : std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".na") != std::string::npos) return s;  // has a point, or nan / inf
  const std::size_t e = s.find('e');
  return e == std::string::npos ? s + ".0" : s.insert(e, ".0");
}

std::string trackerYaml() {
  return yaml(
      trackerSchema(),
      R"(# Parameters of the tracker nodelet (private namespace, e.g. /tracker/...) and of `evaluate`
# (--params: this file by default). The values are the defaults of the option structs.
# Generated from the parameter schema (src/core/pipeline/parameter_schema.cpp) by `make params`:
# change defaults there. A robot with other values keeps its own copy (tracker.launch params:=FILE).
# Types, ranges and run-time changes: doc/parameters.md.
)");
}

std::string detectorYaml() {
  return yaml(
      detectorSchema(),
      R"(# Parameters of the detector nodelet (private namespace, e.g. /detector/...) and of `evaluate
# --detector` (--detector-params: this file by default). The values are the defaults of the option
# structs. Generated from the parameter schema (src/core/pipeline/parameter_schema.cpp) by `make
# params`: change defaults there. A robot with other values keeps its own copy (tracker.launch
# detector_params:=FILE). Types and ranges: doc/parameters.md.
)");
}

std::string trackerReconfigure() {
  const TrackerParameters defaults{};
  std::string out = R"(#!/usr/bin/env python3
# Run-time parameters of the tracker nodelet (dynamic_reconfigure): those of the parameter schema
# (src/core/pipeline/parameter_schema.cpp) that can change at run time, named as in
# config/tracker.yaml with '_' for '/' (refine/rounds is refine_rounds). Generated from the schema
# by `make params`: do not edit.
from dynamic_reconfigure.parameter_generator_catkin import ParameterGenerator, bool_t, double_t, int_t

gen = ParameterGenerator()
)";
  for (const Group& g : groups()) {
    bool any = false;
    for (const Param<TrackerParameters>& p : trackerSchema()) {
      if (p.group != g.name || !p.runtime) continue;
      if (p.type == Type::kString) throw std::logic_error(p.name + ": no run-time strings");
      if (!any) out += std::string("# ") + g.name + "\n", any = true;
      const char* type = p.type == Type::kBool  ? "bool_t"
                         : p.type == Type::kInt ? "int_t"
                                                : "double_t";
      out += "gen.add(\"" + reconfigureName(p.name) + "\", " + type + ", 0, \"" + p.doc +
             (p.unit.empty() ? "" : " (" + p.unit + ")") + "\", " + python(p, p.get(defaults));
      if (p.type == Type::kInt)
        out += ", " + std::to_string(int(p.min)) + ", " + std::to_string(int(p.max));
      if (p.type == Type::kDouble)
        out += ", " + formatNumber(p.min, false) + ", " + formatNumber(p.max, false);
      out += ")\n";
    }
  }
  return out + "exit(gen.generate(\"scene_graph_tracker\", \"tracker\", \"Tracker\"))\n";
}

std::string trackerTables() { return tables(trackerSchema()); }
std::string detectorTables() { return tables(detectorSchema()); }
std::string trackerIndex() { return index(trackerSchema()); }
std::string detectorIndex() { return index(detectorSchema()); }

std::string parameterReference() {
  return "# Parameters\n\n"
         "Every parameter of the tracker and detector nodelets, from the parameter schema\n"
         "(`src/core/pipeline/parameter_schema.cpp`; `make params` writes this file, "
         "`config/*.yaml`,\n"
         "`cfg/Tracker.cfg` and the README's index; `test_parameter_schema` checks them). Names "
         "are the\n"
         "YAML keys in the node's private namespace (`/` nests); dynamic_reconfigure has every "
         "run-time\n"
         "one under the same name with `_` for `/`. The defaults are the option structs'.\n\n"
         "## Tracker (`config/tracker.yaml`, `evaluate --params`)\n\n" +
         trackerTables() +
         "\n## Detector (`config/detector.yaml`, `evaluate --detector-params`)\n\n" +
         detectorTables();
}

std::string generatedSection(const std::string& text, const std::string& what) {
  const auto [b, e] = section(text, what);
  return text.substr(b, e - b);
}

std::string replaceGeneratedSection(const std::string& text, const std::string& what,
                                    const std::string& body) {
  const auto [b, e] = section(text, what);
  return text.substr(0, b) + body + text.substr(e);
}

}  // namespace sgt::params
