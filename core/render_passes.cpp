// render_passes.cpp — pass lists, and pass images resolved from exact sums.
#include "core/render_passes.h"

#include <cmath>
#include <sstream>

#include "core/abi/pmc_types.h"
#include "core/error.h"

namespace pmc {
namespace {

Image blank(const FilmSums& film, int channels) {
  Image im;
  im.width = film.width;
  im.height = film.height;
  im.channels = channels;
  im.pixels.assign(film.pixels() * size_t(channels), 0.0f);
  return im;
}

}  // namespace

const std::vector<PassName>& pass_names() {
  static const std::vector<PassName> names = {
      {kPassAlbedo, "albedo", {"albedo.R", "albedo.G", "albedo.B"}},
      {kPassNormal, "normal", {"N.X", "N.Y", "N.Z"}},
      {kPassDepth, "depth", {"Z"}},
      {kPassPosition, "position", {"P.X", "P.Y", "P.Z"}},
      {kPassMaterial, "material", {"material.id"}},
      {kPassHits, "hits", {"cache_hits.V"}},
  };
  return names;
}

bool parse_pass_list(const std::string& list, uint32_t& bits, std::string& error) {
  bits = 0;
  std::stringstream in(list);
  std::string word;
  while (std::getline(in, word, ',')) {
    if (word.empty()) continue;
    if (word == "all") {
      bits |= kPassAll;
      continue;
    }
    bool found = false;
    for (const PassName& p : pass_names())
      if (word == p.word) {
        bits |= p.bit;
        found = true;
      }
    if (!found) {
      error = "unknown pass '" + word + "' (passes: " + pass_list_text(kPassAll) + ", or all)";
      return false;
    }
  }
  return true;
}

std::string pass_list_text(uint32_t bits) {
  std::string out;
  for (const PassName& p : pass_names())
    if (bits & p.bit) out += (out.empty() ? "" : ",") + std::string(p.word);
  return out;
}

PassImages film_passes(const FilmSums& film) {
  PMC_CHECK(film.has_passes(), "film without passes");
  PassImages out;
  out.albedo = blank(film, 3);
  out.normal = blank(film, 3);
  out.depth = blank(film, 1);
  out.position = blank(film, 3);
  out.material = blank(film, 1);
  out.hits = film_hitmap(film);
  for (size_t i = 0; i < film.pixels(); ++i) {
    const uint32_t samples = film.samples[i], hit = film.pass_hits[i];
    long double n[3], len2 = 0;
    for (int c = 0; c < 3; ++c) {
      if (samples > 0)
        out.albedo.pixels[3 * i + size_t(c)] =
            float(film_pass_sum(film, i, int(PMC_PASS_ALBEDO) + c) / (long double)samples);
      n[c] = film_pass_sum(film, i, int(PMC_PASS_NORMAL) + c);
      len2 += n[c] * n[c];
      if (hit > 0)
        out.position.pixels[3 * i + size_t(c)] =
            float(film_pass_sum(film, i, int(PMC_PASS_POSITION) + c) / (long double)hit);
    }
    if (len2 > 0)
      for (int c = 0; c < 3; ++c) out.normal.pixels[3 * i + size_t(c)] = float(n[c] / std::sqrt(len2));
    if (hit > 0) out.depth.pixels[i] = float(film_pass_sum(film, i, int(PMC_PASS_DEPTH)) / (long double)hit);
    const uint32_t inv = film.pass_material_inv[i];
    out.material.pixels[i] = inv == 0 ? -1.0f : float(~inv);
  }
  return out;
}

std::vector<ImageLayer> pass_layers(const PassImages& passes, uint32_t bits) {
  const Image* images[] = {&passes.albedo,   &passes.normal,   &passes.depth,
                           &passes.position, &passes.material, &passes.hits};
  std::vector<ImageLayer> layers;
  for (size_t k = 0; k < pass_names().size(); ++k)
    if (bits & pass_names()[k].bit) layers.push_back({pass_names()[k].channels, *images[k]});
  return layers;
}

}  // namespace pmc
