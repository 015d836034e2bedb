#pragma once
// Output-file checks shared by subcommands that write files (render, reference, luminaire gen,
// import and farfield; docs/robustness.md), run before any work: an output must have the right
// extension, must not be given twice, must not replace an input of the job (the input file and the
// files it names, followed into luminaire manifests and glTF files; by path, symlink or hard link),
// and must go into an existing, writable directory.
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace nf::app {

// (option, path) pairs: the command's output files.
using OutputFiles = std::vector<std::pair<std::string, std::string>>;

// Throws nf::Error "OPTION PATH: the file name must end in EXT" (case-insensitive).
void check_output_extension(const std::string& path, const std::string& ext, const std::string& option);
// The same for several accepted extensions: "OPTION PATH: the file name must end in .exr or .hdr".
void check_output_extensions(const std::string& path, const std::vector<std::string>& exts, const std::string& option);

// Throws nf::Error naming the option, the path and the problem when an output is given twice, is an
// input of `input_file` (`what` names it in the message; default "the scene INPUT_FILE"), is a
// directory, or lies in a directory that is missing, not a directory or not writable.
void check_output_files(const std::string& input_file, const OutputFiles& outputs, const std::string& what = "");

// An output directory (`luminaire gen|import -o DIR`, created when missing): DIR, or where it does not
// exist yet the nearest directory above it, must be a writable directory; each of `files` (names inside
// DIR) must not be a directory or an input of `input_file` (none when empty).
void check_output_directory(const std::string& option, const std::string& dir, const std::vector<std::string>& files,
                            const std::string& input_file = "", const std::string& what = "");

// Throws nf::Error "OPTION PATH: refusing to overwrite INPUT, an input of WHAT" when `path` is one of
// `inputs` (scene::referenced_files: canonical paths; by path, symlink or hard link).
void check_not_input(const std::string& option, const std::string& path, const std::set<std::filesystem::path>& inputs,
                     const std::string& what);

}  // namespace nf::app
