// obj_parser.cpp — chunked parse (pass 1), ordered join, triangulation (pass 2).
#include "core/obj_parser.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "core/error.h"
#include "core/parallel.h"

namespace pmc {
namespace {

constexpr int32_t kAbsent = std::numeric_limits<int32_t>::min();  // a corner without t or n
constexpr int32_t kBeforeAll = kAbsent + 1;  // a relative index too far back for any file
constexpr size_t kChunkBytes = size_t(1) << 20;
// Concave polygons are ear-clipped up to this many corners, within a budget
// of 4 n^2 point tests each (ear clipping's worst case is n^3, which a file
// of huge concave polygons could turn into a hang); past either, the rest
// becomes a fan, and the loader says how many polygons that happened to.
constexpr size_t kMaxEarClipCorners = 1024;

bool blank(char c) { return c == ' ' || c == '\t'; }

const char* skip_blanks(const char* p, const char* end) {
  while (p < end && blank(*p)) ++p;
  return p;
}

const char* word_end(const char* p, const char* end) {
  while (p < end && !blank(*p)) ++p;
  return p;
}

// One whitespace-delimited number (0 when it is none), as tinyobj reads
// components: a leading '+' is allowed, and a number followed by other
// characters keeps its numeric prefix. Overflow gives +-inf, not an error.
float parse_real(const char*& p, const char* end) {
  p = skip_blanks(p, end);
  const char* token_end = word_end(p, end);
  const char* q = p + (p < token_end && *p == '+' ? 1 : 0);
  p = token_end;
  float value = 0.0f;
  const std::from_chars_result r = std::from_chars(q, token_end, value);
  if (r.ec == std::errc::result_out_of_range)  // beyond float: strtod rounds to inf or 0
    return float(std::strtod(std::string(q, token_end).c_str(), nullptr));
  return r.ec == std::errc() ? value : 0.0f;
}

// atoi's reading of an index: optional sign, then digits; 0 when there are
// none. Huge values saturate (they are out of range anyway).
long long parse_index(const char* p, const char* end) {
  bool negative = false;
  if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
  long long v = 0;
  for (; p < end && *p >= '0' && *p <= '9'; ++p) v = std::min<long long>(v * 10 + (*p - '0'), 1ll << 40);
  return negative ? -v : v;
}

const char* corner_part_end(const char* p, const char* end) {
  while (p < end && *p != '/' && !blank(*p)) ++p;
  return p;
}

// The line number (from 1) of byte `offset`: \n, \r and \r\n end lines.
size_t line_number_at(const std::string& text, size_t offset) {
  size_t line = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i)
    if (text[i] == '\n' || (text[i] == '\r' && (i + 1 >= text.size() || text[i + 1] != '\n'))) ++line;
  return line;
}

struct Corner {
  int32_t v, t, n;
};

// What changes the state of the faces after it.
struct Event {
  size_t face;  // index of the first face (in its chunk) it applies to
  bool usemtl;  // else a shape name (o/g)
  std::string name;
};

struct ChunkError {
  size_t offset = 0;  // byte in the file
  std::string what;
};

// Pass 1's output for one chunk of lines.
struct Chunk {
  size_t begin = 0, end = 0;  // bytes of the file
  std::vector<float> positions, normals, uvs;
  std::vector<Corner> corners;
  std::vector<uint32_t> face_corners;  // corners per face
  std::vector<size_t> face_offsets;    // byte in the file where each face's line starts
  // (index into corners, component 0/1/2): relative indices, stored as
  // chunk-local element counts plus the index; pass 2 adds the chunk's base.
  std::vector<std::pair<size_t, int>> relative;
  std::vector<Event> events;
  std::vector<std::vector<std::string>> mtllibs;
  size_t triangles = 0;
  size_t approximate = 0;  // concave polygons split partly as fans (pass 2)
  bool has_error = false;
  ChunkError error;
  // Set between the passes.
  size_t base[3] = {0, 0, 0};  // positions, uvs, normals before this chunk
  size_t first_triangle = 0;
  int32_t start_usemtl = -1, start_shape = 0;
  int32_t first_run = 0;  // the shape run of this chunk's first o/g line
};

// tinyobj's SplitString(' ', '\\'): escaped characters are kept, empty
// words between spaces dropped, and the last word always kept.
std::vector<std::string> split_mtllib(const char* p, const char* end) {
  std::vector<std::string> words;
  std::string word;
  bool escaping = false;
  for (; p < end; ++p) {
    if (escaping) {
      escaping = false;
    } else if (*p == '\\') {
      escaping = true;
      continue;
    } else if (*p == ' ') {
      if (!word.empty()) words.push_back(word);
      word.clear();
      continue;
    }
    word += *p;
  }
  words.push_back(word);
  return words;
}

class ChunkParser {
 public:
  ChunkParser(const std::string& text, Chunk& chunk) : text_(text), c_(chunk) {}

