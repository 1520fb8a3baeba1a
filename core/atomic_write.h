// atomic_write.h — "no half-written output" for every file pmc writes.
//
// A file is written under a temporary name beside its target (same folder,
// so the rename cannot cross file systems; same extension, so OpenImageIO
// picks the format from it) and renamed into place only once complete: an
// interrupted or failed write never leaves a truncated image, JSON or CSV.
#pragma once

#include <functional>
#include <string>

namespace pmc {

// Calls write(temporary_path), then renames the temporary onto `path`. If
// write throws or the rename fails, the temporary is removed and pmc::Error
// names `path`.
void write_atomically(const std::string& path, const std::function<void(const std::string& tmp)>& write);
// A text file (JSON, CSV, Markdown, SVG), written atomically.
void write_text_file(const std::string& path, const std::string& text);

}  // namespace pmc
