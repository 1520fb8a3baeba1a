// env_map.h — an environment map and the distribution that samples it.
//
// A lat-long map (the convention of core/device/pmc_lights.h: +Y up,
// u = 0.5 + atan2(x, -z)/2pi, v = acos(y)/pi, v = 0 the top row) is read
// through OpenImageIO (OpenEXR, Radiance HDR, anything OIIO reads), checked
// (finite texels; negative ones are clamped to 0 with a warning) and given a
// piecewise-constant sampling density proportional to luminance x
// sin(theta) per texel: the marginal CDF over rows and one conditional CDF
// over the columns of each row, built in double precision.
//
// The map is kept once, in the layout the kernel reads (`data`, pool
// memory): its texels unscaled, then the CDFs, the rows' sines and the
// guide tables. Every render's light table points at it, and CPU devices
// read it in place; the environment's scale is a number in the light
// header, not a scaled copy. A 4096x2048 map is 168 MB in this layout: held
// beside a decoded copy and a scaled one per render, it was three times that.
#pragma once

#include <string>
#include <vector>

#include "core/pool_memory.h"

namespace pmc {

struct EnvMap {
  std::string path;  // where it came from ("" for maps made in memory)
  int width = 0, height = 0;
  // Texels (width * height * 3, linear radiance, top row first), the
  // marginal CDF (height: running sum over rows, last 1), the conditional
  // CDFs (height * width: per row, running sum over columns, last 1), the
  // rows' sines, then each CDF's guide table (cdf_guide; marginal first,
  // then the rows'): the layout core/device/pmc_lights.h reads.
  PoolVector<float> data;
  double integral = 0.0;  // sum over texels of luminance x sin(theta of the row centre)
  size_t texel_count() const { return size_t(width) * size_t(height); }
  const float* rgb() const { return data.data(); }
  const float* marginal() const { return rgb() + 3 * texel_count(); }
  const float* conditional() const { return marginal() + size_t(height); }
  // Integral of the luminance over the sphere (W/(m^2 sr) x sr): the map's
  // share of light power is pi r^2 times this.
  double luminance_integral() const;
  // sin(theta) at the centre of row y: the rows' sampling weight.
  double row_sine(int y) const;
  // How many floats `data` holds for a width x height map.
  static size_t data_floats(int width, int height);
};

// The guide table of an inclusive CDF of n entries: n + 1 entries, entry k
// the first index whose value exceeds k / n (n - 1 if none), as floats
// (exact: indices stay below 2^24). pmc_cdf_search_guided starts there.
std::vector<float> cdf_guide(const float* cdf, int n);

// Reads and checks a map; errors (pmc::Error) name the file.
EnvMap load_env_map(const std::string& path);
// A map from linear rgb texels (top row first); builds the distribution.
EnvMap env_map_from_rgb(int width, int height, const std::vector<float>& rgb, const std::string& path = "");

}  // namespace pmc
