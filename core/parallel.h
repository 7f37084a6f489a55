// Deterministic parallel loops on TBB: work is cut into fixed blocks whose boundaries do not depend
// on the thread count, and each block writes only its own output, so results are identical for any
// number of threads.
#pragma once

#include <cstddef>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

namespace causticbench {

// fn(begin, end, block_index) for consecutive blocks of `block_size` items.
template <typename Function>
void parallel_blocks(size_t count, size_t block_size, Function fn) {
  size_t blocks = (count + block_size - 1) / block_size;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks, 1), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t block = range.begin(); block != range.end(); ++block) {
      size_t begin = block * block_size;
      size_t end = std::min(count, begin + block_size);
      fn(begin, end, block);
    }
  }, tbb::simple_partitioner());
}

// Limits every TBB loop in the process to `threads` threads (0: all cores) while it lives.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  static int current();

 private:
  std::unique_ptr<tbb::global_control> control_;
};

}  // namespace causticbench
