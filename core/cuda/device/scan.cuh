// The result of the two-pass exclusive scan (sph_scan_local and sph_scan_top, grid.cu) at
// entry i: the block's local sum plus the block's offset. Used where a scan of marks ranks
// the marked slots (exchange.cu's compaction, view.cu's kind order).
#pragma once
#include "sph_consts.h"

// The number of marked slots before slot i, from the scan of the marks.
__device__ __forceinline__ unsigned compacted(const unsigned* __restrict__ local, const unsigned* __restrict__ bsum,
                                              unsigned i) {
    return local[i] + bsum[i / MF_SCAN_CELLS];
}
