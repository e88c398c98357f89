#include "skelgrasp/common/signal_cleanup.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

namespace skelgrasp {
namespace {

enum SlotState : int { kFree = 0, kFilling = 1, kReady = 2 };

// Fixed storage, so that the handler reads paths without locks or allocation. A slot is claimed
// (kFree -> kFilling), filled, published (kReady) and freed again (kFree); the handler reads kReady
// slots only.
struct Slot {
  std::atomic<int> state{kFree};
  std::atomic<int> kind{0};
  std::atomic<unsigned long> order{0};  // registration order: directories go innermost first
  char path[kMaxSignalCleanupPathBytes] = {};
};

Slot g_slots[kMaxSignalCleanupEntries];
std::atomic<unsigned long> g_next_order{1};
std::atomic<bool> g_installed{false};

constexpr int kCleanedSignals[] = {SIGINT, SIGTERM, SIGHUP};

bool isDirectoryKind(const Slot& slot) {
  return slot.kind.load(std::memory_order_relaxed) ==
         static_cast<int>(SignalCleanupEntry::Kind::kEmptyDirectory);
}

void handleSignal(int signal_number) {
  runSignalCleanup();
  // SA_RESETHAND restored the default action; raised again, the signal is delivered when this
  // handler returns and ends the process with the status a shell expects (130 for Ctrl-C).
  ::raise(signal_number);
}

}  // namespace

void installSignalCleanup() {
  if (g_installed.exchange(true)) return;
  for (const int signal_number : kCleanedSignals) {
    struct sigaction previous = {};
    if (::sigaction(signal_number, nullptr, &previous) != 0) continue;
    if (previous.sa_handler == SIG_IGN) continue;  // ignored by the parent's wish: stays ignored
    struct sigaction action = {};
    action.sa_handler = handleSignal;
    action.sa_flags = SA_RESETHAND;
    ::sigemptyset(&action.sa_mask);
    for (const int other : kCleanedSignals) ::sigaddset(&action.sa_mask, other);
    ::sigaction(signal_number, &action, nullptr);
  }
}

void runSignalCleanup() {
  for (Slot& slot : g_slots) {
    if (slot.state.load(std::memory_order_acquire) == kReady && !isDirectoryKind(slot))
      ::unlink(slot.path);
  }
  // Directories, the most recently registered first (the atomic writer registers the outermost
  // first); rmdir removes only empty ones. Selection without allocation: each pass takes the
  // newest directory older than the previous pass's.
  unsigned long below = ~0ul;
  for (std::size_t pass = 0; pass < kMaxSignalCleanupEntries; ++pass) {
    Slot* newest = nullptr;
    unsigned long newest_order = 0;
    for (Slot& slot : g_slots) {
      if (slot.state.load(std::memory_order_acquire) != kReady || !isDirectoryKind(slot)) continue;
      const unsigned long order = slot.order.load(std::memory_order_relaxed);
      if (order < below && order > newest_order) {
        newest = &slot;
        newest_order = order;
      }
    }
    if (newest == nullptr) break;
    ::rmdir(newest->path);
    below = newest_order;
  }
}

SignalCleanupEntry::SignalCleanupEntry(const std::string& path, Kind kind) {
  if (path.empty() || path.size() >= kMaxSignalCleanupPathBytes) return;
  for (std::size_t i = 0; i < kMaxSignalCleanupEntries; ++i) {
    Slot& slot = g_slots[i];
    int expected = kFree;
    if (!slot.state.compare_exchange_strong(expected, kFilling, std::memory_order_acquire))
      continue;
    std::memcpy(slot.path, path.c_str(), path.size() + 1);
    slot.kind.store(static_cast<int>(kind), std::memory_order_relaxed);
    slot.order.store(g_next_order++, std::memory_order_relaxed);
    slot.state.store(kReady, std::memory_order_release);
    slot_ = static_cast<int>(i);
    return;
  }
}

SignalCleanupEntry::~SignalCleanupEntry() {
  release();
}

SignalCleanupEntry::SignalCleanupEntry(SignalCleanupEntry&& other) noexcept : slot_(other.slot_) {
  other.slot_ = -1;
}

SignalCleanupEntry& SignalCleanupEntry::operator=(SignalCleanupEntry&& other) noexcept {
  if (this != &other) {
    release();
    slot_ = other.slot_;
    other.slot_ = -1;
  }
  return *this;
}

void SignalCleanupEntry::release() {
  if (slot_ < 0) return;
  g_slots[slot_].state.store(kFree, std::memory_order_release);
  slot_ = -1;
}

}  // namespace skelgrasp
