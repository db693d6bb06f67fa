#include "core/memory_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "core/safe_io.h"

namespace hw {

Result<std::uint64_t> parseMemorySize(const std::string& text) {
  const std::string expected = "expected a size with a unit, e.g. 4G, 512M or 1.5GiB";
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || !std::isfinite(v) || v <= 0 ||
      !std::isdigit(static_cast<unsigned char>(text[0])))
    return makeError("memory size: " + expected + ", got '" + text + "'");
  std::string unit(end);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() >= 2 && unit.substr(unit.size() - 2) == "IB") unit.resize(unit.size() - 2);
  else if (unit.size() >= 2 && unit.back() == 'B') unit.pop_back();
  double scale = 0;
  if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024;
  else if (unit == "G") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
  else return makeError("memory size: " + expected + ", got '" + text + "'");
  const double bytes = v * scale;
  if (bytes < 1024.0 * 1024 || bytes > 1e18)
    return makeError("memory size: expected 1M to 1000000T, got '" + text + "'");
  return static_cast<std::uint64_t>(bytes);
}

MemoryLimits probeMemoryLimits() {
  MemoryLimits m;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0) m.physicalBytes = static_cast<std::uint64_t>(pages) * page;
  std::ifstream cg("/sys/fs/cgroup/memory.max");
  unsigned long long c = 0;
  if (cg >> c) m.cgroupBytes = c;  // "max" fails the read: no limit
  struct rlimit r {};
  if (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    m.addressSpaceBytes = static_cast<std::uint64_t>(r.rlim_cur);
  return m;
}

std::uint64_t defaultMemoryBudget(const MemoryLimits& limits) {
  std::uint64_t least = 0;
  for (std::uint64_t b : {limits.physicalBytes, limits.cgroupBytes, limits.addressSpaceBytes})
    if (b > 0 && (least == 0 || b < least)) least = b;
  if (least == 0) least = 8ull << 30;
  return std::max<std::uint64_t>(least / 10 * 4, 256ull << 20);
}

Status checkMemoryCharge(std::uint64_t charged, std::uint64_t bytes, std::uint64_t budget,
                         const std::string& what, const std::string& hint) {
  if (bytes <= budget && charged <= budget - bytes) return {};
  std::string msg = what + " (" + formatBytes(bytes);
  if (charged > 0) msg += "; " + formatBytes(charged + bytes) + " with what the run holds already";
  msg += "), over the " + formatBytes(budget) + " memory budget";
  if (!hint.empty()) msg += "; " + hint;
  return makeError(msg);
}

namespace {
std::atomic<std::uint64_t> gBudget{0};
std::atomic<std::uint64_t> gCharged{0};
thread_local MemoryScope* tScope = nullptr;
}  // namespace

void setMemoryBudget(std::uint64_t bytes) { gBudget = bytes; }

std::uint64_t memoryBudget() {
  std::uint64_t b = gBudget.load();
  if (b == 0) {
    b = defaultMemoryBudget(probeMemoryLimits());
    std::uint64_t zero = 0;
    gBudget.compare_exchange_strong(zero, b);
    b = gBudget.load();
  }
  return b;
}

std::uint64_t memoryCharged() { return gCharged.load(); }

Status chargeMemory(std::uint64_t bytes, const std::string& what, const std::string& hint) {
  const std::uint64_t budget = memoryBudget();
  std::uint64_t cur = gCharged.load();
  do {
    Status ok = checkMemoryCharge(cur, bytes, budget, what, hint);
    if (!ok) {
      if (tScope && tScope->refused_.empty()) tScope->refused_ = ok.error().message;
      return ok;
    }
  } while (!gCharged.compare_exchange_weak(cur, cur + bytes));
  if (tScope) tScope->charged_ += bytes;
  return {};
}

void releaseCharged(std::uint64_t bytes) {
  std::uint64_t cur = gCharged.load();
  while (!gCharged.compare_exchange_weak(cur, cur >= bytes ? cur - bytes : 0)) {
  }
}

void releaseMemory(std::uint64_t bytes) {
  releaseCharged(bytes);
  if (tScope) tScope->charged_ -= std::min(tScope->charged_, bytes);
}

MemoryScope::MemoryScope() : outer_(tScope) { tScope = this; }

MemoryScope::~MemoryScope() {
  tScope = outer_;
  releaseCharged(charged_);
}

std::shared_ptr<MemoryReservation> MemoryScope::keep() {
  auto r = std::make_shared<MemoryReservation>(charged_);
  charged_ = 0;
  return r;
}

}  // namespace hw
