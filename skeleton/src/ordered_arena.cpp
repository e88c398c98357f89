#include "ordered_arena.h"

#include <sys/mman.h>

#include <algorithm>

#include <unordered_map>
#include <vector>

namespace skelgrasp::internal {

class OrderedArena {
 public:
  // Address space only; pages are committed when touched.
  explicit OrderedArena(std::size_t reserve_bytes) : reserve_(roundUp(reserve_bytes)) {
    void* p = mmap(nullptr, reserve_, PROT_READ | PROT_WRITE,
                   MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    base_ = static_cast<char*>(p);
  }
  ~OrderedArena() { munmap(base_, reserve_); }
  std::size_t used() const { return used_; }
  bool overflowed() const { return overflowed_; }

  void* allocate(std::size_t bytes) {
    const std::size_t size = roundUp(bytes);
    auto& list = free_[size];
    if (!list.empty()) {
      void* p = list.back();
      list.pop_back();
      return p;
    }
    if (used_ + size > reserve_) {
      // Throwing here would unwind through CGAL code that is not exception-safe (it crashed in
      // Delaunay insertion); the heap keeps this run correct, and the caller repeats it in a
      // larger arena because heap addresses break the deterministic order.
      overflowed_ = true;
      return ::operator new(bytes);
    }
    void* p = base_ + used_;
    used_ += size;
    return p;
  }
  void deallocate(void* p, std::size_t bytes) { free_[roundUp(bytes)].push_back(p); }
  bool owns(const void* p) const {
    const char* c = static_cast<const char*>(p);
    return c >= base_ && c < base_ + reserve_;
  }

 private:
  static std::size_t roundUp(std::size_t bytes) {
    return (std::max<std::size_t>(bytes, 1) + 15) & ~std::size_t(15);
  }

  std::size_t reserve_ = 0;
  char* base_ = nullptr;
  std::size_t used_ = 0;
  bool overflowed_ = false;
  std::unordered_map<std::size_t, std::vector<void*>> free_;
};

namespace {
thread_local OrderedArena* current_arena = nullptr;
}

OrderedArena* currentOrderedArena() {
  return current_arena;
}
void* arenaAllocate(OrderedArena& arena, std::size_t bytes) {
  return arena.allocate(bytes);
}
void arenaDeallocate(OrderedArena& arena, void* p, std::size_t bytes) {
  arena.deallocate(p, bytes);
}
bool arenaOwns(const OrderedArena& arena, const void* p) {
  return arena.owns(p);
}

OrderedArenaScope::OrderedArenaScope(std::size_t reserve_bytes)
    : arena_(std::make_unique<OrderedArena>(reserve_bytes)), previous_(current_arena) {
  current_arena = arena_.get();
}

OrderedArenaScope::~OrderedArenaScope() {
  current_arena = previous_;
}

std::size_t OrderedArenaScope::usedBytes() const {
  return arena_->used();
}

bool OrderedArenaScope::overflowed() const {
  return arena_->overflowed();
}

}  // namespace skelgrasp::internal
