// part_options.h — the text forms of a frame's part: "A:B" samples and "x0,y0,x1,y1" windows.
//
// `pmc render --samples A:B --crop x0,y0,x1,y1` parse their values here
// (into RenderConfig::samples / crop, which validate() checks against spp
// and the image size); errors name the option and the value.
#pragma once

#include <array>
#include <string>

namespace pmc {

// "A:B" -> {A, B} (whole numbers, A < B); pmc::Error naming `option` otherwise.
std::array<int, 2> parse_sample_range(const std::string& text, const std::string& option = "--samples");
// "x0,y0,x1,y1" -> the four numbers (x0 < x1, y0 < y1); pmc::Error naming `option` otherwise.
std::array<int, 4> parse_crop_window(const std::string& text, const std::string& option = "--crop");

}  // namespace pmc