  void run() {
    const char* data = text_.data();
    const char* p = data + c_.begin;
    const char* const stop = data + c_.end;
    const char* nl = nullptr;  // the next '\n' at or after p, or stop; kept across lines so
                               // a file of lone '\r' line ends is not rescanned per line
    while (p < stop) {
      if (!nl || nl < p) {
        nl = static_cast<const char*>(std::memchr(p, '\n', size_t(stop - p)));
        if (!nl) nl = stop;
      }
      const char* line_end = nl;
      const char* cr = static_cast<const char*>(std::memchr(p, '\r', size_t(nl - p)));
      const char* next = nl < stop ? nl + 1 : stop;
      if (cr) {
        line_end = cr;
        next = cr + 1 == nl ? (nl < stop ? nl + 1 : stop) : cr + 1;
      }
      if (!line(p, line_end)) return;
      p = next;
    }
  }

 private:
  bool line(const char* begin, const char* end) {
    const char* p = skip_blanks(begin, end);
    if (p == end || *p == '#') return true;
    const size_t rest = size_t(end - p);
    auto keyword = [&](const char* k, size_t n) {  // k followed by a blank
      return rest > n && std::memcmp(p, k, n) == 0 && blank(p[n]);
    };
    if (keyword("v", 1)) {
      p += 2;
      for (int k = 0; k < 3; ++k) c_.positions.push_back(parse_real(p, end));
    } else if (keyword("vn", 2)) {
      p += 3;
      for (int k = 0; k < 3; ++k) c_.normals.push_back(parse_real(p, end));
    } else if (keyword("vt", 2)) {
      p += 3;
      for (int k = 0; k < 2; ++k) c_.uvs.push_back(parse_real(p, end));
    } else if (keyword("f", 1)) {
      return face(begin, p + 2, end);
    } else if (rest >= 6 && std::memcmp(p, "usemtl", 6) == 0) {
      const char* w = skip_blanks(p + 6, end);  // tinyobj's parseString: the first word
      c_.events.push_back({c_.face_corners.size(), true, std::string(w, word_end(w, end))});
    } else if (keyword("mtllib", 6)) {
      c_.mtllibs.push_back(split_mtllib(p + 7, end));
    } else if (keyword("o", 1)) {
      c_.events.push_back({c_.face_corners.size(), false, std::string(p + 2, end)});
    } else if (keyword("g", 1)) {
      std::string name;
      for (const char* w = skip_blanks(p + 2, end); w < end; w = skip_blanks(w, end)) {
        const char* e = word_end(w, end);
        name += (name.empty() ? "" : " ") + std::string(w, e);
        w = e;
      }
      c_.events.push_back({c_.face_corners.size(), false, name});
    }
    return true;
  }

  // One index of a corner; false (and the chunk's error) for 0 or no number.
  bool index(const char* p, const char* end, size_t count, int component, int32_t& out, const char* line) {
    const long long raw = parse_index(p, end);
    if (raw == 0) {
      const char* w = corner_start_;
      return error(line, "a face corner '" + printable(std::string(w, word_end(w, end))) +
                             "' has an index of 0 or no number (OBJ indices start at 1)");
    }
    if (raw > 0) {
      out = int32_t(std::min<long long>(raw - 1, std::numeric_limits<int32_t>::max()));
    } else {
      const long long local = (long long)count + raw;  // the chunk's base is added in pass 2
      out = int32_t(std::max<long long>(local, kBeforeAll));
      c_.relative.emplace_back(c_.corners.size(), component);
    }
    return true;
  }

