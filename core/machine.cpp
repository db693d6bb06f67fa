#include "core/machine.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <thread>

#include "core/gl/context.h"

#ifndef HW_GIT_COMMIT
#define HW_GIT_COMMIT "unknown"
#endif
#ifndef HW_BUILD_TYPE
#define HW_BUILD_TYPE "unknown"
#endif

namespace hw {

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto p = line.find(':');
      if (p != std::string::npos) return line.substr(line.find_first_not_of(' ', p + 1));
    }
  }
  return "unknown";
}

nlohmann::json machineInfo(const std::string& glRenderer, const std::string& glVersion) {
  char host[256] = {0};
  ::gethostname(host, sizeof host - 1);
  const char* lp = std::getenv("LP_NUM_THREADS");
  // Backend and vendor of the headless context these strings came from.
  const gl::ContextStrings last = gl::lastHeadlessContextStrings();
  const bool fromLast = !last.backend.empty() && last.renderer == glRenderer;
  return {{"cpu", cpuModel()},
          {"cores", std::thread::hardware_concurrency()},
          {"host", host},
          {"gl_backend", fromLast ? last.backend : "unknown"},
          {"gl_vendor", fromLast ? last.vendor : "unknown"},
          {"gl_renderer", glRenderer},
          {"gl_version", glVersion},
          {"lp_num_threads", lp ? lp : "unset"},
          {"build_type", HW_BUILD_TYPE},
          {"git_commit", HW_GIT_COMMIT}};
}

}  // namespace hw
