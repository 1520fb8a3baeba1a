// obj_parser.h — the geometry statements of a Wavefront OBJ file, parsed in parallel.
//
// pmc reads OBJ geometry itself instead of through tinyobjloader: on the
// 2-core machines the single-threaded tinyobj parse was the longest serial
// step of loading Sponza (0.35 s of 26 MB). The text is cut at line ends into
// chunks that TBB parses side by side (core/parallel.h; the threads setting holds),
// numbers are read with std::from_chars, and the chunks are joined in order,
// so the result does not depend on the thread count.
//
// What is read, with tinyobjloader's rules where the OBJ format leaves a choice:
// - `v x y z` (extra components such as vertex colours ignored), `vn x y z`,
//   `vt u v`; a component that is not a number reads as 0. `nan`/`inf` and
//   overflowing values stay non-finite: the loader skips such triangles or
//   repairs such normals and uvs, and says so.
// - `f` corners `v`, `v/t`, `v//n`, `v/t/n`; indices start at 1, negative
//   ones count back from the last element written before the face. Quads
//   split along their shorter diagonal (a tie: corners 0-1-3, 1-2-3);
//   larger polygons are ear-clipped in the plane of their Newell normal (a
//   convex one, or one without a normal, becomes a fan around its first
//   corner; concave ones past 1024 corners or a work budget are counted in
//   approximate_polygons, and what is left of them becomes a fan).
// - `usemtl NAME` (its first word) applies to the faces after it; `o NAME`
//   (the rest of the line) and `g A B` (names joined by one space) name the
//   shape of the faces after them; `mtllib` lines keep their file names
//   (split at spaces, `\` escapes one) for the loader.
// - Lines end at \n, \r or \r\n; `#` starts a comment line; other statements
//   (`s`, `l`, `p`, `vp`, ...) are ignored.
// Errors throw pmc::Error naming the file and line: a face with fewer than
// 3 corners, an index of 0 or no number, an index outside the elements the
// file has.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pmc {

struct ObjTriangle {
  int32_t v[3], t[3], n[3];  // 0-based; t and n are -1 when the corner has none
  int32_t usemtl;            // index into ObjGeometry::usemtl_names; -1 before any usemtl
  int32_t shape;             // index into ObjGeometry::shape_names
};

struct ObjGeometry {
  std::vector<float> positions, normals, uvs;  // xyz, xyz, uv
  std::vector<ObjTriangle> triangles;          // in file order
  std::vector<std::string> usemtl_names;       // in order of first use
  // One name per run of faces between `o`/`g` lines ("" before the first);
  // runs without faces are left out.
  std::vector<std::string> shape_names;
  std::vector<std::vector<std::string>> mtllibs;  // the file names of each mtllib line
  // Concave polygons (over 1024 corners, or too irregular for ear clipping's
  // budget) whose triangles were made partly as a fan: they may cover more
  // or less than the polygon.
  size_t approximate_polygons = 0;
};

// Parses `text`, the contents of the OBJ file `path` (named in errors).
ObjGeometry parse_obj(const std::string& path, const std::string& text);

}  // namespace pmc
