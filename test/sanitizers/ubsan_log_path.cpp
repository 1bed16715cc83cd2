// make test-asan: linked into every executable and library of the ASan + UBSan build (Makefile,
// SAN_LINK_FLAGS_asan). gcc's UBSan runtime (libubsan) sits beside ASan's (libasan), and its own
// call of __sanitizer_set_report_path(log_path) binds to libasan's copy: UBSan reports would go to
// stderr, not to UBSAN_OPTIONS' log_path where the test run looks for reports. This sets libubsan's
// own report path from UBSAN_OPTIONS' log_path (sanitizer flags are separated by ':').
#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace {

__attribute__((constructor)) void sgtUbsanLogPath() {
  void* ubsan = dlopen("libubsan.so.1", RTLD_NOW | RTLD_NOLOAD);
  if (ubsan == nullptr) return;
  using SetReportPath = void (*)(const char*);
  const auto set = reinterpret_cast<SetReportPath>(dlsym(ubsan, "__sanitizer_set_report_path"));
  const char* options = std::getenv("UBSAN_OPTIONS");
  if (set != nullptr && options != nullptr) {
    const std::string all = std::string(":") + options;
    const std::size_t at = all.rfind(":log_path=");
    if (at != std::string::npos) {
      const std::size_t begin = at + std::strlen(":log_path=");
      static const std::string path = all.substr(begin, all.find(':', begin) - begin);
      set(path.c_str());
    }
  }
  dlclose(ubsan);
}

}  // namespace