  bool face(const char* line, const char* p, const char* end) {
    const size_t first = c_.corners.size();
    const size_t nv = c_.positions.size() / 3, nt = c_.uvs.size() / 2, nn = c_.normals.size() / 3;
    for (p = skip_blanks(p, end); p < end; p = skip_blanks(p, end)) {
      corner_start_ = p;
      Corner k{0, kAbsent, kAbsent};
      if (!index(p, end, nv, 0, k.v, line)) return false;
      p = corner_part_end(p, end);
      if (p < end && *p == '/') {
        ++p;
        if (p < end && *p == '/') {  // v//n
          if (!index(++p, end, nn, 2, k.n, line)) return false;
          p = corner_part_end(p, end);
        } else {  // v/t or v/t/n
          if (!index(p, end, nt, 1, k.t, line)) return false;
          p = corner_part_end(p, end);
          if (p < end && *p == '/') {
            if (!index(++p, end, nn, 2, k.n, line)) return false;
            p = corner_part_end(p, end);
          }
        }
      }
      c_.corners.push_back(k);
    }
    const size_t n = c_.corners.size() - first;
    if (n < 3) return error(line, "a face has fewer than 3 corners (is the file truncated?)");
    c_.face_corners.push_back(uint32_t(n));
    c_.face_offsets.push_back(size_t(line - text_.data()));
    c_.triangles += n - 2;
    return true;
  }

  bool error(const char* line, std::string what) {
    c_.has_error = true;
    c_.error = {size_t(line - text_.data()), std::move(what)};
    return false;
  }

  const std::string& text_;
  Chunk& c_;
  const char* corner_start_ = nullptr;
};

// Splits `text` into chunks of about kChunkBytes that end after a '\n'.
std::vector<Chunk> make_chunks(const std::string& text) {
  std::vector<Chunk> chunks;
  size_t begin = 0;
  while (begin < text.size()) {
    size_t end = std::min(text.size(), begin + kChunkBytes);
    if (end < text.size()) {
      const void* nl = std::memchr(text.data() + end, '\n', text.size() - end);
      end = nl ? size_t(static_cast<const char*>(nl) - text.data()) + 1 : text.size();
    }
    Chunk c;
    c.begin = begin;
    c.end = end;
    chunks.push_back(std::move(c));
    begin = end;
  }
  return chunks;
}

struct Vec3 {
  double x, y, z;
};
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Triangles of one face of `n` corners, written to `out` (n - 2 of them).
class Triangulator {
 public:
  explicit Triangulator(const std::vector<float>& positions) : p_(positions) {}

  void face(const Corner* k, size_t n, int32_t usemtl, int32_t shape, ObjTriangle* out) {
    out_ = out;
    usemtl_ = usemtl;
    shape_ = shape;
    k_ = k;
    if (n == 3) {
      emit(0, 1, 2);
    } else if (n == 4) {
      quad();
    } else if (!ear_clip(n)) {
      for (size_t i = 1; i + 1 < n; ++i) emit(0, i, i + 1);
    }
  }
  size_t approximate() const { return approximate_; }

 private:
  const float* at(size_t corner) const { return &p_[3 * size_t(k_[corner].v)]; }
  Vec3 point(size_t corner) const {
    const float* q = at(corner);
    return {q[0], q[1], q[2]};
  }

  void emit(size_t a, size_t b, size_t c) {
    ObjTriangle& t = *out_++;
    const size_t idx[3] = {a, b, c};
    for (int j = 0; j < 3; ++j) {
      const Corner& k = k_[idx[j]];
      t.v[j] = k.v;
      t.t[j] = k.t == kAbsent ? -1 : k.t;
      t.n[j] = k.n == kAbsent ? -1 : k.n;
    }
    t.usemtl = usemtl_;
    t.shape = shape_;
  }

  // tinyobj's rule: split along the shorter diagonal, 1-3 on a tie. In
  // float, from the float positions: on Sponza, the Cornell box, the spider
  // and the default room this reproduces every split of Debian's tinyobj
  // (which compares unrounded doubles), where double arithmetic here did not
  // (squares whose diagonals tie only up to rounding).
  void quad() {
    float d02 = 0.0f, d13 = 0.0f;
    for (int c = 0; c < 3; ++c) {
      const float e02 = at(2)[c] - at(0)[c], e13 = at(3)[c] - at(1)[c];
      d02 += e02 * e02;
      d13 += e13 * e13;
    }
    if (d02 < d13) {
      emit(0, 1, 2);
      emit(0, 2, 3);
    } else {
      emit(0, 1, 3);
      emit(1, 2, 3);
    }
  }

