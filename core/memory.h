#pragma once
// Process memory: glibc malloc settings for long runs, and the resident set
// size, for the soak (issue #7, scripts/soak.sh).
//
// glibc raises its mmap threshold each time an mmapped block is freed (up to
// 32 MiB on 64-bit) and its trim threshold to twice that. Scene loading frees
// multi-MiB temporaries, so afterwards llvmpipe's per-draw vertex buffers
// (135–213 KiB, about 12 per in-between frame, malloc'd and freed inside
// glDrawArrays) come from the brk heap between long-lived allocations, and
// the heap top is no longer trimmed after the binner's transient MiBs of each
// keyframe render: the heap's resident size ratchets up to the worst view
// seen although the live heap does not grow. In the 10,000-frame soak
// (indoor, 256², 2026-11) [heap] RSS went 41.8 → 46.1 MiB after frame 1,000
// with the live heap flat at ≈43 MiB (heaptrack). A fixed threshold (glibc's
// default 128 KiB) turns the adjustment off: blocks that large are mmapped
// and unmapped on free, the heap top is trimmed, and [heap] RSS stays flat.
// Cost of that alone: a fixed threshold also fixes the trim threshold at
// 128 KiB, so the heap top is returned to the kernel and faulted back in
// (zeroed pages) many times a frame: 18 brk calls per frame on forza at
// 512², 214k minor faults and 0.9 s of system time over 120 frames. A 4 MiB
// top pad (M_TOP_PAD: the heap grows and shrinks in 4 MiB steps) brings that
// to 78k faults and 0.4 s, in-between frames 5–10 % faster (2026-12, two
// pairs, noisy), at a constant ≤ 4 MiB of RSS. A 1 MiB mmap threshold
// instead was as fast but let the soak's RSS climb to 420 MiB.
namespace hw {

// Sets M_MMAP_THRESHOLD to 128 KiB and M_TOP_PAD to 4 MiB, each unless
// MALLOC_MMAP_THRESHOLD_ / MALLOC_TOP_PAD_ is set in the environment (the
// user's choice wins). No-op without glibc. Call once, at the start of main.
void fixMallocMmapThreshold();

// Resident set size of this process in KiB (/proc/self/statm), or −1 where
// that is not available.
long long residentKiB();

}  // namespace hw
