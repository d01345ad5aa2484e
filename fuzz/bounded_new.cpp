// bounded_new.cpp — operator new for the fuzz targets that hand the input to
// OpenVDB: a request above 1 GiB throws std::bad_alloc, as an allocator that
// cannot serve it does (glibc's does for the petabyte sizes a damaged file
// declares), instead of AddressSanitizer's report, which never throws.
// OpenVDB 10 allocates the sizes a damaged file states before reading them
// (io::bloscFromStream: new char[size read from the stream]); the reader
// (plugin/vdb/vdb_io.cpp) must turn the bad_alloc into an error, and this
// lets the fuzzer check that it does. Smaller requests go to malloc, which
// AddressSanitizer still checks.
#include <cstdlib>
#include <new>

namespace {
constexpr std::size_t kLargest = std::size_t(1) << 30;
void* allocate(std::size_t n) {
  if (n > kLargest) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* allocate_nothrow(std::size_t n) noexcept {
  return n > kLargest ? nullptr : std::malloc(n ? n : 1);
}
}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return allocate_nothrow(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return allocate_nothrow(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
