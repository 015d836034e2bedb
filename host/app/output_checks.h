#pragma once
// Output-file checks shared by subcommands that write files (docs/reference.md, as `render`):
// an output must have the right extension, must not be given twice and must not replace the scene
// or one of its inputs (the files it names, followed into luminaire manifests and glTF files).
#include <string>
#include <utility>
#include <vector>

namespace nf::app {

// Throws nf::Error "OPTION PATH: the file name must end in EXT" (case-insensitive).
void check_output_extension(const std::string& path, const std::string& ext, const std::string& option);
// `outputs`: (option, path) pairs. Throws nf::Error naming the option and the path.
void check_output_files(const std::string& scene_file, const std::vector<std::pair<std::string, std::string>>& outputs);

}  // namespace nf::app
