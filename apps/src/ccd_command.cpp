#include "ccd_command.hpp"

#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli_args.hpp"
#include "invfem/core/io/text_file.hpp"
#include "invfem/collisions/self_collision/ccd/ccd.hpp"
#include "input_check.hpp"
#include "json_reader.hpp"

namespace invfem::app {

const char* const kCcdHelp =
    "usage: invfem ccd QUERIES.txt [--min-distance D]\n"
    "\n"
    "Continuous collision detection over linear trajectories on the normalized step [0, 1]\n"
    "(collisions/ccd: conservative inclusion search, never a false negative). One query per line:\n"
    "  vf  p a b c  p' a' b' c'       a vertex p and a triangle (a, b, c) at t = 0, then at t = 1\n"
    "  ee  a0 a1 b0 b1  a0' a1' b0' b1'  edge (a0, a1) and edge (b0, b1) at t = 0, then at t = 1\n"
    "each point as three numbers x y z (24 numbers after the tag, separated by blanks). Blank lines\n"
    "are skipped; # starts a comment (a line, or the rest of one). Prints one line per query on\n"
    "stdout: 1 when the pair may come within D (default 0) during the step, else 0; and a summary\n"
    "on stderr (queries, hits, seconds spent in CCD, queries per second). A malformed line is an\n"
    "error naming the file and line (exit 2).\n";

namespace {

struct Query {
  bool edge_edge = false;
  std::array<Vec3, 8> x;
};

// A token as shown in a message: bytes outside printable ASCII as \xHH (a NUL would cut the
// message short on a terminal), at most 40 of them.
std::string shown(const char* a, const char* b) {
  std::string out;
  for (const char* c = a; c < b && out.size() < 40; ++c) {
    const auto u = static_cast<unsigned char>(*c);
    if (u >= 0x20 && u < 0x7f) {
      out += *c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", u);
      out += hex;
    }
  }
  return b - a > 40 ? out + "..." : out;
}

// Splits text into lines and parses each query line; throws InputError naming file:line. A `#`
// starts a comment, at the start of a line or after the numbers; a number may have one leading
// sign, + or -.
std::vector<Query> parse_queries(const std::string& text, const std::string& file) {
  std::vector<Query> queries;
  std::size_t pos = 0;
  long line_number = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_number;
    const char* p = text.data() + pos;
    const char* const stop = text.data() + end;
    pos = end + 1;
    auto skip_blanks = [&] {
      while (p < stop && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
    };
    auto fail = [&](const std::string& what) {
      throw InputError(file + ":" + std::to_string(line_number) + ": " + what);
    };
    skip_blanks();
    if (p == stop || *p == '#') continue;
    const char* tag = p;
    while (p < stop && *p != ' ' && *p != '\t' && *p != '\r') ++p;
    const std::string kind(tag, p);
    if (kind != "vf" && kind != "ee") fail("expected a query tag vf or ee, found \"" + shown(tag, p) + "\"");
    Query q;
    q.edge_edge = kind == "ee";
    int count = 0;
    for (;;) {
      skip_blanks();
      if (p == stop || *p == '#') break;
      const char* token = p;
      while (p < stop && *p != ' ' && *p != '\t' && *p != '\r') ++p;
      if (count == 24) fail("more than 24 numbers after \"" + kind + "\" (8 points x y z)");
      double value = 0;
      const char* digits = token + (*token == '+' && p - token > 1 && token[1] != '-' && token[1] != '+');
      const auto [used, ec] = std::from_chars(digits, p, value);
      if (ec != std::errc() || used != p) fail("not a number: \"" + shown(token, p) + "\"");
      if (!std::isfinite(value)) fail("number " + std::to_string(count + 1) + " is not finite");
      q.x[count / 3][count % 3] = value;
      ++count;
    }
    if (count != 24)
      fail("expected 24 numbers after \"" + kind + "\" (8 points x y z), found " + std::to_string(count));
    queries.push_back(q);
  }
  return queries;
}

}  // namespace

int ccd_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "ccd", {"--min-distance"}, {"--help", "-h"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kCcdHelp;
    return 0;
  }
  if (args.positional.size() != 1) throw InputError("ccd: expected one query file (see invfem ccd --help)");
  collisions::CcdSettings settings;
  if (args.has("--min-distance")) {
    const std::string& text = args.value("--min-distance");
    double d = -1;
    const auto [used, ec] = std::from_chars(text.data(), text.data() + text.size(), d);
    if (ec != std::errc() || used != text.data() + text.size() || !std::isfinite(d) || d < 0)
      throw InputError("--min-distance: expected a distance >= 0, found \"" + text + "\"");
    settings.min_distance = d;
  }
  const std::string& file = args.positional[0];
  require_input_file(file, "query file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("cannot open the query file " + file);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  drop_byte_order_mark(text);
  const std::vector<Query> queries = parse_queries(text, file);

  std::string answers(2 * queries.size(), '\n');
  long hits = 0, edge_edge = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const auto& x = queries[i].x;
    double toi = 0;
    const bool hit = queries[i].edge_edge
                         ? collisions::edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, toi)
                         : collisions::vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, toi);
    answers[2 * i] = hit ? '1' : '0';
    hits += hit;
    edge_edge += queries[i].edge_edge;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::fwrite(answers.data(), 1, answers.size(), stdout);
  std::fflush(stdout);
  const long n = static_cast<long>(queries.size());
  std::fprintf(stderr, "ccd: %ld queries (%ld vf, %ld ee), %ld hits, min distance %g, %.3f s in CCD, %.3g queries/s\n",
               n, n - edge_edge, edge_edge, hits, settings.min_distance, seconds, seconds > 0 ? n / seconds : 0.0);
  return 0;
}

}  // namespace invfem::app
