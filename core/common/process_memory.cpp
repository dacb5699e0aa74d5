#include "common/process_memory.hpp"

#include <malloc.h>

#include <cstdlib>

namespace fleet {

void ProcessMemory::limit_arenas() {
  if (const char* set = std::getenv("MALLOC_ARENA_MAX"); set && *set) return;  // glibc read it already
  constexpr int kArenas = 2;
  mallopt(M_ARENA_MAX, kArenas);
}

void ProcessMemory::tick(double now_wall) {
  if (last_ >= 0.0 && now_wall - last_ < period_) return;
  if (last_ >= 0.0) malloc_trim(0);
  last_ = now_wall;
}

}  // namespace fleet
