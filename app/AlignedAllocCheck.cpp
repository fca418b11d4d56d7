// Linked into the budget-slam executable only. MRPT's aligned allocator (mrpt::aligned_malloc,
// behind every mrpt::math matrix) calls aligned_alloc() and does not check for null: when memory
// runs out (an address-space limit, `ulimit -v`), its vectors then write through a null pointer
// and the process dies by SIGSEGV. This definition, which the executable's symbol table puts
// before the C library's for every shared library, makes that failure what every other
// allocation failure is, std::bad_alloc, which the run reports in one line as "out of memory"
// (docs/RELIABILITY.md "Address-space limits"). libstdc++'s aligned operator new, the other
// caller, throws std::bad_alloc on a null result anyway.
//
// <cstdlib> is not included: glibc declares aligned_alloc noexcept there.
#include <cstddef>
#include <new>

extern "C" int posix_memalign(void** memptr, std::size_t alignment, std::size_t size) noexcept;

extern "C" void* aligned_alloc(std::size_t alignment, std::size_t size) {
  void* p = nullptr;
  if (alignment < sizeof(void*)) alignment = sizeof(void*);  // posix_memalign's minimum
  if (posix_memalign(&p, alignment, size) != 0) throw std::bad_alloc();
  return p;
}
