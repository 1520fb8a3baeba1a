// content_hash_test.cpp — the identity hash of render parts (core/content_hash.h).
//
// Empty inputs: an empty vector's data() may be null, and copying zero bytes
// from null is undefined behaviour (UBSan flagged it in scene_hash for a
// scene with an empty array); empty inputs must hash like zero bytes from
// anywhere. Tails: inputs that differ only in their last, partial word, or
// only in length, hash apart.
#include "core/content_hash.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace pmc {
namespace {

TEST(ContentHash, EmptyInputsHashLikeZeroBytes) {
  ContentHash from_null, from_buffer;
  from_null.vec(std::vector<float>{});
  const float x = 1.0f;
  from_buffer.word(0);
  from_buffer.bytes(&x, 0);
  EXPECT_EQ(from_null.hex(), from_buffer.hex());
  ContentHash empty_string;
  empty_string.str(std::string());
  ContentHash nothing;
  EXPECT_NE(empty_string.hex(), nothing.hex()) << "an empty input is still an input";
}

TEST(ContentHash, TailsAndLengthsHashApart) {
  auto hash = [](const std::string& s) {
    ContentHash h;
    h.str(s);
    return h.hex();
  };
  EXPECT_NE(hash("abcdefghij"), hash("abcdefghik")) << "last byte of a partial word";
  EXPECT_NE(hash("abcdefgh"), hash(std::string("abcdefgh\0", 9))) << "a trailing zero byte";
  EXPECT_EQ(hash("abcdefghij"), hash("abcdefghij"));
}

}  // namespace
}  // namespace pmc
