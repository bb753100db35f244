// Fuzz corpus generator: reads the valid seed files in --seeds, adds derived binary PLY seeds,
// and writes --per-seed deterministic mutants of each into --out (flat, so the scene seeds find
// their meshes by relative path). Same --seed, same corpus. Mutants are named
// <stem>.mNNNNN.<ext>, so the reader is still picked by extension; seeds keep their names.
//
//   fuzz_generate --seeds DIR --out DIR [--per-seed N] [--seed S]
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "invfem/core/io/ply_writer.hpp"

namespace fs = std::filesystem;

namespace {

// Mutants larger than this are cut back: the readers' speed on big files is not the point here.
constexpr std::size_t kMaxMutantBytes = 256 * 1024;

struct Token {
  std::size_t pos, len;
  bool number;
};

bool delimiter(char c) {
  return std::isspace(static_cast<unsigned char>(c)) || std::strchr(",:[]{}()\"/", c) != nullptr || c == 0;
}

std::vector<Token> tokens(const std::string& s) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < s.size()) {
    if (delimiter(s[i])) {
      ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < s.size() && !delimiter(s[i])) ++i;
    const char c = s[start];
    const bool number = std::isdigit(static_cast<unsigned char>(c)) ||
                        ((c == '-' || c == '+' || c == '.') && start + 1 < i);
    out.push_back({start, i - start, number});
  }
  return out;
}

// [begin, end) of every line, the newline included.
std::vector<std::pair<std::size_t, std::size_t>> lines(const std::string& s) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::size_t b = 0;
  while (b < s.size()) {
    std::size_t e = s.find('\n', b);
    e = (e == std::string::npos) ? s.size() : e + 1;
    out.emplace_back(b, e);
    b = e;
  }
  return out;
}

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  std::string mutate(std::string s) {
    const int ops = 1 + static_cast<int>(pick(3));
    for (int k = 0; k < ops && !s.empty(); ++k) s = one(std::move(s));
    if (s.size() > kMaxMutantBytes) s.resize(kMaxMutantBytes);
    return s;
  }

 private:
  std::size_t pick(std::size_t n) { return n ? std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_) : 0; }
  template <std::size_t N> const char* pick_of(const std::array<const char*, N>& a) { return a[pick(N)]; }

  // Index of a random token (numbers only if `number`), or -1 if there is none.
  long token_index(const std::vector<Token>& t, bool number) {
    std::vector<long> cand;
    for (std::size_t i = 0; i < t.size(); ++i)
      if (!number || t[i].number) cand.push_back(static_cast<long>(i));
    return cand.empty() ? -1 : cand[pick(cand.size())];
  }

  std::string one(std::string s) {
    static const std::array<const char*, 14> huge = {
        "1e308", "1e309", "-1e309", "99999999999999999999", "2147483647", "2147483648", "-2147483648",
        "4294967296", "9223372036854775807", "18446744073709551616", "1e-320", "4294967295", "65536", "1e18"};
    static const std::array<const char*, 8> nonfinite = {"nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e999", "0x1p9999"};
    static const std::array<const char*, 10> odd = {"null", "true", "[]", "{}", "\"\"", "-0", "1.5", "0.0", "\"x\"", "-1"};
    const std::vector<Token> t = tokens(s);
    const auto ls = lines(s);
    const std::size_t op = pick(15);
    switch (op) {
      case 0: {  // bit flips
        const int flips = 1 + static_cast<int>(pick(4));
        for (int f = 0; f < flips; ++f) s[pick(s.size())] ^= static_cast<char>(1u << pick(8));
        return s;
      }
      case 1:  // truncation
        s.resize(pick(s.size()));
        return s;
      case 2: {  // duplicated line
        const auto [b, e] = ls[pick(ls.size())];
        s.insert(e, s.substr(b, e - b));
        return s;
      }
      case 3: {  // deleted line
        const auto [b, e] = ls[pick(ls.size())];
        s.erase(b, e - b);
        return s;
      }
      case 4: {  // two lines swapped
        auto a = ls[pick(ls.size())], b = ls[pick(ls.size())];
        if (a.first > b.first) std::swap(a, b);
        if (a.second > b.first) return s;
        const std::string la = s.substr(a.first, a.second - a.first), lb = s.substr(b.first, b.second - b.first);
        s.replace(b.first, lb.size(), la);
        s.replace(a.first, la.size(), lb);
        return s;
      }
      case 5: case 6: case 7: case 10: case 14: {  // a number replaced
        const long i = token_index(t, true);
        if (i < 0) return s;
        const Token& k = t[static_cast<std::size_t>(i)];
        std::string r;
        const std::string old = s.substr(k.pos, k.len);
        if (op == 5) r = pick_of(huge);
        else if (op == 6) r = pick_of(nonfinite);
        else if (op == 7) r = pick(2) ? "-" + old : "-1";
        else if (op == 10) r = "0";
        else r = std::to_string(std::strtoll(old.c_str(), nullptr, 10) + (pick(2) ? 1 : -1));  // off by one
        s.replace(k.pos, k.len, r);
        return s;
      }
      case 8: {  // a token deleted
        const long i = token_index(t, false);
        if (i >= 0) s.erase(t[static_cast<std::size_t>(i)].pos, t[static_cast<std::size_t>(i)].len);
        return s;
      }
      case 9: {  // random bytes inserted
        static const char bytes[] = {'\0', '\xff', '\n', ' ', '"', '{', '[', '$', '#', '-', '\r', '\t', 'e', '.'};
        std::string ins;
        for (std::size_t n = 1 + pick(8); n > 0; --n) ins += bytes[pick(sizeof bytes)];
        s.insert(pick(s.size() + 1), ins);
        return s;
      }
      case 11: {  // a word replaced by another word of the file (keywords out of place)
        const long a = token_index(t, false), b = token_index(t, false);
        if (a < 0) return s;
        const Token& ka = t[static_cast<std::size_t>(a)];
        s.replace(ka.pos, ka.len, s.substr(t[static_cast<std::size_t>(b)].pos, t[static_cast<std::size_t>(b)].len));
        return s;
      }
      case 12: {  // a token replaced by a JSON-ish value of another type
        const long i = token_index(t, false);
        if (i < 0) return s;
        s.replace(t[static_cast<std::size_t>(i)].pos, t[static_cast<std::size_t>(i)].len, pick_of(odd));
        return s;
      }
      default: {  // a line repeated many times (counts no longer match the data)
        const auto [b, e] = ls[pick(ls.size())];
        const std::string line = s.substr(b, e - b);
        std::string rep;
        for (std::size_t n = 50 + pick(200); n > 0; --n) rep += line;
        s.insert(e, rep);
        return s;
      }
    }
  }

  std::mt19937_64 rng_;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void spit(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
  if (!out) throw std::runtime_error("cannot write " + p.string());
}

