#pragma once
// Internal: makes CGAL's mean-curvature-flow contraction deterministic within a process.
//
// The contraction copies the mesh into a pointer-based Polyhedron_3 and collapses edges taken from
// std::set<edge_descriptor>, i.e. in memory-address order. With malloc, addresses depend on the
// heap's history, so the same mesh contracted twice in one process gave 135, 134 and 131 skeleton
// vertices. While an OrderedArenaScope is alive on a thread, CGAL containers in contraction.cpp
// (CGAL_ALLOCATOR is defined to OrderedArenaAllocator there) allocate from one reserved address
// range by bumping a pointer, with per-size free lists: addresses then follow the order of
// allocations, which depends on the input only.
//
// The range is reserved per scope, sized by the caller from its input. Growing it in separate
// chunks would break the address order (a later chunk may lie below an earlier one). Allocations
// past the range come from the heap instead (throwing would unwind through CGAL code that is not
// exception-safe) and mark the arena overflowed; the caller then repeats its work in a larger
// arena. Relative addresses, and so the result, do not depend on the reservation's size. A fixed
// giant reservation (32 GiB before) fails under any `ulimit -v` below it.
#include <cstddef>
#include <memory>
#include <new>

namespace skelgrasp::internal {

class OrderedArena;

// Current arena of this thread, or nullptr.
OrderedArena* currentOrderedArena();

void* arenaAllocate(OrderedArena& arena, std::size_t bytes);
void arenaDeallocate(OrderedArena& arena, void* p, std::size_t bytes);
bool arenaOwns(const OrderedArena& arena, const void* p);

// Activates a fresh arena of `reserve_bytes` address space on this thread; everything allocated
// from it must be released (or never touched again) before the scope ends, when the address range
// is unmapped. Throws std::bad_alloc when the range cannot be reserved at all.
class OrderedArenaScope {
 public:
  explicit OrderedArenaScope(std::size_t reserve_bytes);
  ~OrderedArenaScope();
  // Bytes handed out so far (sizes the next reservation of a similar input).
  std::size_t usedBytes() const;
  // True when the range ran out and later allocations came from the heap.
  bool overflowed() const;
  OrderedArenaScope(const OrderedArenaScope&) = delete;
  OrderedArenaScope& operator=(const OrderedArenaScope&) = delete;

 private:
  std::unique_ptr<OrderedArena> arena_;
  OrderedArena* previous_;
};

template <class T>
struct OrderedArenaAllocator {
  using value_type = T;
  OrderedArenaAllocator() noexcept = default;
  template <class U>
  OrderedArenaAllocator(const OrderedArenaAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (OrderedArena* arena = currentOrderedArena()) {
      return static_cast<T*>(arenaAllocate(*arena, n * sizeof(T)));
    }
    return std::allocator<T>().allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    OrderedArena* arena = currentOrderedArena();
    if (arena && arenaOwns(*arena, p)) {
      arenaDeallocate(*arena, p, n * sizeof(T));
    } else {
      std::allocator<T>().deallocate(p, n);
    }
  }
  template <class U>
  bool operator==(const OrderedArenaAllocator<U>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const OrderedArenaAllocator<U>&) const noexcept {
    return false;
  }
};

}  // namespace skelgrasp::internal
