// Reading a fuzzer's bytes as typed values: past the end, values are zero.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace hope {
namespace fuzz {

class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  template <class T>
  T take() {
    T value{};
    const std::size_t n = std::min(sizeof(T), size_ - used_);
    if (n > 0) std::memcpy(&value, data_ + used_, n);
    used_ += n;
    return value;
  }
  std::vector<std::uint8_t> rest() {
    std::vector<std::uint8_t> out(data_ + used_, data_ + size_);
    used_ = size_;
    return out;
  }
  std::size_t remaining() const { return size_ - used_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t used_ = 0;
};

}  // namespace fuzz
}  // namespace hope
