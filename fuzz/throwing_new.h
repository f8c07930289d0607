// Replaces the global operator new and delete, in the one fuzz target that
// includes this header, by malloc and free with the C++ library's own
// contract: std::bad_alloc when the memory cannot be had.
//
// Why: OpenVDB allocates the size a block of a .vdb file claims before it
// reads the block, so a damaged size field asks for exabytes. The C++
// library then throws std::bad_alloc, which ReadDensityGrid turns into a
// clear error naming the file; AddressSanitizer's own operator new instead
// reports "out of memory" and aborts, so under it the fuzzer would report
// a crash the program does not have. With ASAN_OPTIONS
// allocator_may_return_null=1 and max_allocation_size_mb (scripts/fuzz.sh)
// malloc returns null past the limit; every other check of AddressSanitizer
// (overflows, use after free, leaks) still holds, only new/delete mismatches
// are no longer told apart from malloc/free ones.
//
// Include it in exactly one translation unit of a target. The aligned
// forms stay AddressSanitizer's: they are allocated and freed as a pair.
#ifndef SYLVA_FUZZ_THROWING_NEW_H_
#define SYLVA_FUZZ_THROWING_NEW_H_

#include <cstddef>
#include <cstdlib>
#include <new>

void* operator new(std::size_t size) {
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return std::malloc(size == 0 ? 1 : size);
}
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete[](void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
void operator delete[](void* memory, std::size_t) noexcept { std::free(memory); }
void operator delete(void* memory, const std::nothrow_t&) noexcept { std::free(memory); }
void operator delete[](void* memory, const std::nothrow_t&) noexcept { std::free(memory); }

#endif  // SYLVA_FUZZ_THROWING_NEW_H_
