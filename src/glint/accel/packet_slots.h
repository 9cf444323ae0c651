// PacketSlots: a packet's per-ray values (rays, hits, shading state), left
// unconstructed until each is set. Arrays of kPacketSize rays or hits are
// zeroed by their default member initializers on every packet: about 13 KB a
// camera packet, 4-5% of a render's samples in memset.
#pragma once

#include <new>
#include <optional>
#include <type_traits>

#include "glint/accel/accelerator.h"

namespace glint {

// Slot i is set by assigning to it (T implicit-lifetime: rays, colors) or by
// `new (&slots[i]) T(...)`; only slots that were set may be read.
template <class T>
struct PacketSlots {
  static_assert(std::is_trivially_destructible_v<T>);
  PacketSlots() {}  // leaves `values` unconstructed
  T& operator[](int i) { return values[i]; }
  const T& operator[](int i) const { return values[i]; }
  T* data() { return values; }
  const T* data() const { return values; }
  union {
    T values[kPacketSize];
  };
};

// Hits for intersect_packet: the first `count` empty (their flags set, the
// Hits themselves left unwritten).
struct PacketHits : PacketSlots<std::optional<Hit>> {
  explicit PacketHits(int count) {
    for (int i = 0; i < count; ++i) new (&values[i]) std::optional<Hit>;
  }
};

}  // namespace glint