template <class T> void append_be(std::string& out, T v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::little) std::reverse(b, b + sizeof(T));
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

// Binary seeds are made here rather than stored: the tetrahedron surface of tetra_ascii.ply as
// write_ply's binary little-endian output, and by hand as big-endian float/uint.
void write_binary_seeds(const fs::path& out) {
  invfem::Points x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  invfem::Tris t(4, 3);
  t << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  invfem::write_ply((out / "tetra_le.ply").string(), x, t);
  std::string be =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar uint vertex_indices\nend_header\n";
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) append_be<float>(be, static_cast<float>(x(i, k)));
  for (int f = 0; f < 4; ++f) {
    be += static_cast<char>(3);
    for (int k = 0; k < 3; ++k) append_be<std::uint32_t>(be, static_cast<std::uint32_t>(t(f, k)));
  }
  spit(out / "tetra_be.ply", be);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path seeds, out;
  int per_seed = 500;
  std::uint64_t seed = 20040814;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "fuzz_generate: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--seeds") seeds = next();
    else if (a == "--out") out = next();
    else if (a == "--per-seed") per_seed = std::stoi(next());
    else if (a == "--seed") seed = std::stoull(next());
    else {
      std::cerr << "usage: fuzz_generate --seeds DIR --out DIR [--per-seed N] [--seed S]\n";
      return 2;
    }
  }
  if (seeds.empty() || out.empty() || per_seed < 0) {
    std::cerr << "usage: fuzz_generate --seeds DIR --out DIR [--per-seed N] [--seed S]\n";
    return 2;
  }
  try {
    fs::remove_all(out);
    fs::create_directories(out);
    for (const auto& e : fs::directory_iterator(seeds))
      if (e.is_regular_file()) fs::copy_file(e.path(), out / e.path().filename());
    write_binary_seeds(out);
    std::vector<fs::path> all;
    for (const auto& e : fs::directory_iterator(out)) all.push_back(e.path());
    std::sort(all.begin(), all.end());
    std::size_t written = 0;
    for (std::size_t s = 0; s < all.size(); ++s) {
      const std::string text = slurp(all[s]);
      // One stream per seed file (by name, not by directory order), so adding a seed leaves the
      // other seeds' mutants unchanged.
      std::uint64_t h = 1469598103934665603ull;  // FNV-1a: the same on every platform
      for (unsigned char c : all[s].filename().string()) h = (h ^ c) * 1099511628211ull;
      Mutator m(seed ^ (h * 0x9E3779B97F4A7C15ull));
      for (int k = 0; k < per_seed; ++k) {
        char tag[16];
        std::snprintf(tag, sizeof tag, ".m%05d", k);
        spit(out / (all[s].stem().string() + tag + all[s].extension().string()), m.mutate(text));
        ++written;
      }
    }
    std::cout << "fuzz_generate: " << all.size() << " seeds, " << written << " mutants in " << out << "\n";
  } catch (const std::exception& e) {
    std::cerr << "fuzz_generate: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
