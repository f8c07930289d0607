// Process-wide memory settings.
#ifndef SYLVA_CORE_UTIL_MEMORY_H_
#define SYLVA_CORE_UTIL_MEMORY_H_

namespace sylva {

// Lets the C allocator keep freed memory for reuse. The stages allocate and
// free buffers of megabytes over and over (mattes, summed-area tables, ray
// systems, meshes); by default glibc maps each block over its adaptive
// threshold afresh and returns freed memory to the system, so every reuse
// costs page faults and the kernel zeroing pages: a fifth of the density
// stage's time on the demo. With blocks up to glibc's largest threshold
// (32 MiB) taken from the heap and the heap never trimmed, `sylva run` after
// a density edit took 60k page faults instead of 92k and 10 % less CPU time.
// The cost: a process keeps its peak heap until it exits (the app too,
// between runs; later runs reuse it). Programs call it first thing in
// main(); a no-op where glibc is not used.
void KeepFreedMemoryForReuse();

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_MEMORY_H_
