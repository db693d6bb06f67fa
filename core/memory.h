#pragma once
// Process memory: glibc malloc settings for long runs, and the resident set
// size, for the soak (scripts/soak.sh).
//
// A fixed malloc mmap threshold (128 KiB) keeps the heap's resident size flat
// over long walks, and a 4 MiB top pad keeps the heap top from being returned
// and faulted back in many times a frame. Measurements: docs/notes/memory.md.
namespace hw {

// Sets M_MMAP_THRESHOLD to 128 KiB and M_TOP_PAD to 4 MiB, each unless
// MALLOC_MMAP_THRESHOLD_ / MALLOC_TOP_PAD_ is set in the environment (the
// user's choice wins). No-op without glibc. Call once, at the start of main.
void fixMallocMmapThreshold();

// Gives the free pages of every malloc arena back to the kernel (glibc
// malloc_trim(0): free pages inside the heap as well as its top), so the
// resident size follows the live heap instead of its high-water mark.
// Costs a walk over the free lists and one madvise per free run of pages;
// the pages are faulted back in (zeroed) when next used, so call it where
// a large transient peak has just ended, not every frame (the walk: at each
// keyframe step that drops a keyframe, and before each 500-frame resident
// sample). No-op without glibc.
void returnFreeHeapPages();

// Resident set size of this process in KiB (/proc/self/statm), or −1 where
// that is not available.
long long residentKiB();

}  // namespace hw
