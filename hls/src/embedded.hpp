// The files compiled into parallax_hls as text (hls/CMakeLists.txt writes the tables).
#pragma once

#include <string>
#include <vector>

namespace parallax::hlsx::detail {

struct EmbeddedFile {
  const char* name;         // copied files: path in the project; templates: file name
  const char* const* text;  // the file's text
};

// Kernel headers and compat/ headers, copied unchanged into every project.
const std::vector<EmbeddedFile>& copied_files();
// Templates of the generated files, with @KEY@ placeholders.
const std::vector<EmbeddedFile>& templates();

}  // namespace parallax::hlsx::detail
