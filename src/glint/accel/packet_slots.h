// PacketSlots: a packet's per-ray values (rays, hits, shading state), left
// unconstructed until each is set. Arrays of kPacketSize rays or hits are
// zeroed by their default member initializers on every packet: about 13 KB a
// camera packet, 4-5% of a render's samples in memset.
#pragma once

#include <cstddef>
#include <cstring>
#include <new>
#include <optional>
#include <type_traits>

#include "glint/accel/accelerator.h"

// Filled with 0xff bytes where assertions or AddressSanitizer are on (the
// test suite's sanitizer build among them).
#if !defined(NDEBUG) || defined(__SANITIZE_ADDRESS__)
#define GLINT_FILL_PACKET_SLOTS 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GLINT_FILL_PACKET_SLOTS 1
#endif
#endif

namespace glint {

// Raw storage for N values of T (a packet's kPacketSize by default). Slot i is set by assigning to it
// or to its fields (T implicit-lifetime: rays, colors, whose objects the
// byte array creates implicitly) or by `new (&slots[i]) T(...)`; only slots
// that were set may be read. Checking builds (GLINT_FILL_PACKET_SLOTS) fill
// the storage with 0xff bytes (NaN doubles), so a slot read before it is set
// shows in the tests that compare packets with single rays bit for bit.
template <class T, int N = kPacketSize>
class PacketSlots {
  static_assert(std::is_trivially_destructible_v<T>);

 public:
  PacketSlots() {
#ifdef GLINT_FILL_PACKET_SLOTS
    std::memset(storage_, 0xff, sizeof storage_);
#endif
  }
  T& operator[](int i) { return data()[i]; }
  const T& operator[](int i) const { return data()[i]; }
  T* data() { return std::launder(reinterpret_cast<T*>(storage_)); }
  const T* data() const { return std::launder(reinterpret_cast<const T*>(storage_)); }

 private:
  alignas(T) std::byte storage_[N * sizeof(T)];
};

// Hits for intersect_packet: the first `count` empty (their flags set, the
// Hits themselves left unwritten).
template <int N = kPacketSize>
struct PacketHits : PacketSlots<std::optional<Hit>, N> {
  explicit PacketHits(int count) {
    for (int i = 0; i < count; ++i) new (&(*this)[i]) std::optional<Hit>;
  }
};

}  // namespace glint
