// Minimal binary (de)serialisation for checkpoints: trivially copyable values and vectors of
// them, written in the machine's byte order (a checkpoint restarts on the same kind of machine).
#pragma once

#include <cstdint>
#include <cstring>
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

 private:
  std::string buffer_;
};

class BinaryReader {
 public:
  explicit BinaryReader(const std::string& bytes) : bytes_(bytes) {}
  template <class T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    take(&v, sizeof(T));
    return v;
  }
  template <class T>
  void vector(std::vector<T>& v) {
    const auto n = value<std::uint64_t>();
    if (n > (bytes_.size() - position_) / (sizeof(T) == 0 ? 1 : sizeof(T)))
      throw std::runtime_error("checkpoint is truncated or corrupt");
    v.resize(n);
    if (n) take(v.data(), n * sizeof(T));
  }
  std::string string() {
    const auto n = value<std::uint64_t>();
    if (n > bytes_.size() - position_) throw std::runtime_error("checkpoint is truncated or corrupt");
    std::string s = bytes_.substr(position_, n);
    position_ += n;
    return s;
  }
  bool at_end() const { return position_ == bytes_.size(); }

 private:
  void take(void* out, std::size_t n) {
    if (n > bytes_.size() - position_) throw std::runtime_error("checkpoint is truncated or corrupt");
    std::memcpy(out, bytes_.data() + position_, n);
    position_ += n;
  }
  const std::string& bytes_;
  std::size_t position_ = 0;
};

}  // namespace quarry
