// How the process's heap gives memory back: large blocks go back to the system when freed.
#pragma once

namespace m2mlat::core {

// glibc's malloc raises its mmap threshold (up to 32 MiB) each time an mmapped block is freed; from
// then on blocks below that size come from the heap, and a freed one stays resident while anything
// allocated after it lives. The analysis allocates and frees arrays of 10 to 100 MB phase after
// phase (the matcher's passes, the summary), so those remnants added up: `m2mlat stats` at 10^7
// edges a side held about 20 MiB of them while summarising. This fixes the threshold at 1 MiB, so
// that every block of 1 MiB or more is mmapped and returned when freed. cli::run calls it first
// thing; it does nothing with another C library.
void return_large_blocks_when_freed();

}  // namespace m2mlat::core
