// part_options.cpp — parsing "A:B" and "x0,y0,x1,y1".
#include "app/part_options.h"

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <vector>

#include "core/error.h"

namespace pmc {
namespace {

bool whole_number(const std::string& s, int& out) {
  if (s.empty() || s.size() > 11) return false;
  for (size_t i = 0; i < s.size(); ++i)
    if (!(std::isdigit((unsigned char)s[i]) || (i == 0 && s[i] == '-'))) return false;
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (errno != 0 || *end != '\0' || v < INT_MIN || v > INT_MAX) return false;
  out = int(v);
  return true;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts(1);
  for (char c : s) {
    if (c == sep)
      parts.emplace_back();
    else
      parts.back() += c;
  }
  return parts;
}

}  // namespace

std::array<int, 2> parse_sample_range(const std::string& text, const std::string& option) {
  const std::vector<std::string> p = split(text, ':');
  std::array<int, 2> r{};
  if (p.size() != 2 || !whole_number(p[0], r[0]) || !whole_number(p[1], r[1]))
    fail(option, ": expected A:B, two whole numbers (sample indices [A, B)), got '", text, "'");
  if (r[0] < 0 || r[0] >= r[1]) fail(option, ": the range A:B must satisfy 0 <= A < B, got '", text, "'");
  return r;
}

std::array<int, 4> parse_crop_window(const std::string& text, const std::string& option) {
  const std::vector<std::string> p = split(text, ',');
  std::array<int, 4> w{};
  bool ok = p.size() == 4;
  for (size_t i = 0; ok && i < 4; ++i) ok = whole_number(p[i], w[i]);
  if (!ok)
    fail(option, ": expected x0,y0,x1,y1, four whole numbers (pixels [x0,x1) x [y0,y1)), got '", text, "'");
  if (w[0] < 0 || w[1] < 0 || w[0] >= w[2] || w[1] >= w[3])
    fail(option, ": the window x0,y0,x1,y1 must satisfy 0 <= x0 < x1 and 0 <= y0 < y1, got '", text, "'");
  return w;
}

}  // namespace pmc
