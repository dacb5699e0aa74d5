#pragma once

namespace fleet {

/// Upkeep of a long-running process's resident memory under glibc's malloc.
///
/// Cyclone's receive and delivery threads allocate the samples the main loop later frees. glibc
/// serves those threads from arenas of their own and returns a freed chunk to the arena it came
/// from, where it stays resident until the arena's top is trimmed; a thread that finds its arena
/// locked is even given a new one. In an 8-agent soak an agent's live heap stayed flat
/// (heaptrack) while a second arena's resident pages grew by about 1.4 MB in two minutes.
class ProcessMemory {
 public:
  /// At most two arenas, unless MALLOC_ARENA_MAX is set. Call before any thread starts.
  static void limit_arenas();

  explicit ProcessMemory(double trim_period_wall_s = 10.0) : period_(trim_period_wall_s) {}
  /// Every `trim_period_wall_s`: hands the free pages of every arena back to the system
  /// (malloc_trim). It takes well under a millisecond for a process of this size.
  void tick(double now_wall);

 private:
  double period_;
  double last_ = -1.0;
};

}  // namespace fleet
