#pragma once
// A one-line progress report on stderr for long runs: "LABEL: frame N/M (P%)
// elapsed S s, ETA E s", at most once a second and once at the end.
#include <cstdio>
#include <string>

#include "core/timer.h"

namespace hw {

class Progress {
 public:
  Progress(bool on, int total, std::string label) : on_(on), total_(total), label_(std::move(label)) {}
  void update(int done) {
    if (!on_ || (sinceLast_.ms() < 1000 && done < total_)) return;
    sinceLast_.restart();
    const double el = all_.ms() / 1000.0;
    const double eta = done > 0 ? el / done * (total_ - done) : 0;
    std::fprintf(stderr, "\r%s: frame %d/%d (%3.0f%%) elapsed %.0f s, ETA %.0f s   ", label_.c_str(),
                 done, total_, total_ > 0 ? 100.0 * done / total_ : 100.0, el, eta);
    if (done >= total_) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }

 private:
  bool on_;
  int total_;
  std::string label_;
  Stopwatch all_, sinceLast_;
};

}  // namespace hw
