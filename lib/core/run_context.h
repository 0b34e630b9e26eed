// What every stage of one run shares, handed down whole instead of copied field by field: the
// seed of its random streams, its worker threads and whether it may talk on stderr.
#pragma once

#include <cstdint>

namespace sss {

struct RunContext {
  // Every Monte Carlo stage derives its streams from it (with its own offset), so a result
  // depends on the seed alone, never on the thread count (core/random.h).
  uint64_t seed = 1;
  int threads = 0;    // <= 0: all cores
  bool quiet = true;  // no progress bars or informational lines
};

}  // namespace sss
