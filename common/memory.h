// Process-wide tuning of glibc's malloc for the solvers' allocation pattern: each Newton iteration
// on a whole course builds and frees Jacobians and sparse factors of tens to hundreds of
// megabytes. glibc serves blocks above 32 MB (its largest mmap threshold) by fresh mappings,
// whose pages the kernel faults in and zeroes on first touch and unmaps on free: on the TT course
// that was 61 s of system time in a 475 s solve (docs/lap_log.md "Freed memory kept for reuse": 26 s
// and 443.5 s with this).
#pragma once

namespace ttz {

// Makes malloc serve every block from its heap (no mmap) and keep freed memory there for reuse
// (trim threshold INT_MAX, about 2 GB, the most mallopt takes: a free heap top above that is
// still given back, so a solver must not reserve far more than it uses, lap/solver/sparse_lu.cc);
// call once at the start of main(). The price is a higher peak resident
// size: the heap keeps what a freed block leaves between live ones.
void KeepFreedMemory();

}  // namespace ttz
