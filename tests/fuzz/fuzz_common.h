// Shared by the fuzz targets: a byte reader and the invariant every call must satisfy — it returns
// finite positions of the right shape, or throws bdinterp::InvalidInput / SolverError. Anything
// else (another exception, a crash, a sanitizer report, NaN or inf in the output) is a finding.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <functional>

#include "bdinterp/types.h"

namespace fuzz {

// Reads fixed-size values from the input; past its end every value reads as zero bytes.
class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool empty() const { return pos_ >= size_; }
  uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  template <class T>
  T raw() {
    T v{};
    unsigned char b[sizeof(T)] = {};
    for (size_t k = 0; k < sizeof(T); ++k) b[k] = byte();
    std::memcpy(&v, b, sizeof(T));
    return v;
  }
  // A double: raw bits (NaN, inf, denormals, 1e300 ...) when the selector byte is odd, else a
  // small "reasonable" value in [-lo, lo) so that most inputs get past validation.
  double number(double lo) {
    if (byte() & 1) return raw<double>();
    return lo * (raw<int16_t>() / 32768.0);
  }

 private:
  const uint8_t* data_;
  size_t size_, pos_ = 0;
};

[[noreturn]] inline void finding(const char* what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
  std::abort();
}

// Runs `call`, which fills `out`; checks the invariant above for `rows` x 2 output.
inline void check(const std::function<void(bdinterp::Positions& out)>& call, long rows) {
  bdinterp::Positions out;
  try {
    call(out);
  } catch (const bdinterp::InvalidInput&) {
    return;
  } catch (const bdinterp::SolverError&) {
    return;
  } catch (const std::bad_alloc&) {
    finding("std::bad_alloc (an input size is not bounded by validation)");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "untyped exception: %s\n", e.what());
    finding("an exception other than InvalidInput / SolverError");
  }
  if (out.rows() != rows) finding("output has the wrong number of rows");
  if (!out.allFinite()) finding("non-finite output presented as a result");
}

}  // namespace fuzz
