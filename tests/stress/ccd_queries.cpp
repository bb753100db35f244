// CCD queries with known answers (tests/unit/ccd_queries.hpp): writes a query file for
// `invfem ccd` and its answers, and checks the library's answers in process.
//
//   ccd_queries [--count N] [--seed S] [--out DIR]
//
// N queries (default 1,000,000): vf and ee alternate, half of each are hits (contact by
// construction), half misses (separated by a plane by 1e-4 to 0.1). With --out, writes
// DIR/queries.txt (the `invfem ccd` format) and DIR/answers.txt (one line per query: 1 or 0, the
// variant, and for misses the separation). Then runs every query through vertex_face_ccd /
// edge_edge_ccd and prints false negatives (must be 0), false positives, the queries per second
// and the costliest variants; exits 1 on a false negative, 2 on bad arguments.
//
// Compare `invfem ccd` with the answers:
//   build/apps/invfem ccd DIR/queries.txt > got.txt
//   paste -d' ' got.txt DIR/answers.txt | awk '$1==0&&$2==1{fn++} $1==1&&$2==0{fp++} END{print fn+0, fp+0}'
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "ccd_queries.hpp"
#include "invfem/collisions/self_collision/ccd/ccd.hpp"

using namespace invfem;

int main(int argc, char** argv) {
  long count = 1'000'000;
  unsigned long long seed = 1;
  std::string out;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 < argc && a == "--count") count = std::atol(argv[++i]);
    else if (i + 1 < argc && a == "--seed") seed = std::strtoull(argv[++i], nullptr, 10);
    else if (i + 1 < argc && a == "--out") out = argv[++i];
    else {
      std::fprintf(stderr, "usage: ccd_queries [--count N] [--seed S] [--out DIR]\n");
      return 2;
    }
  }
  if (count < 1) {
    std::fprintf(stderr, "ccd_queries: --count must be >= 1\n");
    return 2;
  }
  test::KnownCcdQueries gen(seed);
  std::vector<test::KnownCcdQuery> queries;
  queries.reserve(count);
  for (long k = 0; k < count; ++k) queries.push_back(gen.next(k % 2 == 1, (k / 2) % 2 == 0, 5e-5));

  if (!out.empty()) {
    std::filesystem::create_directories(out);
    FILE* q = std::fopen((out + "/queries.txt").c_str(), "w");
    FILE* a = std::fopen((out + "/answers.txt").c_str(), "w");
    if (!q || !a) {
      std::fprintf(stderr, "ccd_queries: cannot write in %s\n", out.c_str());
      return 2;
    }
    std::fprintf(q, "# %ld CCD queries with known answers (tests/stress/ccd_queries.cpp, seed %llu)\n", count, seed);
    for (const auto& x : queries) {
      std::fputs(x.edge_edge ? "ee" : "vf", q);
      for (const Vec3& p : x.x) std::fprintf(q, " %.17g %.17g %.17g", p[0], p[1], p[2]);
      std::fputc('\n', q);
      if (x.hit) std::fprintf(a, "1 %s\n", x.variant.c_str());
      else std::fprintf(a, "0 %s, separation %.3g\n", x.variant.c_str(), x.separation);
    }
    std::fclose(q);
    std::fclose(a);
  }

  collisions::CcdSettings settings;
  long false_negatives = 0, false_positives = 0, exhausted = 0;
  std::map<std::string, std::pair<long, long>> boxes;  // variant -> (queries, boxes)
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& q : queries) {
    const auto& x = q.x;
    double toi = 0;
    collisions::CcdStats stats;
    const bool hit = q.edge_edge
                         ? collisions::edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, toi, stats)
                         : collisions::vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, toi, stats);
    false_negatives += q.hit && !hit;
    false_positives += !q.hit && hit;
    exhausted += stats.exhausted;
    auto& b = boxes[q.variant];
    ++b.first;
    b.second += stats.boxes;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%ld queries: %ld false negatives, %ld false positives, %ld out of iterations; %.3f s (%.3g queries/s)\n",
              count, false_negatives, false_positives, exhausted, seconds, count / seconds);
  std::printf("mean boxes examined per query, by variant:\n");
  for (const auto& [variant, b] : boxes)
    std::printf("  %8.1f  %s (%ld)\n", double(b.second) / b.first, variant.c_str(), b.first);
  return false_negatives == 0 ? 0 : 1;
}
