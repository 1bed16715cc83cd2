// Helpers of the fuzz targets (test/fuzz/fuzz_targets.hpp): numbers that reach both the usual
// and the edge cases, and temporary files for the loaders that take a path.
#pragma once

#include <fuzzer/FuzzedDataProvider.h>
#include <stdlib.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace sgt::fuzz {

// An invariant of the result: a violation is a finding (abort), not an error to catch.
inline void expect(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz target: expected %s\n", what);
  std::abort();
}

// SGT_FUZZ_VERBOSE set: targets say what an input did (for writing seeds), on stderr.
inline bool verbose() {
  static const bool v = std::getenv("SGT_FUZZ_VERBOSE") != nullptr;
  return v;
}

// A double that is mostly in [-range, range] and sometimes NaN, infinite, huge, tiny or any bit
// pattern at all.
inline double number(FuzzedDataProvider& p, double range = 2.0) {
  using L = std::numeric_limits<double>;
  switch (p.ConsumeIntegralInRange<int>(0, 15)) {
    case 0:
      return L::quiet_NaN();
    case 1:
      return p.ConsumeBool() ? L::infinity() : -L::infinity();
    case 2:
      return p.ConsumeBool() ? 1e300 : -1e300;
    case 3:
      return p.ConsumeBool() ? L::denorm_min() : L::max();
    case 4:
      return 0.0;
    case 5:
      return p.ConsumeFloatingPoint<double>();
    default:
      return p.ConsumeFloatingPointInRange(-range, range);
  }
}

// An unsigned count: mostly in [0, usual], sometimes any value of the type.
template <typename T>
T count(FuzzedDataProvider& p, T usual) {
  return p.ConsumeIntegralInRange<int>(0, 7) == 0 ? p.ConsumeIntegral<T>()
                                                  : p.ConsumeIntegralInRange<T>(0, usual);
}

// One of `names`, or (sometimes) a short arbitrary string.
inline std::string name(FuzzedDataProvider& p, const std::vector<std::string>& names) {
  if (names.empty() || p.ConsumeIntegralInRange<int>(0, 7) == 0)
    return p.ConsumeRandomLengthString(16);
  return names[p.ConsumeIntegralInRange<std::size_t>(0, names.size() - 1)];
}

// A directory of this process under the temporary directory, removed at exit.
inline const std::string& tempDir() {
  struct Dir {
    std::string path;
    Dir() {
      std::string tmpl = (std::filesystem::temp_directory_path() / "sgt_fuzz_XXXXXX").string();
      if (!mkdtemp(tmpl.data())) throw std::runtime_error("cannot create a temporary directory");
      path = tmpl;
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

// Writes `bytes` to tempDir()/name; returns the path.
inline std::string writeTemp(const std::string& name, const std::uint8_t* bytes, std::size_t size) {
  const std::string path = tempDir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes), static_cast<std::streamsize>(size));
  if (!out) throw std::runtime_error("cannot write " + path);
  return path;
}

inline std::string writeTemp(const std::string& name, const std::string& text) {
  return writeTemp(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

}  // namespace sgt::fuzz
