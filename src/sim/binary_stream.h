// Minimal binary (de)serialisation for checkpoints: trivially copyable values and vectors of
// them, written in the machine's byte order (a checkpoint restarts on the same kind of machine).
#pragma once

#include <cstdint>
#include <cstring>
#include <istream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace quarry {

class BinaryWriter {
 public:
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* bytes = reinterpret_cast<const char*>(&v);
    buffer_.append(bytes, sizeof(T));
  }
  template <class T>
  void vector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value<std::uint64_t>(v.size());
    if (!v.empty()) buffer_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void string(const std::string& s) {
    value<std::uint64_t>(s.size());
    buffer_.append(s);
  }
  const std::string& bytes() const { return buffer_; }
  std::string& bytes() { return buffer_; }

 private:
  std::string buffer_;
};

// Reads what BinaryWriter wrote, straight from a stream of known length: no copy of the whole
// file in memory (a checkpoint of millions of particles is gigabytes). Throws
// std::runtime_error on a truncated or corrupt stream; never reads past `size` bytes, and never
// allocates more than the bytes that remain could fill.
class BinaryReader {
 public:
  BinaryReader(std::istream& in, std::uint64_t size) : in_(in), remaining_(size) {}
  template <class T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    take(&v, sizeof(T));
    return v;
  }
  template <class T>
  void vector(std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto n = value<std::uint64_t>();
    if (n > remaining_ / (sizeof(T) == 0 ? 1 : sizeof(T)))
      throw std::runtime_error("an array is longer than the rest of the file (truncated or corrupt)");
    v.resize(n);
    if (n) take(v.data(), n * sizeof(T));
  }
  std::string string() {
    const auto n = value<std::uint64_t>();
    if (n > remaining_) throw std::runtime_error("a text is longer than the rest of the file (truncated or corrupt)");
    std::string s(n, '\0');
    if (n) take(s.data(), n);
    return s;
  }
  bool at_end() const { return remaining_ == 0; }

 private:
  void take(void* out, std::uint64_t n) {
    if (n > remaining_) throw std::runtime_error("the file ends early (truncated)");
    in_.read(static_cast<char*>(out), static_cast<std::streamsize>(n));
    if (!in_) throw std::runtime_error("the file ends early or cannot be read");
    remaining_ -= n;
  }
  std::istream& in_;
  std::uint64_t remaining_;
};

}  // namespace quarry
