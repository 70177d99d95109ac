// Keeping freed memory in the process for the next frame's images.
#pragma once

namespace lt {

// glibc serves blocks above its mmap threshold (128 KiB to 32 MiB, growing as
// such blocks are freed) from fresh mappings and returns them to the kernel on
// free, and trims the heap's free top above its trim threshold. A frame's
// per-pixel buffers (chief hits, film, ground truth: about 150 bytes a pixel)
// were then mapped anew and page-faulted in every frame: at 640x480, some
// 13 000 faults a frame, a third of the 1-spp dim frame's wall time on two
// threads (docs/performance.md). This raises both thresholds to 1 GiB, so that freed
// blocks stay in the heap for the next frame (the process keeps at most its
// peak). Call once, at the start of main, before any threads; does nothing
// on other C libraries.
void RetainFreedMemory();

}  // namespace lt
