// The dba program's operator new: large blocks (every array that grows with
// the problem: observations, the RCS, PCG's vectors) are advised onto huge
// pages before they are first written (common/memory.h AdviseHugePages).
//
// Why: each first write of a 4 KiB page is a page fault, and where the
// system shadows page tables (virtual machines without nested paging; this
// project's benchmark machine) a fault costs about 17 µs: 4.2 s per GiB
// touched, against 0.1 s per GiB of 2 MiB pages that the guest still backs.
// A 1M-image solve first-touches tens of GiB (its arrays, and the pages
// PCG's scratch gives back between LM iterations). Random reads into the RCS
// also miss the TLB less.
//
// In the executable only, not in dba_core: a library must not replace a host
// program's (Python's) allocation functions; nor under the sanitizers, whose
// own operator new checks the pairs. Blocks come from malloc and go back
// with free; every other operator new and delete of libstdc++ (nothrow,
// array, sized) ends in these or in malloc and free. malloc maps the large
// blocks afresh (untouched; from 32 MiB on always), while blocks of 4 to 32
// MiB may come from its heap once its threshold has risen: the advice then
// applies to those heap pages, which malloc reuses without new faults.
// Over-aligned new (aligned_alloc) and delete (free) keep libstdc++'s
// definitions and are not advised: nothing large is over-aligned here.
#include <cstdlib>
#include <new>

#include "dba/common/memory.h"

namespace {

// Smaller blocks come from malloc's arenas, already touched; 4 MiB holds at
// least one whole huge page wherever it starts.
constexpr std::size_t kAdviseBytes = std::size_t{4} << 20;

void* Allocate(std::size_t bytes) {
  void* p = nullptr;
  // As the standard's operator new: the new-handler until it gives up.
  while ((p = std::malloc(bytes == 0 ? 1 : bytes)) == nullptr) {
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
  if (bytes >= kAdviseBytes) dba::AdviseHugePages(p, static_cast<int64_t>(bytes));
  return p;
}

}  // namespace

void* operator new(std::size_t bytes) { return Allocate(bytes); }
void* operator new[](std::size_t bytes) { return Allocate(bytes); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
