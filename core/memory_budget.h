#pragma once
// One memory budget for a whole run: decoded textures and imported meshes
// are charged against it before they are allocated, so an input that would
// exhaust memory is refused with a message naming it (docs/bad-input.md).
//
// The budget is process-wide (set once from --max-memory; the default is a
// fraction of the memory this process may use). Charges are made on the
// loading thread; a MemoryScope collects what one scene load charged so the
// scene can give it back when it is destroyed.
#include <cstdint>
#include <memory>
#include <string>

#include "core/result.h"

namespace hw {

// "4G", "512M", "1.5GiB", "800MB", "65536K", "2T" → bytes. Units are binary
// (K = KiB); "B" and "iB" are optional; a unit is required (a bare number is
// refused, so "4" cannot mean 4 bytes).
Result<std::uint64_t> parseMemorySize(const std::string& text);

// What limits this process: physical memory, the cgroup's memory.max and
// the address-space rlimit (ulimit -v); 0 = no such limit.
struct MemoryLimits {
  std::uint64_t physicalBytes = 0;
  std::uint64_t cgroupBytes = 0;
  std::uint64_t addressSpaceBytes = 0;
};
MemoryLimits probeMemoryLimits();

// 40 % of the smallest limit (at least 256 MiB): the GL driver keeps its
// own copy of textures and meshes (with mipmaps), and the address space also
// holds libraries, thread stacks and malloc arenas.
std::uint64_t defaultMemoryBudget(const MemoryLimits& limits);

// The refusal, or success, of adding `bytes` to `charged` under `budget`.
// `what` names the item ("t.png: texture 16384x16384 decoded"; the size is
// appended in brackets), `hint` what the user can change.
Status checkMemoryCharge(std::uint64_t charged, std::uint64_t bytes, std::uint64_t budget,
                         const std::string& what, const std::string& hint);

// The process-wide budget: 0 restores the default (probed once).
void setMemoryBudget(std::uint64_t bytes);
std::uint64_t memoryBudget();
std::uint64_t memoryCharged();
// Charges `bytes` or refuses (checkMemoryCharge); a success is counted by
// the innermost live MemoryScope of this thread.
Status chargeMemory(std::uint64_t bytes, const std::string& what, const std::string& hint);
// Gives back bytes charged on this thread (and uncounts them from its scope).
void releaseMemory(std::uint64_t bytes);
// Gives back bytes of the process-wide total only (a reservation's).
void releaseCharged(std::uint64_t bytes);

// Bytes held until the last copy of the handle is destroyed.
class MemoryReservation {
 public:
  explicit MemoryReservation(std::uint64_t bytes) : bytes_(bytes) {}
  ~MemoryReservation() { releaseCharged(bytes_); }
  MemoryReservation(const MemoryReservation&) = delete;
  MemoryReservation& operator=(const MemoryReservation&) = delete;
  std::uint64_t bytes() const { return bytes_; }

 private:
  std::uint64_t bytes_;
};

// Collects the charges this thread makes while it lives; releases them on
// destruction unless keep() handed them to a reservation.
class MemoryScope {
 public:
  MemoryScope();
  ~MemoryScope();
  MemoryScope(const MemoryScope&) = delete;
  MemoryScope& operator=(const MemoryScope&) = delete;
  std::uint64_t charged() const { return charged_; }
  // The first charge refused while this scope lived (empty: none), so a
  // loader that turns a failed texture into a warning still fails the load.
  const std::string& refused() const { return refused_; }
  std::shared_ptr<MemoryReservation> keep();

 private:
  friend Status chargeMemory(std::uint64_t, const std::string&, const std::string&);
  friend void releaseMemory(std::uint64_t);
  std::uint64_t charged_ = 0;
  std::string refused_;
  MemoryScope* outer_ = nullptr;
};

}  // namespace hw
