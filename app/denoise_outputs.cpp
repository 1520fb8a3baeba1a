// denoise_outputs.cpp — paths of a denoise's outputs.
#include "app/denoise_outputs.h"

#include <filesystem>

#include "app/output_guard.h"

namespace pmc {

DenoisePaths denoise_paths(const std::string& exr) {
  auto with = [&](const char* ext) { return std::filesystem::path(exr).replace_extension(ext).string(); };
  return {exr, with(".png"), with(".noisy.exr"), with(".noisy.png")};
}

std::vector<std::pair<std::string, std::string>> check_noisy_outputs(const DenoisePaths& paths) {
  check_output_path("-o (its noisy EXR)", paths.noisy_exr, ".exr");
  check_output_path("-o (its noisy PNG)", paths.noisy_png);
  return {{"-o (its noisy EXR)", paths.noisy_exr}, {"-o (its noisy PNG)", paths.noisy_png}};
}

}  // namespace pmc
