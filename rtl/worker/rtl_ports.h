// Helpers for the worker's RTL tests: Verilated ports of any width as 128-bit integers, and sign extension.
// Verilator gives a port of up to 8, 16, 32 or 64 bits as CData, SData, IData or QData and a wider one as
// VlWide<words> (32-bit words, least significant first).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

// Verilator's headers are not warning-free under -Wextra: included here first, with that warning off.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>
#pragma GCC diagnostic pop

#include <tripsitter/core/fixed.h>

namespace tripsitter::rtl {

using core::Int128;
using core::UInt128;

inline void put(CData& port, UInt128 v) { port = static_cast<CData>(v); }
inline void put(SData& port, UInt128 v) { port = static_cast<SData>(v); }
inline void put(IData& port, UInt128 v) { port = static_cast<IData>(v); }
inline void put(QData& port, UInt128 v) { port = static_cast<QData>(v); }
template <std::size_t Words>
void put(VlWide<Words>& port, UInt128 v) {
  for (std::size_t i = 0; i < Words; ++i) port[i] = i < 4 ? static_cast<EData>(v >> (32 * i)) : EData{0};
}

// One clock of a Verilated model with a `clk` input: the rising edge, after which its registers hold the new state.
template <class Top>
void rising_edge(Top& top) {
  top.clk = 0;
  top.eval();
  top.clk = 1;
  top.eval();
}

// The low `bits` bits set (all 64 from 63 on).
inline std::int64_t mask(int bits) { return bits >= 63 ? -1 : (std::int64_t{1} << bits) - 1; }

inline UInt128 get(CData port) { return port; }
inline UInt128 get(SData port) { return port; }
inline UInt128 get(IData port) { return port; }
inline UInt128 get(QData port) { return port; }
template <std::size_t Words>
UInt128 get(const VlWide<Words>& port) {
  UInt128 v = 0;
  for (std::size_t i = 0; i < Words && i < 4; ++i) v |= static_cast<UInt128>(port[i]) << (32 * i);
  return v;
}

// The low `bits` bits of v as a two's complement number.
inline Int128 sign_extend(UInt128 v, int bits) {
  const UInt128 mask = bits >= 128 ? ~UInt128{0} : (UInt128{1} << bits) - 1;
  v &= mask;
  if (bits < 128 && ((v >> (bits - 1)) & 1) != 0) v |= ~mask;
  return static_cast<Int128>(v);
}

// A decimal string of a 128-bit integer (for failure messages).
inline std::string to_string(Int128 v) {
  if (v == 0) return "0";
  const bool negative = v < 0;
  UInt128 m = negative ? static_cast<UInt128>(-(v + 1)) + 1 : static_cast<UInt128>(v);
  std::string s;
  while (m != 0) {
    s.insert(s.begin(), static_cast<char>('0' + static_cast<int>(m % 10)));
    m /= 10;
  }
  return negative ? "-" + s : s;
}
inline std::string to_string(UInt128 v) {
  if (v == 0) return "0";
  std::string s;
  while (v != 0) {
    s.insert(s.begin(), static_cast<char>('0' + static_cast<int>(v % 10)));
    v /= 10;
  }
  return s;
}

// Bits [lo, lo + width) of a port of any width, width <= 64: set to v's low bits, or read (unsigned).
template <std::size_t Words>
void set_bits(VlWide<Words>& port, int lo, int width, std::int64_t v) {
  for (int b = 0; b < width; ++b) {
    const auto at = static_cast<std::size_t>(lo + b);
    const EData bit = static_cast<EData>((static_cast<std::uint64_t>(v) >> b) & 1u) << (at % 32);
    port[at / 32] = (port[at / 32] & ~(EData{1} << (at % 32))) | bit;
  }
}
template <class Port>
void set_bits(Port& port, int lo, int width, std::int64_t v) {
  const UInt128 m = ((UInt128{1} << width) - 1) << lo;
  put(port, (get(port) & ~m) | ((static_cast<UInt128>(static_cast<std::uint64_t>(v)) << lo) & m));
}
template <std::size_t Words>
std::int64_t bits_of(const VlWide<Words>& port, int lo, int width) {
  std::uint64_t v = 0;
  for (int b = 0; b < width; ++b) {
    const auto at = static_cast<std::size_t>(lo + b);
    v |= static_cast<std::uint64_t>((port[at / 32] >> (at % 32)) & 1u) << b;
  }
  return static_cast<std::int64_t>(v);
}
template <class Port>
std::int64_t bits_of(const Port& port, int lo, int width) {
  return static_cast<std::int64_t>((get(port) >> lo) & ((UInt128{1} << width) - 1));
}

}  // namespace tripsitter::rtl
