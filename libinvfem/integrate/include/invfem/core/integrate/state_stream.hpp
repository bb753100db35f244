#pragma once
// Binary streams for the state a simulation carries beyond positions and velocities (plastic
// Fp, plastic rest angles): each stateful Force writes and reads its own (Force::save_state,
// restore_state), so checkpoints know no force type. Values are stored in the machine's byte
// order (a checkpoint is for resuming on the same build), counts as 64-bit integers.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "invfem/core/math/types.hpp"

namespace invfem {

// A state stream that does not hold what its reader expects. The message names the item.
class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class StateWriter {
 public:
  template <class T> void pod(const T& v) { bytes_.append(reinterpret_cast<const char*>(&v), sizeof v); }
  void count(std::size_t n) { pod(static_cast<std::uint64_t>(n)); }
  // n, then n doubles.
  void doubles(const double* p, std::size_t n) {
    count(n);
    bytes_.append(reinterpret_cast<const char*>(p), n * sizeof(double));
  }
  void doubles(const std::vector<double>& v) { doubles(v.data(), v.size()); }
  void string(const std::string& s) {
    count(s.size());
    bytes_ += s;
  }
  // A matrix list: n, then n blocks of R*C doubles (column-major, as Eigen stores them).
  template <class M> void matrices(const std::vector<M>& list) {
    count(list.size());
    for (const M& m : list) bytes_.append(reinterpret_cast<const char*>(m.data()), sizeof(double) * m.size());
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class StateReader {
 public:
  explicit StateReader(std::string bytes) : bytes_(std::move(bytes)) {}
  template <class T> T pod(const std::string& what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  std::uint64_t count(const std::string& what) { return pod<std::uint64_t>(what); }
  // Reads n doubles written by StateWriter::doubles; n must equal `expected`.
  void doubles(double* p, std::size_t expected, const std::string& what) {
    const std::uint64_t n = count(what);
    if (n != expected)
      throw StateError(what + " holds " + std::to_string(n) + " values, " + std::to_string(expected) + " expected");
    need(n * sizeof(double), what);
    std::memcpy(p, bytes_.data() + pos_, n * sizeof(double));
    pos_ += n * sizeof(double);
  }
  void doubles(std::vector<double>& v, std::size_t expected, const std::string& what) {
    v.resize(expected);
    doubles(v.data(), expected, what);
  }
  std::string string(const std::string& what) {
    const std::uint64_t n = count(what);
    need(n, what);
    std::string s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  template <class M> void matrices(std::vector<M>& list, std::size_t expected, const std::string& what) {
    const std::uint64_t n = count(what);
    if (n != expected)
      throw StateError(what + " holds " + std::to_string(n) + " entries, " + std::to_string(expected) + " expected");
    list.resize(n);
    for (M& m : list) {
      const std::size_t size = sizeof(double) * static_cast<std::size_t>(m.size());
      need(size, what);
      std::memcpy(m.data(), bytes_.data() + pos_, size);
      pos_ += size;
    }
  }
  bool at_end() const { return pos_ == bytes_.size(); }
  void expect_end(const std::string& what) const {
    if (!at_end()) throw StateError(what + " has " + std::to_string(bytes_.size() - pos_) + " bytes too many");
  }

 private:
  void need(std::uint64_t n, const std::string& what) const {
    if (n > bytes_.size() - pos_) throw StateError(what + " is truncated");
  }
  std::string bytes_;
  std::size_t pos_ = 0;
};

}  // namespace invfem