  // Ear clipping in the plane of the Newell normal, trying corner 1 first,
  // so a convex polygon becomes a fan around corner 0. False (nothing
  // emitted) for a polygon without a normal; a polygon that runs out of ears
  // (self-intersecting) gets a fan of what is left.
  bool ear_clip(size_t n) {
    Vec3 normal{0, 0, 0};
    for (size_t i = 0; i < n; ++i) {
      const Vec3 a = point(i), b = point((i + 1) % n);
      normal.x += (a.y - b.y) * (a.z + b.z);
      normal.y += (a.z - b.z) * (a.x + b.x);
      normal.z += (a.x - b.x) * (a.y + b.y);
    }
    const double length = std::sqrt(dot(normal, normal));
    if (!(length > 0.0) || !std::isfinite(length)) return false;
    const Vec3 w{normal.x / length, normal.y / length, normal.z / length};
    const Vec3 a = std::fabs(w.x) > 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    Vec3 u = cross(a, w);
    const double ul = std::sqrt(dot(u, u));
    u = {u.x / ul, u.y / ul, u.z / ul};
    const Vec3 v = cross(w, u);  // (u, v, w) right-handed: the polygon runs counter-clockwise in (u, v)
    xy_.resize(n);
    for (size_t i = 0; i < n; ++i) xy_[i] = {dot(point(i), u), dot(point(i), v)};
    bool convex = true;  // a fan is then the ear clipping's own result, found in O(n)
    for (size_t i = 0; i < n && convex; ++i) convex = area2((i + n - 1) % n, i, (i + 1) % n) >= 0.0;
    if (convex) return false;
    if (n > kMaxEarClipCorners) {
      ++approximate_;
      return false;
    }
    left_.resize(n);
    for (size_t i = 0; i < n; ++i) left_[i] = i;
    tests_ = 4 * n * n;
    size_t i = 1, misses = 0;
    while (left_.size() > 3) {
      if (tests_ == 0) {
        ++approximate_;
        break;
      }
      const size_t m = left_.size();
      const size_t prev = left_[(i + m - 1) % m], cur = left_[i % m], next = left_[(i + 1) % m];
      if (is_ear(prev, cur, next)) {
        emit(prev, cur, next);
        left_.erase(left_.begin() + std::ptrdiff_t(i % m));
        i = std::max<size_t>(1, i % m) % left_.size();
        misses = 0;
      } else if (++misses > m) {
        break;  // no ear left
      } else {
        i = (i + 1) % m;
      }
    }
    for (size_t j = 1; j + 1 < left_.size(); ++j) emit(left_[0], left_[j], left_[j + 1]);
    return true;
  }

  double area2(size_t a, size_t b, size_t c) const {
    return (xy_[b].x - xy_[a].x) * (xy_[c].y - xy_[a].y) - (xy_[b].y - xy_[a].y) * (xy_[c].x - xy_[a].x);
  }

  bool is_ear(size_t prev, size_t cur, size_t next) {
    if (!(area2(prev, cur, next) > 0.0)) return false;  // reflex or degenerate
    tests_ -= std::min(tests_, left_.size());
    for (size_t j : left_) {
      if (j == prev || j == cur || j == next) continue;
      if (area2(prev, cur, j) > 0.0 && area2(cur, next, j) > 0.0 && area2(next, prev, j) > 0.0) return false;
    }
    return true;
  }

  struct XY {
    double x, y;
  };
  const std::vector<float>& p_;
  const Corner* k_ = nullptr;
  ObjTriangle* out_ = nullptr;
  int32_t usemtl_ = -1, shape_ = 0;
  std::vector<XY> xy_;
  std::vector<size_t> left_;
  size_t tests_ = 0, approximate_ = 0;
};

template <typename T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

}  // namespace

