// Command-line flags of the package's tools: `--name VALUE` and `--switch`. A flag without its
// value, an unknown flag or a missing required one prints what is wrong and the synopsis, and
// exits with 2.
#pragma once

#include <cstdlib>
#include <functional>
#include <iostream>
#include <map>
#include <string>

namespace sgt::cli {

class Flags {
 public:
  Flags(std::string tool, std::string synopsis)
      : tool_(std::move(tool)), synopsis_(std::move(synopsis)) {}

  [[noreturn]] void fail(const std::string& error) const {
    std::cerr << tool_ << ": " << error << "\nusage: " << tool_ << " " << synopsis_ << "\n";
    std::exit(2);
  }

  // Calls `on(flag, value)` for each argument; `value()` takes the argument after the flag.
  // `on` returns false for a flag it does not know.
  void parse(int argc, char** argv,
             const std::function<bool(const std::string& flag,
                                      const std::function<std::string()>& value)>& on) const {
    for (int i = 1; i < argc; ++i) {
      const std::string flag = argv[i];
      const std::function<std::string()> value = [&]() -> std::string {
        if (i + 1 >= argc) fail(flag + " needs a value");
        return argv[++i];
      };
      if (!on(flag, value)) fail("unknown argument " + flag);
    }
  }

  // parse() for tools whose flags all take a string: each flag and the string it sets.
  void parse(int argc, char** argv, const std::map<std::string, std::string*>& strings) const {
    parse(argc, argv, [&](const std::string& flag, const std::function<std::string()>& value) {
      const auto it = strings.find(flag);
      if (it == strings.end()) return false;
      *it->second = value();
      return true;
    });
  }

 private:
  std::string tool_, synopsis_;
};

}  // namespace sgt::cli