ObjGeometry parse_obj(const std::string& path, const std::string& text) {
  std::vector<Chunk> chunks = make_chunks(text);
  parallel_for_each_index(chunks.size(), [&](size_t i) { ChunkParser(text, chunks[i]).run(); });
  for (const Chunk& c : chunks)  // the first malformed line (index ranges are checked in pass 2)
    if (c.has_error) fail(path, ": line ", line_number_at(text, c.error.offset), ": ", c.error.what);

  // The join: bases, names and the state each chunk starts in.
  ObjGeometry g;
  size_t positions = 0, normals = 0, uvs = 0, triangles = 0;
  std::unordered_map<std::string, int32_t> usemtl_ids;
  std::vector<std::string> run_names{""};  // shape runs; run 0 before any o/g
  int32_t usemtl = -1, shape = 0;
  for (Chunk& c : chunks) {
    c.base[0] = positions / 3;
    c.base[1] = uvs / 2;
    c.base[2] = normals / 3;
    c.first_triangle = triangles;
    c.start_usemtl = usemtl;
    c.start_shape = shape;
    c.first_run = int32_t(run_names.size());
    positions += c.positions.size();
    normals += c.normals.size();
    uvs += c.uvs.size();
    triangles += c.triangles;
    for (Event& e : c.events) {
      if (e.usemtl) {
        if (e.name.empty()) {
          usemtl = -1;  // no name: the default material
        } else {
          auto [it, added] = usemtl_ids.emplace(e.name, int32_t(g.usemtl_names.size()));
          if (added) g.usemtl_names.push_back(e.name);
          usemtl = it->second;
        }
      } else {
        shape = int32_t(run_names.size());
        run_names.push_back(e.name);
      }
    }
    for (auto& m : c.mtllibs) g.mtllibs.push_back(std::move(m));
  }
  const size_t most = size_t(std::numeric_limits<int32_t>::max()) - 1;
  if (positions / 3 > most || normals / 3 > most || uvs / 2 > most || triangles > most)
    fail(path, ": more than 2^31 - 2 vertices, normals, texture coordinates or triangles");
  g.positions.reserve(positions);
  g.normals.reserve(normals);
  g.uvs.reserve(uvs);
  for (const Chunk& c : chunks) {
    append(g.positions, c.positions);
    append(g.normals, c.normals);
    append(g.uvs, c.uvs);
  }
  g.triangles.resize(triangles);

  // Pass 2: resolve and check indices, triangulate, in place per chunk.
  const int64_t counts[3] = {int64_t(positions / 3), int64_t(uvs / 2), int64_t(normals / 3)};
  parallel_for_each_index(chunks.size(), [&](size_t i) {
    Chunk& c = chunks[i];
    for (const auto& [corner, component] : c.relative) {
      int32_t& x = component == 0   ? c.corners[corner].v
                   : component == 1 ? c.corners[corner].t
                                    : c.corners[corner].n;
      x = x == kBeforeAll ? -1 : int32_t(std::max<int64_t>(int64_t(x) + int64_t(c.base[component]), -1));
    }
    Triangulator tri(g.positions);
    ObjTriangle* out = g.triangles.data() + c.first_triangle;
    int32_t usemtl_now = c.start_usemtl, shape_now = c.start_shape, next_run = c.first_run;
    size_t event = 0, corner = 0;
    for (size_t f = 0; f < c.face_corners.size(); ++f) {
      for (; event < c.events.size() && c.events[event].face <= f; ++event) {
        const Event& e = c.events[event];
        if (e.usemtl)
          usemtl_now = e.name.empty() ? -1 : usemtl_ids.at(e.name);
        else
          shape_now = next_run++;
      }
      const size_t n = c.face_corners[f];
      const Corner* k = &c.corners[corner];
      for (size_t j = 0; j < n && !c.has_error; ++j) {
        const int64_t idx[3] = {k[j].v, k[j].t, k[j].n};
        static const char* const kWhat[3] = {"vertex", "texture-coordinate", "normal"};
        static const char* const kPlural[3] = {"vertices", "texture coordinates", "normals"};
        for (int a = 0; a < 3; ++a) {
          if (a > 0 && idx[a] == kAbsent) continue;
          if (idx[a] < 0 || idx[a] >= counts[a]) {
            c.has_error = true;
            const std::string what = kWhat[a];
            c.error = {
                c.face_offsets[f],
                what + " index out of range: " +
                    (idx[a] < 0 ? "a face's relative index points before the first " + what
                                : "a face uses " + what + " index " + std::to_string(idx[a] + 1) +
                                      " but the file has " + std::to_string(counts[a]) + " " + kPlural[a])};
            break;
          }
        }
      }
      if (c.has_error) return;
      tri.face(k, n, usemtl_now, shape_now, out);
      out += n - 2;
      corner += n;
    }
    c.approximate = tri.approximate();
  });
  for (const Chunk& c : chunks) {
    if (c.has_error) fail(path, ": line ", line_number_at(text, c.error.offset), ": ", c.error.what);
    g.approximate_polygons += c.approximate;
  }

  // Shape runs without faces are dropped.
  std::vector<int32_t> run_index(run_names.size(), -1);
  for (ObjTriangle& t : g.triangles) {
    int32_t& r = run_index[size_t(t.shape)];
    if (r < 0) {
      r = int32_t(g.shape_names.size());
      g.shape_names.push_back(run_names[size_t(t.shape)]);
    }
    t.shape = r;
  }
  return g;
}

}  // namespace pmc
